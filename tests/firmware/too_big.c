/* A program whose flash image (two 20,000-byte constant tables) does not fit the
 * ATmega328P's 32 KiB: ddmr-hil must refuse it before running. Linked for
 * the ATmega644P (avr5 like the 328P, 64 KiB of flash) so the linker accepts
 * it and the architecture check passes: the check that must fire is the size. */
#include <avr/pgmspace.h>

const char big1[20000] PROGMEM = {1};
const char big2[20000] PROGMEM = {2};

int main(void) {
    volatile char c = pgm_read_byte(&big1[19999]);
    c = pgm_read_byte(&big2[19999]);
    (void)c;
    for (;;) {
    }
}
