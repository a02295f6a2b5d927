/* Pin modes in stages, for the PinProbe and PinDriver tests (ATmega328P
 * datasheet 7810D section 13.2.1, Table 13-1). The test writes `stage`; the
 * firmware configures PD7 (Arduino pin 7) as the stage says, reads PIND7
 * into `pin_read` and sets `done` to the stage:
 *   1 input, PORT = 0 (floating)     5 PORT = 1, then output (high)
 *   2 input, PORT = 1 (pull-up on)   6 write 1 to PIND7: PORT toggles (low)
 *   3 PUD set in MCUCR               7 input again (PORT = 0: floating)
 *   4 PUD cleared                    8 pull-up on, then PD6 toggled: a write
 *                                      to PORTD that is not about PD7 */
#include <avr/io.h>
#include <stdint.h>

volatile uint8_t stage;
volatile uint8_t done;
volatile uint8_t pin_read;

static void run_stage(uint8_t s) {
    switch (s) {
        case 1: DDRD &= (uint8_t)~_BV(PD7); PORTD &= (uint8_t)~_BV(PD7); break;
        case 2: PORTD |= _BV(PD7); break;
        case 3: MCUCR |= _BV(PUD); break;
        case 4: MCUCR &= (uint8_t)~_BV(PUD); break;
        case 5: PORTD |= _BV(PD7); DDRD |= _BV(PD7); break;
        case 6: PIND = _BV(PD7); break;
        case 7: DDRD &= (uint8_t)~_BV(PD7); break;
        case 8: PORTD |= _BV(PD7); PORTD ^= _BV(PD6); break;
        default: break;
    }
}

int main(void) {
    for (;;) {
        const uint8_t s = stage;
        if (s == done) continue;
        run_stage(s);
        pin_read = (uint8_t)((PIND >> PD7) & 1U);
        done = s;
    }
}
