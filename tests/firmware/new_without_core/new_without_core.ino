// A sketch that uses `new` as the PinChangeInt library does, with the core's
// <new.h> included. Debian's Arduino core declares `operator new` weak there,
// so nothing pulls new.cpp's definition from the core's archive and `new`
// links to `call 0`: the firmware restarts at its first `new`, thousands of
// times a second (issue 32). The sketch build reports the call (in watch(),
// naming operator new), and a run ends with exit reason reset_loop.
#include <new.h>

struct PinWatch {
    explicit PinWatch(uint8_t p) : pin(p), next(nullptr) {}
    uint8_t pin;
    PinWatch* next;
};

PinWatch* watches = nullptr;

// Not inlined: the report names this function.
__attribute__((noinline)) void watch(uint8_t pin) {
    PinWatch* w = new PinWatch(pin);
    w->next = watches;
    watches = w;
}

void setup() {
    // Before Serial: a restart without a reset keeps the USART's registers,
    // and one in the middle of a transmission can leave Serial waiting for
    // an interrupt that Serial.begin() switched off (the run then hangs).
    watch(2);
    watch(3);
    Serial.begin(9600);
    Serial.println("watching pins 2 and 3");
}

void loop() {}
