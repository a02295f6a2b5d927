/* Enables the watchdog (15 ms) and never resets it: the chip resets. */
#include <avr/wdt.h>

#include "common.h"

int main(void) {
    uart_init();
    uart_puts((MCUSR & _BV(WDRF)) ? "after watchdog\r\n" : "booted\r\n");
    MCUSR = 0;
    wdt_enable(WDTO_15MS);
    for (;;) {
    }
}
