/* An I2C master written from the ATmega328P datasheet (section 22.7 "Using
 * the TWI", Table 22-3 master transmitter and 22-4 master receiver status
 * codes), as the Wire library does it, busy-waiting on TWINT. Shared by the
 * TWI fixtures. The status after each wait is kept in status[]. */
#ifndef DDMR_TWI_MASTER_H
#define DDMR_TWI_MASTER_H
#include <avr/io.h>
#include <stdint.h>

volatile uint8_t status[16];
volatile uint8_t status_count;

static uint8_t wait(void) {
    while (!(TWCR & _BV(TWINT))) {
    }
    const uint8_t s = TWSR & 0xF8;
    if (status_count < sizeof status) status[status_count++] = s;
    return s;
}

static uint8_t start(void) {
    TWCR = _BV(TWINT) | _BV(TWSTA) | _BV(TWEN);
    return wait();
}

static uint8_t send(uint8_t byte) {
    TWDR = byte;
    TWCR = _BV(TWINT) | _BV(TWEN);
    return wait();
}

static uint8_t receive(uint8_t ack) {
    TWCR = _BV(TWINT) | _BV(TWEN) | (ack ? _BV(TWEA) : 0);
    wait();
    return TWDR;
}

static void stop(void) {
    TWCR = _BV(TWINT) | _BV(TWEN) | _BV(TWSTO);
    while (TWCR & _BV(TWSTO)) {
    }
}
#endif
