/* Test firmware for IsrMonitor: one ISR of known length and a main loop of
 * known instructions, so entry latency and duration can be worked out by hand
 * from the disassembly (avr-objdump -d isr_timing.elf).
 *
 *   INT0 (pin 2, any change): naked ISR = 5 x NOP (1 cycle each) + RETI (4).
 *   The vector is "jmp __vector_1" (3 cycles).
 *   main: configures INT0, sei, then "rjmp .-2" forever (2 cycles).
 */
#include <avr/interrupt.h>
#include <avr/io.h>

#include "nop_isr.h" /* tests/firmware */

NOP_ISR(INT0_vect)

int main(void) {
    EICRA = _BV(ISC00); /* any logical change on INT0 */
    EIMSK = _BV(INT0);
    sei();
    for (;;) {
    }
}
