/* Prints a line, then jumps past the end of flash: simavr stops the CPU
 * (crashed at PC ...). */
#include "common.h"

int main(void) {
    uart_init();
    uart_puts("jumping\r\n");
    void (*nowhere)(void) = (void (*)(void))0x7FF0; /* word address 0x7FF0: byte 0xFFE0, erased flash to the end */
    nowhere();
    for (;;) {
    }
}
