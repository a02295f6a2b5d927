/* USART0 as the Arduino core sets it for Serial.begin(9600) (U2X0,
 * UBRR0 = 207 at 16 MHz: 9615 baud, datasheet 7810D 19.10), transmit only,
 * and a busy-waiting write of a text: for the C fixtures without the core. */
#ifndef DDMR_TEST_USART0_H
#define DDMR_TEST_USART0_H
#include <avr/io.h>

static inline void usart0_begin_9600(void) {
    UCSR0A = _BV(U2X0);
    UBRR0 = 207;
    UCSR0B = _BV(TXEN0);
}

static inline void usart0_put(const char* s) {
    for (; *s != '\0'; ++s) {
        while (!(UCSR0A & _BV(UDRE0))) {
        }
        UDR0 = (unsigned char)*s;
    }
}
#endif
