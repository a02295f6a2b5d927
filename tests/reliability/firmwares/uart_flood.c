/* Writes to the UART as fast as the line allows, forever. */
#include "common.h"

int main(void) {
    uart_init();
    for (unsigned long n = 0;; ++n) uart_puts(n % 2 ? "flood flood flood flood\r\n" : "FLOOD FLOOD FLOOD FLOOD\r\n");
}
