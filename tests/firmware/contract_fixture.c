/* A firmware that is not the reference sketch, driven through its sketch
 * contract (tests/firmware/contract_fixture.yaml, docs/contracts.md):
 *   - sends "ready\r\n" at boot, then waits for one byte: the case digit;
 *   - runs 50 loop iterations (~1 ms each: TIMER0 overflows), each calling
 *     step() (the contract's loop.function), which adds
 *     0.01 to `t` and case * 0.002 m to `px`, 0.001 m to `py`, 0.01 rad to `th`;
 *   - every 10th iteration logs int(px * 100) at EEPROM 100 + k and
 *     int(py * 100) at 300 + k (one byte each, stride 1);
 *   - then prints "DONE\r\n", "<px in mm>,<py in mm>\r\n", "bye\r\n" and
 *     spins; afterwards it zeroes px (so the pose is only right when read
 *     at "DONE").
 */
#include <avr/eeprom.h>
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

volatile float t, px, py, th;
static volatile uint8_t overflows;

ISR(TIMER0_OVF_vect) { overflows++; }

static void put(char c) {
    while (!(UCSR0A & _BV(UDRE0))) {
    }
    UDR0 = (uint8_t)c;
}
static void puts_(const char* s) {
    while (*s) put(*s++);
}
static void put_int(int v) {
    char buf[8];
    uint8_t n = 0;
    if (v < 0) {
        put('-');
        v = -v;
    }
    do {
        buf[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v != 0);
    while (n != 0) put(buf[--n]);
}

/* One control-loop iteration: the contract's loop.function (the profile's loop mark). */
__attribute__((noinline)) static void step(uint8_t mode) {
    t += 0.01f;
    px += 0.002f * mode;
    py += 0.001f;
    th += 0.01f;
}

int main(void) {
    UBRR0H = 0;
    UBRR0L = 207; /* 9600 baud with U2X0 at 16 MHz */
    UCSR0A = _BV(U2X0);
    UCSR0B = _BV(TXEN0) | _BV(RXEN0);
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
    TCCR0B = _BV(CS01); /* clk/8: an overflow every 128 us */
    TIMSK0 = _BV(TOIE0);
    sei();
    puts_("ready\r\n");
    while (!(UCSR0A & _BV(RXC0))) {
    }
    const uint8_t mode = (uint8_t)(UDR0 - '0');
    for (uint8_t i = 0; i < 50; ++i) {
        const uint8_t start = overflows;
        while ((uint8_t)(overflows - start) < 8) {
        }
        step(mode);
        if (i % 10 == 9) {
            const uint8_t k = i / 10;
            eeprom_write_byte((uint8_t*)(100 + k), (uint8_t)(int)(px * 100.0f));
            eeprom_write_byte((uint8_t*)(300 + k), (uint8_t)(int)(py * 100.0f));
        }
    }
    puts_("DONE\r\n");
    put_int((int)(px * 1000.0f + 0.5f));
    put(',');
    put_int((int)(py * 1000.0f + 0.5f));
    puts_("\r\nbye\r\n");
    px = 0.0f;
    for (;;) {
    }
}
