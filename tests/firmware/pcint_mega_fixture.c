/* pcint_mega_fixture: counts pin-change interrupts on the ATmega2560's
 * PCINT1 (PCINT9 = PJ0, Mega pin 15) and PCINT2 (PCINT16 = PK0, Mega pin A8),
 * the groups simavr 1.6's core lacks, and on PCINT0 (PCINT0 = PB0, pin 53),
 * which it has. PCINT17 (PK1) stays masked. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

volatile uint16_t pcint0_count;
volatile uint16_t pcint1_count;
volatile uint16_t pcint2_count;

ISR(PCINT0_vect) { pcint0_count++; }
ISR(PCINT1_vect) { pcint1_count++; }
ISR(PCINT2_vect) { pcint2_count++; }

int main(void) {
    PCMSK0 = _BV(PCINT0);
    PCMSK1 = _BV(PCINT9);
    PCMSK2 = _BV(PCINT16);
    PCICR = _BV(PCIE0) | _BV(PCIE1) | _BV(PCIE2);
    sei();
    for (;;) {
    }
}
