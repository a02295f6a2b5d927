/* Echoes every byte received on USART0 (9600 baud 8N1 as Arduino sets it:
 * U2X0, UBRR0 = 207), upper-cased, for the `run --send` tests. No Arduino
 * core, none of the reference sketch's globals: `run` treats it as a
 * firmware without a sketch contract. */
#include <avr/io.h>

int main(void) {
    UCSR0A = _BV(U2X0);
    UBRR0 = 207;
    UCSR0B = _BV(TXEN0) | _BV(RXEN0);
    for (;;) {
        while (!(UCSR0A & _BV(RXC0))) {
        }
        char c = (char)UDR0;
        if (c >= 'a' && c <= 'z') c = (char)(c - 'a' + 'A');
        while (!(UCSR0A & _BV(UDRE0))) {
        }
        UDR0 = (unsigned char)c;
    }
}
