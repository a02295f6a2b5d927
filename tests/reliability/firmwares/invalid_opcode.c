/* Executes a word that is no AVR instruction. */
#include "common.h"

int main(void) {
    uart_init();
    uart_puts("invalid\r\n");
    __asm__ volatile(".word 0x0001"); /* reserved encoding: simavr reports an invalid opcode */
    for (;;) {
    }
}
