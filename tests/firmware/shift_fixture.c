/* A 74HC595 driven as the Adafruit Motor Shield v1's library does
 * (DRIVERS.md section 4): DS = D8 (PB0), SHCP = D4 (PD4), STCP = D12 (PB4),
 * OE = D7 (PD7). For the 74HC595 part's tests and the parts wired in a board
 * file. The test writes `data` and `oe`, then `request`; the firmware sets
 * OE to `oe`, shifts `data` bit 7 first (data with the clock low, then the
 * clock raised), raises the latch, and sets `done` to the request. */
#include <avr/io.h>
#include <stdint.h>

volatile uint8_t request;
volatile uint8_t done;
volatile uint8_t data;
volatile uint8_t oe;

static void send(uint8_t byte) {
    PORTB &= (uint8_t)~_BV(PB4); /* latch low */
    for (int8_t bit = 7; bit >= 0; --bit) {
        PORTD &= (uint8_t)~_BV(PD4); /* clock low */
        if (byte & (1U << bit)) {
            PORTB |= _BV(PB0);
        } else {
            PORTB &= (uint8_t)~_BV(PB0);
        }
        PORTD |= _BV(PD4); /* clock high: DS enters stage 0 */
    }
    PORTB |= _BV(PB4); /* latch high: the stages go to Q0..Q7 */
}

int main(void) {
    DDRB |= _BV(PB0) | _BV(PB4);
    DDRD |= _BV(PD4) | _BV(PD7);
    for (;;) {
        const uint8_t r = request;
        if (r == done) continue;
        if (oe) {
            PORTD |= _BV(PD7);
        } else {
            PORTD &= (uint8_t)~_BV(PD7);
        }
        send(data);
        done = r;
    }
}
