/* An I2C master written from the ATmega328P datasheet (section 22.7 "Using
 * the TWI", Table 22-3 master transmitter and 22-4 master receiver status
 * codes), as the Wire library does it (twi_master.h): 100 kHz (TWBR = 72,
 * prescaler 1: SCL = F_CPU / (16 + 2 * 72) = 100 kHz, section 22.5.2),
 * busy-waiting on TWINT. For the TwiSlave tests, against a device at 0x68:
 *   1. write register 0x10 = 0xA5, then 0x11 = 0x5A (pointer auto-increment);
 *   2. read 6 bytes from register 0x3B (write the pointer, repeated START,
 *      SLA+R, 5 bytes with ACK, the last with NACK, STOP) into block[];
 *   3. read 2 bytes back from 0x10 after a STOP (the pointer survives it);
 *   4. address 0x42 (nobody there): TWSR after SLA+W into nack_w, after
 *      SLA+R into nack_r.
 * The status after each step is kept in status[]; done = 1 at the end. */
#include "twi_master.h"

#define DEVICE 0x68
#define NOBODY 0x42

volatile uint8_t block[6];
volatile uint8_t readback[2];
volatile uint8_t nack_w;
volatile uint8_t nack_r;
volatile uint8_t done;

int main(void) {
    TWSR = 0;
    TWBR = 72;
    start();
    send(DEVICE << 1);
    send(0x10);
    send(0xA5);
    send(0x5A);
    stop();

    start();
    send(DEVICE << 1);
    send(0x3B);
    start(); /* repeated START */
    send(DEVICE << 1 | 1);
    for (uint8_t i = 0; i < 6; ++i) block[i] = receive(i < 5);
    stop();

    start();
    send(DEVICE << 1);
    send(0x10);
    stop();
    start();
    send(DEVICE << 1 | 1);
    readback[0] = receive(1);
    readback[1] = receive(0);
    stop();

    start();
    nack_w = send(NOBODY << 1);
    stop();
    start();
    nack_r = send(NOBODY << 1 | 1);
    stop();
    done = 1;
    for (;;) {
    }
}
