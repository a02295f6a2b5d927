/* A QTR-RC read as Pololu's QTRSensors::read() does it ([QTRAN] section 2),
 * written from the ATmega328P datasheet for the reflectance part's tests:
 * on each request (++request), D7 (PD7) is driven high for 20 us, made an
 * input with the pull-up off (DDR cleared before PORT, as pinMode(INPUT)
 * does), and Timer1 at /8 (0.5 us a tick) times it until it reads low:
 * decay_ticks, then done = request. */
#define F_CPU 16000000UL /* the Uno's crystal, for _delay_us */
#include <avr/io.h>
#include <stdint.h>
#include <util/delay.h>

volatile uint8_t request;
volatile uint8_t done;
volatile uint16_t decay_ticks;

static uint16_t read_line(void) {
    DDRD |= _BV(PD7);
    PORTD |= _BV(PD7);
    _delay_us(20);
    TCNT1 = 0;
    DDRD &= (uint8_t)~_BV(PD7);
    PORTD &= (uint8_t)~_BV(PD7);
    while ((PIND & _BV(PD7)) && TCNT1 < 60000) {
    }
    return TCNT1;
}

int main(void) {
    TCCR1A = 0;
    TCCR1B = _BV(CS11); /* /8: 2 MHz */
    for (;;) {
        const uint8_t r = request;
        if (r != done) {
            decay_ticks = read_line();
            done = r;
        }
    }
}
