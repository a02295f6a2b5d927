/* One timer in a phase-correct PWM mode that simavr 1.6 lacks, every one of
 * its interrupts enabled with a NOP ISR, then sleep (idle) for ever, for
 * tests/hil/phase_correct_timer_test.cpp. The test records when each flag
 * is raised and reads TCNTn, against the datasheet's timing (7810D §15.9.4,
 * §17.7.4): one period is 2 * TOP * N cycles.
 *
 *   PC_T1_MODE1:  Timer1 WGM 1 (8-bit, TOP 0xFF) at clk/64 as Arduino's
 *                 init() sets it; OCR1A = 100, OCR1B = 255 (= TOP).
 *   PC_T2_MODE1:  Timer2 WGM 1 (TOP 0xFF) at clk/64 (CS22); OCR2A = 200,
 *                 OCR2B = 0 (= BOTTOM).
 *   PC_T1_MODE10: Timer1 WGM 10 (TOP = ICR1 = 1000) at clk/8; OCR1A = 250,
 *                 OCR1B = 1000 (= TOP).
 *   PC_T2_CHANGES: Timer2 at clk/64, OCR2A = 99, through four settings,
 *                 each held for a few of its interrupts: WGM 1 (taken
 *                 over), CTC (WGM 2, simavr's: OCF2A every 6,400 cycles),
 *                 WGM 1 again, then ASSR.AS2 (clocked from TOSC1: simavr's). */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>

#include "nop_isr.h"

#if defined(PC_T1_MODE1) || defined(PC_T1_MODE10)
NOP_ISR(TIMER1_OVF_vect)
NOP_ISR(TIMER1_COMPA_vect)
NOP_ISR(TIMER1_COMPB_vect)
NOP_ISR(TIMER1_CAPT_vect)
#elif defined(PC_T2_CHANGES)
static volatile uint8_t overflows, matches;
ISR(TIMER2_OVF_vect) { ++overflows; }
ISR(TIMER2_COMPA_vect) { ++matches; }
static void sleep_while_below(volatile uint8_t* counter, uint8_t n) {
    const uint8_t start = *counter;
    while ((uint8_t)(*counter - start) < n) sleep_cpu();
}
#elif defined(PC_T2_MODE1)
NOP_ISR(TIMER2_OVF_vect)
NOP_ISR(TIMER2_COMPA_vect)
NOP_ISR(TIMER2_COMPB_vect)
#else
#error "define one of PC_T1_MODE1, PC_T2_MODE1, PC_T1_MODE10, PC_T2_CHANGES"
#endif

int main(void) {
#if defined(PC_T2_CHANGES)
    set_sleep_mode(SLEEP_MODE_IDLE);
    sleep_enable();
    OCR2A = 99;
    TIMSK2 = _BV(TOIE2) | _BV(OCIE2A);
    sei();
    TCCR2A = _BV(WGM20);
    TCCR2B = _BV(CS22);
    sleep_while_below(&overflows, 4);
    TCCR2A = _BV(WGM21);
    sleep_while_below(&matches, 8);
    TCCR2A = _BV(WGM20);
    sleep_while_below(&overflows, 4);
    ASSR = _BV(AS2);
    for (;;) sleep_cpu();
#elif defined(PC_T1_MODE1)
    OCR1A = 100;
    OCR1B = 255;
    TIMSK1 = _BV(TOIE1) | _BV(OCIE1A) | _BV(OCIE1B) | _BV(ICIE1);
    TCCR1A = _BV(WGM10);
    TCCR1B = _BV(CS11) | _BV(CS10);
#elif defined(PC_T2_MODE1)
    OCR2A = 200;
    OCR2B = 0;
    TIMSK2 = _BV(TOIE2) | _BV(OCIE2A) | _BV(OCIE2B);
    TCCR2A = _BV(WGM20);
    TCCR2B = _BV(CS22);
#else
    ICR1 = 1000;
    OCR1A = 250;
    OCR1B = 1000;
    TIMSK1 = _BV(TOIE1) | _BV(OCIE1A) | _BV(OCIE1B) | _BV(ICIE1);
    TCCR1A = _BV(WGM11);
    TCCR1B = _BV(WGM13) | _BV(CS11);
#endif
#if !defined(PC_T2_CHANGES)
    set_sleep_mode(SLEEP_MODE_IDLE);
    sleep_enable();
    sei();
    for (;;) sleep_cpu();
#endif
}
