/* Servo pulses on D9 (PB1) the way the Arduino Servo library makes them
 * (Servo.cpp: Timer1 in normal mode at /8, 0.5 us a tick, the COMPA
 * interrupt raising the pin and scheduling its fall): a HIGH pulse of
 * pulse_ticks / 2 microseconds every 20 ms; pulse_ticks = 0: no pulses
 * (set by the test). pulses counts them. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

volatile uint16_t pulse_ticks = 0;
volatile uint16_t pulses = 0;

ISR(TIMER1_COMPA_vect) {
    if (PORTB & _BV(PB1)) {
        PORTB &= (uint8_t)~_BV(PB1); /* the pulse ends */
        ++pulses;
        OCR1A = 40000;               /* the 20 ms frame's end */
    } else if (pulse_ticks != 0) {
        TCNT1 = 0;
        PORTB |= _BV(PB1);           /* a pulse starts */
        OCR1A = pulse_ticks;
    } else {
        TCNT1 = 0;
        OCR1A = 40000;
    }
}

int main(void) {
    DDRB = _BV(PB1);
    TCCR1A = 0;
    TCCR1B = _BV(CS11); /* /8 */
    OCR1A = 40000;
    TIMSK1 = _BV(OCIE1A);
    sei();
    for (;;) {
    }
}
