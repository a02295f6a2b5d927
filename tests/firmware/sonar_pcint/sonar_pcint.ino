// HC-SR04 with ECHO timed by a pin-change interrupt: ECHO on D8 (PB0,
// PCINT0), its edges stamped with micros() in ISR(PCINT0_vect); TRIG on D7.
// Our own sketch, for the ultrasonic part's tests.
const uint8_t kTrig = 7;
const uint8_t kEcho = 8;

volatile unsigned long rise_us = 0;
volatile unsigned long echo_us = 0;
volatile bool echo_done = false;
volatile unsigned int distance_cm = 0;
volatile uint8_t pings = 0;

ISR(PCINT0_vect) {
    if (PINB & _BV(PB0)) {
        rise_us = micros();
    } else {
        echo_us = micros() - rise_us;
        echo_done = true;
    }
}

void setup() {
    pinMode(kTrig, OUTPUT);
    pinMode(kEcho, INPUT);
    PCMSK0 |= _BV(PCINT0);
    PCIFR = _BV(PCIF0);
    PCICR |= _BV(PCIE0);
}

void loop() {
    echo_done = false;
    digitalWrite(kTrig, HIGH);
    delayMicroseconds(10);
    digitalWrite(kTrig, LOW);
    const unsigned long start = millis();
    while (!echo_done && millis() - start < 50) {
    }
    distance_cm = echo_done ? echo_us / 58 : 0;
    ++pings;
    delay(60);
}
