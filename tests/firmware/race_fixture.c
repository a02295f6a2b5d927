/* Test firmware for RaceDetector (issue 16): the three races it finds, and
 * with -DFIXED the same program without them.
 *
 * TIMER0_OVF runs every 256 cycles (prescaler 1). It
 *   - adds 100 to `ticks` (a volatile long: carries cross bytes often),
 *   - copies `setpoint` (a 16-bit value the main program writes) to `seen`,
 *   - once the main program has set `armed`, sets `flag` after 10 overflows.
 * The main program
 *   1. for kIterations: reads `ticks` (4 x LDS, interrupts on: a torn read;
 *      FIXED: in ATOMIC_BLOCK) and counts the reads whose value went
 *      backwards in `backwards`; writes setpoint = i * 0x0101 (2 x STS: a torn
 *      write the ISR can read; FIXED: in ATOMIC_BLOCK);
 *   2. sets `armed` and waits with `while (!flag) {}`: `flag` is not volatile,
 *      so avr-gcc loads it once and spins in `rjmp .-2` for ever (a stale
 *      read; FIXED: volatile, the loop re-reads it and ends);
 *   3. sets `done`.
 */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>
#include <util/atomic.h>

#ifdef FIXED
#define SHARED volatile
#else
#define SHARED
#endif

enum { kIterations = 12000 };

volatile long ticks;
volatile uint16_t setpoint;
volatile uint16_t seen;
volatile uint8_t armed;
volatile uint8_t done;
volatile uint16_t backwards;
static volatile uint8_t waited;
SHARED uint8_t flag;

ISR(TIMER0_OVF_vect) {
    ticks += 100;
    seen = setpoint;
    if (armed && ++waited >= 10) flag = 1;
}

static long read_ticks(void) {
#ifdef FIXED
    long v;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { v = ticks; }
    return v;
#else
    return ticks;
#endif
}

static void write_setpoint(uint16_t v) {
#ifdef FIXED
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { setpoint = v; }
#else
    setpoint = v;
#endif
}

int main(void) {
    TCCR0A = 0;
    TCCR0B = _BV(CS00); /* clk/1: overflow every 256 cycles */
    TIMSK0 = _BV(TOIE0);
    sei();
    long last = 0;
    for (uint16_t i = 0; i < kIterations; ++i) {
        const long now = read_ticks();
        if (now < last) ++backwards;
        last = now;
        write_setpoint((uint16_t)(i * 0x0101U));
        /* 0..7 extra cycles so the loop and the timer do not lock in phase. */
        for (uint8_t k = (uint8_t)(i & 7); k != 0; --k) __asm__ volatile("");
    }
    armed = 1;
    while (!flag) {
    }
    done = 1;
    for (;;) {
    }
}
