/* Prints a line, disables interrupts and sleeps: nothing can wake it. */
#include <avr/interrupt.h>
#include <avr/sleep.h>

#include "common.h"

int main(void) {
    uart_init();
    uart_puts("sleeping\r\n");
    while (!(UCSR0A & _BV(TXC0))) {
    }
    cli();
    set_sleep_mode(SLEEP_MODE_PWR_DOWN);
    sleep_enable();
    sleep_cpu();
    for (;;) {
    }
}
