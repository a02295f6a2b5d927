/* An MPU-6050 read register by register as common sketches do (i2cdevlib:
 * write the register pointer, STOP, then read), over the master of
 * twi_master.h at 100 kHz (TWBR = 72: SCL = 16 MHz / (16 + 2 x 72), section
 * 22.5.2). It reads WHO_AM_I into who, wakes the chip (PWR_MGMT_1 = 0), sets
 * DLPF_CFG 0; then for ever: GYRO_CONFIG = fs_sel << 3, the six GYRO_*OUT
 * bytes into gyro[] (reads counts them), and, once touch_fifo is set by the
 * test, USER_CTRL = FIFO_EN. */
#include "twi_master.h"

#define DEVICE 0x68

volatile uint8_t who;
volatile uint8_t gyro[6];
volatile uint8_t fs_sel;
volatile uint8_t touch_fifo;
volatile uint16_t reads;

static void write_reg(uint8_t reg, uint8_t value) {
    start();
    send(DEVICE << 1);
    send(reg);
    send(value);
    stop();
}

static void read_regs(uint8_t reg, volatile uint8_t* out, uint8_t n) {
    start();
    send(DEVICE << 1);
    send(reg);
    stop(); /* the pointer survives the STOP */
    start();
    send(DEVICE << 1 | 1);
    for (uint8_t i = 0; i < n; ++i) out[i] = receive(i + 1 < n);
    stop();
}

int main(void) {
    TWSR = 0;
    TWBR = 72;
    read_regs(0x75, &who, 1);
    write_reg(0x6B, 0x00);
    write_reg(0x1A, 0x00);
    for (;;) {
        write_reg(0x1B, (uint8_t)(fs_sel << 3));
        read_regs(0x43, gyro, 6);
        ++reads;
        if (touch_fifo) write_reg(0x6A, 0x40);
    }
}
