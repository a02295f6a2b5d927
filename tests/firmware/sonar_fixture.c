/* Pings an HC-SR04 with TRIG on D7 (PD7): on each request (++request), a
 * 12 us HIGH on TRIG, then done = request; the rest of the time a sled of
 * 1-cycle NOPs, so ECHO's edges (D8, PB0) land on instruction boundaries
 * and the test can see them at their exact cycles. */
#define F_CPU 16000000UL /* the Uno's crystal, for _delay_us */
#include <avr/io.h>
#include <stdint.h>
#include <util/delay.h>

volatile uint8_t request;
volatile uint8_t done;

int main(void) {
    DDRD |= _BV(PD7);
    for (;;) {
        const uint8_t r = request;
        if (r != done) {
            PORTD |= _BV(PD7);
            _delay_us(12);
            PORTD &= (uint8_t)~_BV(PD7);
            done = r;
        }
        __asm__ volatile(".rept 100\n\tnop\n\t.endr");
    }
}
