/* analogRead() as the Arduino core does it, written from the ATmega328P
 * datasheet (section 24.9: ADMUX, ADCSRA, ADCL/ADCH), for the AdcInput tests:
 * the ADC enabled with the /128 prescaler (125 kHz at 16 MHz, as wiring.c's
 * init() sets it), then forever: codes[n] = channel n (A0..A5) against AVCC
 * (REFS1:0 = 01, the core's DEFAULT), code_1v1 = A0 against the internal
 * 1.1 V (REFS1:0 = 11), then ++rounds. Built for the ATmega2560 as well
 * (2549Q section 26.8, Table 26-4): there codes_high[n] = ADC8+n (A8..A13),
 * selected as the Mega core's analogRead() does, with MUX5 in ADCSRB set and
 * MUX4:0 = n. */
#include <avr/io.h>
#include <stdint.h>

volatile uint16_t codes[6];
volatile uint16_t code_1v1;
volatile uint8_t rounds;
#if defined(MUX5)
volatile uint16_t codes_high[6];
#endif

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
#if defined(MUX5)
        ADCSRB |= _BV(MUX5);
        for (uint8_t ch = 0; ch < 6; ++ch) codes_high[ch] = convert(_BV(REFS0) | ch);
        ADCSRB &= (uint8_t)~_BV(MUX5);
#endif
        ++rounds;
    }
}
