/* Encoder interrupts the way robot sketches configure them, for the
 * EncoderInjector tests (ATmega328P datasheet 7810D, section 12):
 *   INT0 (D2) on RISING edges only (EICRA ISC01:0 = 11): int0_count++, and
 *     the level of D4 (a quadrature B channel on a plain pin) read in the
 *     ISR: b_high_count++ when it is high;
 *   pin-change group 1 (PCICR PCIE1) with PCMSK1 = PCINT12 | PCINT13 (A4,
 *     A5): pcint1_count++, and the last PINC seen in the ISR.
 * main() then spins with interrupts on. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

volatile uint16_t int0_count;
volatile uint16_t b_high_count;
volatile uint16_t pcint1_count;
volatile uint8_t last_pinc;
volatile uint8_t ready;

ISR(INT0_vect) {
    ++int0_count;
    if (PIND & _BV(PD4)) ++b_high_count;
}

ISR(PCINT1_vect) {
    ++pcint1_count;
    last_pinc = PINC;
}

int main(void) {
    EICRA = _BV(ISC01) | _BV(ISC00);
    EIFR = _BV(INTF0);
    EIMSK = _BV(INT0);
    PCMSK1 = _BV(PCINT12) | _BV(PCINT13);
    PCIFR = _BV(PCIF1);
    PCICR = _BV(PCIE1);
    sei();
    ready = 1;
    for (;;) {
    }
}
