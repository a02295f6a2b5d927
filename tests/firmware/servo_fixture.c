/* Servo pulses on D9 (PB1) the way the Arduino Servo library makes them
 * (Servo.cpp: Timer1 in normal mode at /8, 0.5 us a tick, the COMPA
 * interrupt raising the pin and scheduling its fall): a HIGH pulse of
 * pulse_ticks / 2 microseconds every 20 ms; pulse_ticks = 0: no pulses
 * (set by the test). pulses counts them.
 * Built with -DHARDWARE_PWM, the pulses come from OC1A instead (datasheet
 * 7810D section 16.9.3, Table 16-4 mode 14: fast PWM, TOP = ICR1 = 39999,
 * 20 ms at /8; COM1A1: high from BOTTOM to OCR1A, (OCR1A + 1) ticks). */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

volatile uint16_t pulse_ticks = 0;
volatile uint16_t pulses = 0;

#if defined(HARDWARE_PWM)
int main(void) {
    DDRB = _BV(PB1);
    ICR1 = 39999;
    TCCR1A = _BV(WGM11);
    TCCR1B = _BV(WGM13) | _BV(WGM12) | _BV(CS11);
    for (;;) {
        const uint16_t ticks = pulse_ticks;
        if (ticks == 0) {
            TCCR1A = _BV(WGM11); /* OC1A off: the port bit (low) */
        } else {
            OCR1A = ticks - 1;
            TCCR1A = _BV(COM1A1) | _BV(WGM11);
        }
    }
}
#else
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
#endif
