/* analogRead() as the Arduino core does it, written from the ATmega328P
 * datasheet (section 24.9: ADMUX, ADCSRA, ADCL/ADCH), for the AdcInput tests:
 * the ADC enabled with the /128 prescaler (125 kHz at 16 MHz, as wiring.c's
 * init() sets it), then forever: codes[n] = channel n (A0..A5) against AVCC
 * (REFS1:0 = 01, the core's DEFAULT), code_1v1 = A0 against the internal
 * 1.1 V (REFS1:0 = 11), then ++rounds. */
#include <avr/io.h>
#include <stdint.h>

volatile uint16_t codes[6];
volatile uint16_t code_1v1;
volatile uint8_t rounds;

static uint16_t convert(uint8_t admux) {
    ADMUX = admux;
    ADCSRA |= _BV(ADSC);
    while (ADCSRA & _BV(ADSC)) {
    }
    const uint8_t low = ADCL; /* ADCL first: it locks ADCH until read */
    const uint8_t high = ADCH;
    return (uint16_t)((uint16_t)high << 8 | low);
}

int main(void) {
    ADCSRA = _BV(ADEN) | _BV(ADPS2) | _BV(ADPS1) | _BV(ADPS0);
    for (;;) {
        for (uint8_t ch = 0; ch < 6; ++ch) codes[ch] = convert(_BV(REFS0) | ch);
        code_1v1 = convert(_BV(REFS1) | _BV(REFS0));
        ++rounds;
    }
}
