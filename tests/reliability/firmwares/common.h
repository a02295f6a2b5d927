/* Shared by the misbehaving test firmwares: USART0 at 9600 baud 8N1 as
 * Arduino sets it (U2X0, UBRR0 = 207) and a blocking byte write. */
#include <avr/io.h>

static void uart_init(void) {
    UCSR0A = _BV(U2X0);
    UBRR0 = 207;
    UCSR0B = _BV(TXEN0) | _BV(RXEN0);
}

static void uart_put(char c) {
    while (!(UCSR0A & _BV(UDRE0))) {
    }
    UDR0 = (unsigned char)c;
}

static void uart_puts(const char* s) {
    while (*s) uart_put(*s++);
}
