/* Both motors of the default board (firmware/ddmr_tracking/board.yaml)
 * driven forward at full drive from reset, with encoder interrupts of known
 * length and interrupts off half the time, for the scenario tests that make
 * each step kind fail (tests/tools/scenario_failures_test.cpp). No Arduino
 * core: the robot moves within milliseconds of reset, not after the
 * reference sketch's delay(5000).
 *   D10 (EN1), D11 (EN2), D12 (DIR1), D13 (DIR2): outputs, high. No timer
 *     drives D10/D11, so the enables are a static high level: duty 1.
 *   INT0 (D2, encoder 1), any change: count1++ (a uint32_t, as the
 *     reference's Count1).
 *   INT1 (D3, encoder 2), any change: a naked ISR of 5 NOPs and RETI. With
 * the vector's JMP: 3 + 5 x 1 + 4 = 12 cycles (nop_isr.h).
 *   main: interrupts off for 20,000 cycles (1.25 ms), then on for 20,000,
 *     forever. At full speed an encoder edges every ~11,900 cycles (the
 *     motor's 1055 rad/s no-load speed, plant/params/default.yaml, at 8
 *     edges a turn), so an edge raised early in an off window waits for up
 *     to 20,000 cycles, and an off window that holds two edges of one wheel
 *     loses the second (its flag is still set). */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

#include "nop_isr.h"

volatile uint32_t count1;

ISR(INT0_vect) { ++count1; }

NOP_ISR(INT1_vect)

int main(void) {
    const uint8_t drive = _BV(PB2) | _BV(PB3) | _BV(PB4) | _BV(PB5); /* D10..D13 */
    PORTB |= drive;
    DDRB |= drive;
    EICRA = _BV(ISC00) | _BV(ISC10); /* INT0, INT1: any logical change */
    EIMSK = _BV(INT0) | _BV(INT1);
    for (;;) {
        cli();
        __builtin_avr_delay_cycles(20000);
        sei();
        __builtin_avr_delay_cycles(20000);
    }
}
