/* A control loop of known cycle counts for the loop-profiler test: no
 * interrupts, a body of 5 NOPs, and a loop-mark function of 3 NOPs.
 * Expected (ATmega328P instruction set manual, 16-bit PC):
 *   mark:  nop nop nop ret            -> 3 x 1 + 4 = 7 cycles (the wait part)
 *   main:  nop x5, call mark, rjmp    -> after mark returns: rjmp 2, nop 5,
 *                                        call 4 = 11 cycles (the compute part)
 *   period = 18 cycles. */
__attribute__((noinline, used)) void mark(void) {
    __asm__ volatile("nop\n\tnop\n\tnop\n\t");
}

int main(void) {
    for (;;) {
        __asm__ volatile("nop\n\tnop\n\tnop\n\tnop\n\tnop\n\t");
        mark();
    }
}
