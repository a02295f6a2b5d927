/* A weak function that nothing defines: the linker resolves it to 0, so a
 * call to it is `call 0`, a restart from the reset vector (hil/zero_calls).
 * GUARDED: the call is tested first, as the Arduino core's serialEventRun
 * tests the weak serialEvent: never reported. NULL_POINTER: a call through a
 * null function pointer read at run time (`icall` with Z = 0): nothing to
 * find in the ELF, a restart when run. Otherwise the call is unguarded:
 * reported, in main, naming `hook`; it restarts the firmware when run. */
#include <stdint.h>

void hook(void) __attribute__((weak));

volatile uint8_t ticks;

int main(void) {
#if defined(GUARDED)
    if (hook) hook();
#elif defined(NULL_POINTER)
    void (*volatile callback)(void) = 0;
    callback();
#else
    hook();
#endif
    for (;;) ++ticks;
}
