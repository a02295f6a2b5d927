/* Writes the EEPROM as fast as it can, forever: write n goes to address
 * n mod 1024 and holds (n / 8) mod 256, so every pass over the EEPROM leaves
 * other values than the one before. */
#include <avr/eeprom.h>

int main(void) {
    for (unsigned long n = 0;; ++n) eeprom_write_byte((uint8_t*)(unsigned)(n & 1023U), (uint8_t)(n >> 3));
}
