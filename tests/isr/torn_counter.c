/* Test firmware for TornReadDetector: a 32-bit counter written by the
 * TIMER0_OVF ISR (every 256 cycles, prescaler 1) and read by the main loop.
 *
 * The ISR stores n * 0x01010101 (all four bytes equal, n = 1, 2, ... mod 256),
 * so any read that mixes bytes from before and after an ISR has unequal bytes;
 * the main loop counts such reads itself in `inconsistent`, which the HIL's
 * detector must match.
 *
 * How the main loop reads `counter` (one ELF per mode):
 *   default           4 x LDS with interrupts enabled (racy)
 *   READ_POINTER      LD/LDD through Z from a volatile pointer (racy)
 *   READ_ATOMIC       cli; 4 x LDS; sei (never torn)
 */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <stdint.h>

volatile uint32_t counter;
volatile uint32_t copy;
volatile uint32_t reads;
volatile uint32_t inconsistent;
static volatile uint8_t n;
#if defined(READ_POINTER)
volatile uint32_t* volatile counter_ptr = &counter;
#endif

ISR(TIMER0_OVF_vect) {
    uint8_t v = (uint8_t)(n + 1);
    n = v;
    uint32_t w = v;
    w |= w << 8;
    w |= w << 16;
    counter = w;
}

static inline uint32_t read_counter(void) {
#if defined(READ_ATOMIC)
    cli();
    uint32_t v = counter;
    sei();
    return v;
#elif defined(READ_POINTER)
    return *counter_ptr;
#else
    return counter;
#endif
}

int main(void) {
    TCCR0A = 0;
    TCCR0B = _BV(CS00); /* clk/1: overflow every 256 cycles */
    TIMSK0 = _BV(TOIE0);
    sei();
    for (;;) {
        uint32_t v = read_counter();
        copy = v;
        uint8_t b0 = (uint8_t)v;
        uint8_t b1 = (uint8_t)(v >> 8);
        uint8_t b2 = (uint8_t)(v >> 16);
        uint8_t b3 = (uint8_t)(v >> 24);
        if (b0 != b1 || b1 != b2 || b2 != b3) ++inconsistent;
        uint32_t r = reads + 1;
        reads = r;
        /* 0..7 extra cycles: without them the loop and the 256-cycle timer
         * lock in phase and the 4 x LDS read is never split. */
        for (uint8_t i = (uint8_t)(r & 7); i != 0; --i) __asm__ volatile("");
    }
}
