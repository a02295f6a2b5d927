/* A naked ISR of known length for the test firmwares: five NOPs and RETI,
 * no register saved. With the vector table's JMP: 3 + 5 x 1 + 4 = 12 cycles
 * (ATmega328P instruction set manual). */
#ifndef DDMR_TEST_NOP_ISR_H
#define DDMR_TEST_NOP_ISR_H

#include <avr/interrupt.h>

#define NOP_ISR(vector)                                                          \
    ISR(vector, ISR_NAKED) {                                                     \
        __asm__ volatile("nop\n\tnop\n\tnop\n\tnop\n\tnop\n\treti\n\t");        \
    }

#endif
