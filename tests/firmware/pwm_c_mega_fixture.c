/* pwm_c_mega_fixture: output-compare channel C of the ATmega2560's 16-bit
 * timers, set up as the Arduino core's init() and analogWrite() do (phase
 * correct 8-bit PWM, WGMn0; clock/64; COMnC1 non-inverting): pin 3 = OC3C
 * (PE5) at 64, pin 8 = OC4C (PH5) at 128, pin 44 = OC5C (PL5) at 192 of 255.
 * Period 2 x 255 x 64 = 32,640 cycles, high OCR/255 of it (datasheet 2549Q
 * 17.9.4). No Arduino core. */
#include <avr/io.h>

int main(void) {
    DDRE |= _BV(PE5);
    DDRH |= _BV(PH5);
    DDRL |= _BV(PL5);
    OCR3C = 64;
    OCR4C = 128;
    OCR5C = 192;
    TCCR3A = _BV(COM3C1) | _BV(WGM30);
    TCCR4A = _BV(COM4C1) | _BV(WGM40);
    TCCR5A = _BV(COM5C1) | _BV(WGM50);
    TCCR3B = _BV(CS31) | _BV(CS30);
    TCCR4B = _BV(CS41) | _BV(CS40);
    TCCR5B = _BV(CS51) | _BV(CS50);
    for (;;) {
    }
}
