/* Loops that fast-forward (hil/fast_forward.hpp) must skip exactly or
 * leave alone, for tests/tools/fast_forward_test.cpp: each mode's output
 * must be byte for byte the same with and without --no-fast-forward. No
 * Arduino core: Timer0 runs as the core's init() sets it (fast PWM, clk/64,
 * overflow interrupt counting overflows: 1024 cycles each), and us() reads
 * it as the core's micros() does (TCNT0, TOV0 with interrupts off).
 *
 *   FF_SRAM_COUNTER: counts passes of a 5 ms wait in SRAM (never skipped:
 *     "changes ... from pass to pass"), then waits 3 ms in a loop that
 *     writes nothing (skipped).
 *   FF_ISR_FLAG: waits for a flag that Timer1's compare-match ISR sets
 *     every 10 ms (CTC, OCR1A = 2499, clk/64): a loop that only reads.
 *   FF_PIN_POLL: both motors of the default board at full drive (as
 *     drive_fixture.c); polls PIND bit 2 (encoder 1) for 20 edges.
 *   FF_UDR_POLL: polls UCSR0A's RXC0 for bytes from the host and echoes
 *     each with its time.
 *   FF_WATCHDOG: prints MCUSR, enables the watchdog (15 ms) and never
 *     resets it: the chip resets about every 16 ms, inside the wait loop
 *     after "done" (a reset that comes while fast-forward steps must be
 *     the core's, as without it).
 *   FF_LATE_ENABLE: Timer2 in the Arduino core's phase-correct mode (WGM
 *     1, clk/64) with its overflow interrupt off sets TOV2 every 32,640
 *     cycles inside waits fast-forward skips; the interrupt is then
 *     enabled and entered at once, its latency counted from the raise.
 *   FF_TCNT2_POLL: Timer2 in phase-correct PWM at clk/64 (counting
 *     0..TOP..0, hil/phase_correct_timer.hpp), interrupts off; polls TCNT2
 *     up past one value and down past another, three times each in WGM 1
 *     (TOP 0xFF), in WGM 5 with OCR2A = 150 as TOP, and after OCR2A = 90
 *     (a new TOP, taken at the next TOP).
 *   FF_PORT_WRITES: a kit robot's loop(): both motors of the default board
 *     at full drive, and every pass sets their four pins (PORTB) and one
 *     pin's direction (DDRB) again with the values they hold, under cli as
 *     digitalWrite() and pinMode() do, through one function called four
 *     times a pass (a PC the pass runs through four times), writes
 *     TCCR0A and OCR0B (Timer0 in fast PWM) their values, and reads PD2
 *     (encoder 1): 20 edges. Then loops whose writes are not inert in
 *     simavr 1.6, each 10 ms: with PCINT2 (PB2, an output) in PCMSK0
 *     (every PORTB write raises PCIF0); with OC0B (D5) driven by Timer0's
 *     PWM and a PORTD write each pass (PIN5 follows the waveform, PORT5
 *     does not); and one that sets a pin low and high each pass.
 *   FF_DELAY_MS: the Arduino core's delay() algorithm (a millisecond
 *     counted down each time us() has moved on 1000 us: the path changes
 *     every 16,000 cycles), 100 ms called from run() and 100 ms from three
 *     calls deeper (another stack depth).
 *   FF_UNREAD_EDGES: both motors at full drive, the encoders' edges on
 *     PD2 (INT0, PCINT18) and PD3 (INT1, PCINT19) while a loop waits
 *     without reading PIND, four ways (100, 50, 50 and 20 ms): INT0/INT1 in their reset state
 *     (low-level sense, off: simavr sets INTFn on a low only with the I flag
 *     set), sensing rising edges but off (INTFn set), PCMSK2 set with PCIE2
 *     off (PCIF2 set), and PCIE2 on with an ISR counting the edges. Prints
 *     EIFR, PCIFR and the count after each.
 *   FF_MASKED_PIN: both motors at full drive, the encoders' edges on PD2
 *     and PD3 (interrupts off) while loops read PIND and use bit 7 only (a
 *     pull-up, always high): 50 ms through Arduino's digitalRead() scheme
 *     (the input register's address and the pin's mask from flash tables,
 *     the register loaded whole and masked), 50 ms through SBIS; then the
 *     same read_pin() of PD2 counts 20 of encoder 1's edges.
 *   FF_OC_PWM: PWM on OC0A/OC0B (Timer0, D6/D5) and OC1A/OC1B (Timer1 in
 *     mode 14 at 20 kHz, D9/D10), no compare interrupts: a 50 ms wait that
 *     reads none of the pins; a 10 ms wait on PB0 (reading PINB);
 *     10 ms with PCINT1 (PB1) enabled, an ISR counting; 10 ms with OC1A
 *     toggling on compare match (simavr writes PORTB then).
 *   FF_T1_CLOCK: Timer1 counts the falling edges of OC0B's PWM on D5 (its
 *     T1 pin); a loop polls TCNT1 up to 40.
 * Each prints one line per event, with us() at it, then "done". */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

