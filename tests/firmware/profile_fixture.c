/* A firmware of known call structure for the function-profiler test: a loop
 * of known instructions with a call, a nested call, a tail call and a loop
 * mark, and an INT0 ISR that calls a function. avr-objdump -d (avr-gcc -Os):
 *
 *   leaf:       nop x4, ret                        4 + 4      =  8 cycles
 *   middle:     nop, call leaf, nop, ret           1+4+1+4    = 10 (+ leaf)
 *   tailer:     nop, jmp leaf                      1 + 3      =  4 (+ leaf)
 *   mark:       nop x2, ret                        2 + 4      =  6
 *   __vector_1: nop, call leaf, nop, reti          1+4+1+4    = 10 (+ leaf)
 *   vector 1:   jmp __vector_1 (in __vectors)                    3
 *   main loop:  call middle, call tailer, call mark, rjmp      4+4+4+2 = 14
 *
 * Cycles: ATmega328P instruction set summary, 16-bit PC: NOP 1, RJMP 2,
 * JMP 3, CALL 4, RET 4, RETI 4. One loop iteration is 50 cycles; each INT0
 * interrupt 3 + 10 + 8 = 21 (simavr 1.6 charges no response cycles). */
#include <avr/interrupt.h>
#include <avr/io.h>

__attribute__((noinline, used)) void leaf(void) {
    __asm__ volatile("nop\n\tnop\n\tnop\n\tnop\n\t");
}

/* The NOP after the call keeps it a call (not a tail jump). */
__attribute__((noinline, used)) void middle(void) {
    __asm__ volatile("nop\n\t");
    leaf();
    __asm__ volatile("nop\n\t");
}

/* -Os turns the last call into "jmp leaf": a tail transfer. */
__attribute__((noinline, used)) void tailer(void) {
    __asm__ volatile("nop\n\t");
    leaf();
}

__attribute__((noinline, used)) void mark(void) {
    __asm__ volatile("nop\n\tnop\n\t");
}

/* Naked: exactly these four instructions, no register saving. */
ISR(INT0_vect, ISR_NAKED) {
    __asm__ volatile("nop\n\tcall leaf\n\tnop\n\treti\n\t");
}

int main(void) {
    EICRA = _BV(ISC00); /* any logical change on INT0 */
    EIMSK = _BV(INT0);
    sei();
    for (;;) {
        middle();
        tailer();
        mark();
    }
}
