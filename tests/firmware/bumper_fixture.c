/* A bumper on D7 (PD7) read as a sketch does it, with pinMode(7,
 * INPUT_PULLUP), while the sketch also writes to the same port: forever,
 * PD4 (an output: an LED) is toggled by writing PORTD, then PD7 is read.
 * level = the last read, lows / highs count the reads of each level. For
 * the bumper part's tests (SENSORS.md section 4: simavr 1.6 re-raises the
 * pull-up on every PORTx write unless the part's level is external). */
#include <avr/io.h>
#include <stdint.h>

volatile uint8_t level;
volatile uint16_t lows;
volatile uint16_t highs;

int main(void) {
    DDRD = _BV(PD4);
    PORTD = _BV(PD7); /* INPUT_PULLUP on D7 */
    for (;;) {
        PORTD ^= _BV(PD4); /* a write to the bumper's port */
        level = (uint8_t)((PIND >> PD7) & 1);
        if (level) {
            ++highs;
        } else {
            ++lows;
        }
    }
}