#include "usart0.h"

static volatile uint32_t overflows;
ISR(TIMER0_OVF_vect) { ++overflows; }

static uint32_t us(void) {
    const uint8_t sreg = SREG;
    cli();
    uint32_t m = overflows;
    const uint8_t t = TCNT0;
    if ((TIFR0 & _BV(TOV0)) && t < 255) ++m;
    SREG = sreg;
    return ((m << 8) + t) * 4U;
}

static void wait_us(uint32_t d) {
    const uint32_t start = us();
    while (us() - start < d) {
    }
}

static void put_u32(uint32_t v) {
    char buf[11];
    char* p = buf + sizeof buf - 1;
    *p = '\0';
    do {
        *--p = (char)('0' + v % 10U);
        v /= 10U;
    } while (v != 0U);
    usart0_put(p);
}

static void event(const char* what, uint32_t value) {
    usart0_put(what);
    usart0_put(" ");
    put_u32(value);
    usart0_put(" at ");
    put_u32(us());
    usart0_put("\n");
}

#if defined(FF_SRAM_COUNTER)
static volatile uint32_t passes;
static void run(void) {
    for (uint8_t i = 0; i < 5; ++i) {
        passes = 0;
        const uint32_t start = us();
        while (us() - start < 5000U) ++passes;
        event("passes", passes);
        wait_us(3000U);
    }
}
#elif defined(FF_ISR_FLAG)
static volatile uint8_t flag;
static volatile uint16_t ticks;
ISR(TIMER1_COMPA_vect) {
    flag = 1;
    ++ticks;
}
static void run(void) {
    OCR1A = 2499;
    TCCR1B = _BV(WGM12) | _BV(CS11) | _BV(CS10); /* CTC, clk/64: 10 ms */
    TIMSK1 = _BV(OCIE1A);
    for (uint8_t i = 0; i < 8; ++i) {
        while (!flag) {
        }
        flag = 0;
        event("tick", ticks);
    }
}
#elif defined(FF_PIN_POLL)
static void run(void) {
    const uint8_t drive = _BV(PB2) | _BV(PB3) | _BV(PB4) | _BV(PB5); /* D10..D13 */
    PORTB |= drive;
    DDRB |= drive;
    for (uint8_t i = 0; i < 20; ++i) {
        const uint8_t level = PIND & _BV(PD2);
        while ((PIND & _BV(PD2)) == level) {
        }
        event("edge", i);
    }
}
#elif defined(FF_UDR_POLL)
static void run(void) {
    UCSR0B |= _BV(RXEN0);
    for (uint8_t i = 0; i < 3; ++i) {
        while (!(UCSR0A & _BV(RXC0))) {
        }
        event("byte", UDR0);
    }
}
#elif defined(FF_WATCHDOG)
#include <avr/wdt.h>
static void run(void) {
    event("mcusr", MCUSR);
    MCUSR = 0;
    wdt_enable(WDTO_15MS);
}
#elif defined(FF_LATE_ENABLE)
static volatile uint8_t t2_overflows;
ISR(TIMER2_OVF_vect) {
    ++t2_overflows;
    TIMSK2 = 0;
}
static void run(void) {
    TCCR2A = _BV(WGM20); /* phase-correct PWM, TOP 0xFF (as the core's init()) */
    TCCR2B = _BV(CS22);  /* clk/64: one overflow per 32,640 cycles */
    for (uint8_t i = 0; i < 6; ++i) {
        wait_us(3000U + 777U * i);
        TIMSK2 = _BV(TOIE2);
        event("t2", t2_overflows);
    }
}
#elif defined(FF_TCNT2_POLL)
static void poll_count(uint8_t high, uint8_t low) {
    while (TCNT2 < high) {
    }
    event("up", TCNT2);
    while (TCNT2 > low) {
    }
    event("down", TCNT2);
}
static void run(void) {
    TCCR2A = _BV(WGM20);
    TCCR2B = _BV(CS22);
    for (uint8_t i = 0; i < 3; ++i) poll_count(200, 50);
    OCR2A = 150;
    TCCR2B = _BV(WGM22) | _BV(CS22);
    for (uint8_t i = 0; i < 3; ++i) poll_count(140, 20);
    OCR2A = 90;
    for (uint8_t i = 0; i < 3; ++i) poll_count(80, 20);
}
#elif defined(FF_DELAY_MS)
static void delay_ms(uint32_t ms) {
    uint32_t start = us();
    while (ms > 0) {
        while (ms > 0 && (us() - start) >= 1000U) {
            --ms;
            start += 1000U;
        }
    }
}
static void deeper(uint8_t depth) {
    volatile uint8_t frame[8];
    frame[0] = depth;
    if (depth > 0) {
        deeper((uint8_t)(depth - 1));
    } else {
        delay_ms(100);
    }
    (void)frame[0];
}
static void run(void) {
    delay_ms(100);
    event("delay", 100);
    deeper(3);
    event("delay", 200);
}
#elif defined(FF_PORT_WRITES)
static __attribute__((noinline)) void set_pin(volatile uint8_t* port, uint8_t bit, uint8_t high) {
    const uint8_t sreg = SREG;
    cli();
    if (high) {
        *port |= bit;
    } else {
        *port &= (uint8_t)~bit;
    }
    SREG = sreg;
}
static __attribute__((noinline)) void make_output(volatile uint8_t* ddr, uint8_t bit) {
    const uint8_t sreg = SREG;
    cli();
    *ddr |= bit;
    SREG = sreg;
}
static uint8_t drive_pass(void) {
    make_output(&DDRB, _BV(PB2));
    set_pin(&PORTB, _BV(PB2), 1);
    set_pin(&PORTB, _BV(PB3), 1);
    set_pin(&PORTB, _BV(PB4), 1);
    set_pin(&PORTB, _BV(PB5), 1);
    TCCR0A |= _BV(WGM00);
    OCR0B = 0;
    return PIND & _BV(PD2);
}
static void for_10_ms(void (*pass)(void)) {
    const uint32_t start = us();
    while (us() - start < 10000U) pass();
}
static void portb_pass(void) { set_pin(&PORTB, _BV(PB3), 1); }
static void portd_pass(void) { set_pin(&PORTD, _BV(PD7), 1); }
static void toggle_pass(void) {
    set_pin(&PORTB, _BV(PB5), 0);
    set_pin(&PORTB, _BV(PB5), 1);
}
static void run(void) {
    DDRB |= _BV(PB2) | _BV(PB3) | _BV(PB4) | _BV(PB5); /* D10..D13 */
    for (uint8_t i = 0; i < 20; ++i) {
        const uint8_t level = drive_pass();
        while (drive_pass() == level) {
        }
    }
    event("edges", 20);
    PCMSK0 = _BV(PCINT2);
    for_10_ms(portb_pass);
    event("pcmsk", PCIFR);
    PCMSK0 = 0;
    DDRD |= _BV(PD5) | _BV(PD7);
    OCR0B = 100;
    TCCR0A |= _BV(COM0B1);
    for_10_ms(portd_pass);
    event("pwm", OCR0B);
    for_10_ms(toggle_pass);
    event("toggle", PINB);
}
#elif defined(FF_UNREAD_EDGES)
static volatile uint16_t changes;
ISR(PCINT2_vect) { ++changes; }
static void run(void) {
    const uint8_t drive = _BV(PB2) | _BV(PB3) | _BV(PB4) | _BV(PB5); /* D10..D13 */
    PORTB |= drive;
    DDRB |= drive;
    wait_us(100000U);
    event("level sense", EIFR);
    EICRA = _BV(ISC01) | _BV(ISC00) | _BV(ISC11) | _BV(ISC10);
    wait_us(50000U);
    event("rising edges", EIFR);
    PCMSK2 = _BV(PCINT18) | _BV(PCINT19);
    wait_us(50000U);
    event("pcmsk", PCIFR);
    PCICR = _BV(PCIE2);
    wait_us(20000U);
    event("pcint", changes);
}
#elif defined(FF_MASKED_PIN)
#include <avr/pgmspace.h>
static const uint8_t pin_masks[16] PROGMEM = {1, 2, 4, 8, 16, 32, 64, 128, 1, 2, 4, 8, 16, 32, 64, 128};
static const uint8_t pin_inputs[2] PROGMEM = {_SFR_MEM_ADDR(PIND), _SFR_MEM_ADDR(PINB)};
/* digitalRead(): pins 0..7 on PORTD, 8..15 on PORTB. */
__attribute__((noinline)) static uint8_t read_pin(uint8_t pin) {
    const uint8_t mask = pgm_read_byte(&pin_masks[pin]);
    volatile uint8_t* input = (volatile uint8_t*)(uint16_t)pgm_read_byte(&pin_inputs[pin >> 3]);
    return (*input & mask) ? 1 : 0;
}
static void run(void) {
    const uint8_t drive = _BV(PB2) | _BV(PB3) | _BV(PB4) | _BV(PB5); /* D10..D13 */
    PORTB |= drive;
    DDRB |= drive;
    PORTD |= _BV(PD7); /* pull-up */
    uint32_t start = us();
    while (read_pin(7) && us() - start < 50000U) {
    }
    event("digitalRead", read_pin(7));
    start = us();
    while (bit_is_set(PIND, PD7) && us() - start < 50000U) {
    }
    event("sbis", PIND & _BV(PD7));
    uint8_t last = read_pin(2);
    for (uint8_t n = 0; n < 20;) {
        const uint8_t now = read_pin(2);
        if (now != last) {
            ++n;
            last = now;
        }
    }
    event("edges", 20);
}
#elif defined(FF_OC_PWM)
static volatile uint16_t oc_changes;
ISR(PCINT0_vect) { ++oc_changes; }
static void run(void) {
    /* OC0A (D6) and OC0B (D5): Timer0's fast PWM, non-inverting. */
    OCR0A = 64;
    OCR0B = 192;
    DDRD |= _BV(PD5) | _BV(PD6);
    TCCR0A |= _BV(COM0A1) | _BV(COM0B1);
    /* OC1A (D9) and OC1B (D10): Timer1 in mode 14 (fast PWM, TOP = ICR1),
     * clk/1: 20 kHz, a change every 400 cycles on average. */
    ICR1 = 799;
    OCR1A = 300;
    OCR1B = 500;
    DDRB |= _BV(PB1) | _BV(PB2);
    TCCR1A = _BV(COM1A1) | _BV(COM1B1) | _BV(WGM11);
    TCCR1B = _BV(WGM13) | _BV(WGM12) | _BV(CS10);
    wait_us(50000U);
    event("pwm", TCNT1);
    /* A wait on PB0 (a pull-up): each read of PINB stores PORTB's bits into
     * its output bits (simavr 1.6), over OC1A's and OC1B's levels, which
     * therefore bound the jumps. */
    PORTB |= _BV(PB0);
    const uint32_t start = us();
    while (bit_is_set(PINB, PB0) && us() - start < 10000U) {
    }
    event("pinb", PINB);
    /* PCINT1 on OC1A's pin: each change requests PCINT0. */
    PCMSK0 = _BV(PCINT1);
    PCICR = _BV(PCIE0);
    wait_us(10000U);
    PCICR = 0;
    event("pcint", oc_changes);
    /* Toggle on compare match (COM1A = 1): simavr writes PORTB. */
    TCCR1A = _BV(COM1A0) | _BV(COM1B1) | _BV(WGM11);
    wait_us(10000U);
    event("toggle", PORTB);
}
#elif defined(FF_T1_CLOCK)
static void run(void) {
    /* OC0B (D5, T1) drives Timer1's clock: Timer1 counts its falling edges
     * (CS12:0 = 6), at Timer0's compare match B (the rising ones come at
     * its overflow, whose interrupt bounds every jump anyway). */
    OCR0B = 192;
    DDRD |= _BV(PD5);
    TCCR0A |= _BV(COM0B1);
    TCCR1A = 0;
    TCCR1B = _BV(CS12) | _BV(CS11);
    while (TCNT1 < 40U) {
    }
    event("t1", TCNT1);
}
#else
#error "define one of FF_SRAM_COUNTER, FF_ISR_FLAG, FF_PIN_POLL, FF_UDR_POLL, FF_WATCHDOG, FF_LATE_ENABLE, FF_TCNT2_POLL, FF_PORT_WRITES, FF_DELAY_MS, FF_UNREAD_EDGES, FF_MASKED_PIN, FF_OC_PWM, FF_T1_CLOCK"
#endif

int main(void) {
    TCCR0A = _BV(WGM01) | _BV(WGM00);
    TCCR0B = _BV(CS01) | _BV(CS00);
    TIMSK0 = _BV(TOIE0);
    usart0_begin_9600();
    sei();
    run();
    usart0_put("done\n");
    for (;;) {
        wait_us(1000U);
    }
}
