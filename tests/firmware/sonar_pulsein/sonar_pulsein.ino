// HC-SR04 read with pulseIn(), as most kit obstacle avoiders do: a 10 us
// trigger, then pulseIn() counts ECHO's high time in 16-cycle loops
// (arduino-core-avr wiring_pulse.c). TRIG on D7, ECHO on D8. Our own sketch,
// for the ultrasonic part's tests (tests/hil/parts/ultrasonic_hcsr04_test.cpp).
const uint8_t kTrig = 7;
const uint8_t kEcho = 8;

volatile unsigned long echo_us = 0;
volatile unsigned int distance_cm = 0;
volatile uint8_t pings = 0;

void setup() {
    pinMode(kTrig, OUTPUT);
    pinMode(kEcho, INPUT);
}

void loop() {
    digitalWrite(kTrig, LOW);
    delayMicroseconds(2);
    digitalWrite(kTrig, HIGH);
    delayMicroseconds(10);
    digitalWrite(kTrig, LOW);
    const unsigned long us = pulseIn(kEcho, HIGH, 30000UL);  // 0 when no echo within 30 ms
    echo_us = us;
    distance_cm = us / 58;  // the datasheet's "uS / 58 = centimeters"
    ++pings;
    delay(60);  // the datasheet's "over 60 ms measurement cycle"
}
