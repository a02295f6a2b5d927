/* Interrupts on pin edges, for the PinDriver's scheduled edges (ATmega328P
 * datasheet 7810D section 12): INT0 (D2) on rising edges (EICRA ISC01:0 =
 * 11) counts int0_count; pin-change group 1 with PCMSK1 = PCINT8 (A0)
 * counts pcint1_count. main() then runs a sled of 1-cycle NOPs with
 * interrupts on, so an edge at any cycle but the loop's RJMP falls on an
 * instruction boundary. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

volatile uint16_t int0_count;
volatile uint16_t pcint1_count;
volatile uint8_t ready;

ISR(INT0_vect) { ++int0_count; }

ISR(PCINT1_vect) { ++pcint1_count; }

int main(void) {
    EICRA = _BV(ISC01) | _BV(ISC00);
    EIFR = _BV(INTF0);
    EIMSK = _BV(INT0);
    PCMSK1 = _BV(PCINT8);
    PCIFR = _BV(PCIF1);
    PCICR = _BV(PCIE1);
    sei();
    ready = 1;
    for (;;) {
        __asm__ volatile(".rept 250\n\tnop\n\t.endr");
    }
}
