/* serial1_mega_fixture: the ATmega2560's second USART as a Bluetooth module
 * would use it. Serial1 (USART1, RXD1 = PD2 = D19, TXD1 = PD3 = D18) runs at
 * 19200 baud (U2X1, UBRR1 = 103: a bit is (103 + 1) x 8 = 832 cycles at
 * 16 MHz, datasheet 2549Q 22.3.1) and echoes every byte upper-cased; Serial
 * (USART0) at 9600 baud prints "usart0\r\n" once at start. No Arduino core. */
#include "usart0.h"

int main(void) {
    usart0_begin_9600();
    UCSR1A = _BV(U2X1);
    UBRR1 = 103;
    UCSR1B = _BV(TXEN1) | _BV(RXEN1);
    usart0_put("usart0\r\n");
    for (;;) {
        while (!(UCSR1A & _BV(RXC1))) {
        }
        char c = (char)UDR1;
        if (c >= 'a' && c <= 'z') c = (char)(c - 'a' + 'A');
        while (!(UCSR1A & _BV(UDRE1))) {
        }
        UDR1 = (unsigned char)c;
    }
}
