/* Encoder interrupts the way robot sketches configure them, for the
 * EncoderInjector tests (ATmega328P datasheet 7810D, section 12):
 *   INT0 (D2) on RISING edges only (EICRA ISC01:0 = 11): int0_count++, and
 *     the level of D4 (a quadrature B channel on a plain pin) read in the
 *     ISR: b_high_count++ when it is high;
 *   pin-change group 1 (PCICR PCIE1) with PCMSK1 = PCINT12 | PCINT13 (A4,
 *     A5): pcint1_count++, and the last PINC seen in the ISR;
 *   pin-change group 2 with PCMSK2 = PCINT20 (D4) only, while Timer0 runs
 *     fast PWM on OC0B = D5, a pin of the same group (976.6 Hz, OCR0B 100):
 *     pcint2_count++. A PWM edge on D5 must not raise PCINT2 (simavr fixed
 *     false pin-change interrupts from timer pins only after 1.6: #343, #427).
 * main() then spins with interrupts on. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

volatile uint16_t int0_count;
volatile uint16_t b_high_count;
volatile uint16_t pcint1_count;
volatile uint8_t last_pinc;
volatile uint16_t pcint2_count;
volatile uint8_t ready;

ISR(INT0_vect) {
    ++int0_count;
    if (PIND & _BV(PD4)) ++b_high_count;
}

ISR(PCINT1_vect) {
    ++pcint1_count;
    last_pinc = PINC;
}

ISR(PCINT2_vect) { ++pcint2_count; }

int main(void) {
    DDRD = _BV(PD5);
    OCR0B = 100;
    TCCR0A = _BV(COM0B1) | _BV(WGM01) | _BV(WGM00);
    TCCR0B = _BV(CS01) | _BV(CS00);
    EICRA = _BV(ISC01) | _BV(ISC00);
    EIFR = _BV(INTF0);
    EIMSK = _BV(INT0);
    PCMSK1 = _BV(PCINT12) | _BV(PCINT13);
    PCMSK2 = _BV(PCINT20);
    PCIFR = _BV(PCIF1) | _BV(PCIF2);
    PCICR = _BV(PCIE1) | _BV(PCIE2);
    sei();
    ready = 1;
    for (;;) {
    }
}
