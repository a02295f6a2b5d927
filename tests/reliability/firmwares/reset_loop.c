/* Prints a line, then calls a weak function that nothing defines: the call
 * links to `call 0` and restarts the firmware without a reset, again and
 * again (one boot per 8 bytes at 9600 baud: about 110 a second). */
#include "common.h"

void missing_hook(void) __attribute__((weak));

int main(void) {
    uart_init();
    uart_puts("booted\r\n");
    missing_hook();
    for (;;) {
    }
}
