/* A C++ firmware for the loop mark's names (tools/loop_mark.cpp): a member
 * function, two overloads and a serialEventRun() mangled as the Arduino
 * core's (_Z14serialEventRunv), in main's endless loop as Arduino's main
 * calls loop()'s work and serialEventRun(). No Arduino core: no loop(),
 * no delay(). Expected candidates (called from one place in main's loop):
 * serialEventRun, MyClass::step, tick(int), tick(long); not once() (before
 * the loop) nor twice() (two calls in it). */
#include <stdint.h>

namespace {
volatile uint8_t sink;
}

#define KEEP __attribute__((noinline, noclone))

class MyClass {
public:
    KEEP void step() { sink = static_cast<uint8_t>(sink + 1); }
};

KEEP void tick(int v) { sink = static_cast<uint8_t>(v); }
KEEP void tick(long v) { sink = static_cast<uint8_t>(v >> 8); }
KEEP void once() { sink = 7; }
KEEP void twice() { sink = static_cast<uint8_t>(sink ^ 2); }
KEEP void serialEventRun() { sink = static_cast<uint8_t>(sink ^ 1); }

int main() {
    MyClass c;
    once();
    for (;;) {
        c.step();
        tick(3);
        twice();
        tick(4L);
        twice();
        serialEventRun();
    }
}
