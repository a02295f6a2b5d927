// HC-SR04 with ECHO polled from a timer interrupt, the way NewPing's
// ping_timer() does it: Timer2 in CTC mode at /64 with OCR2A = 5, a compare
// interrupt every 24 us that looks at ECHO (D8) and stamps its edges with
// micros(). TRIG on D7. Taking Timer2 ends PWM on D3 and D11. Our own
// sketch, for the ultrasonic part's tests.
const uint8_t kTrig = 7;
const uint8_t kEcho = 8;

volatile bool waiting = false;
volatile bool started = false;
volatile unsigned long rise_us = 0;
volatile unsigned long echo_us = 0;
volatile bool echo_done = false;
volatile unsigned int distance_cm = 0;
volatile uint8_t pings = 0;

ISR(TIMER2_COMPA_vect) {
    if (!waiting) return;
    const bool high = (PINB & _BV(PB0)) != 0;
    if (!started && high) {
        started = true;
        rise_us = micros();
    } else if (started && !high) {
        echo_us = micros() - rise_us;
        waiting = false;
        echo_done = true;
    }
}

void setup() {
    pinMode(kTrig, OUTPUT);
    pinMode(kEcho, INPUT);
    TCCR2A = _BV(WGM21);  // CTC, TOP = OCR2A
    TCCR2B = _BV(CS22);   // /64: 4 us a count
    OCR2A = 5;            // (5 + 1) x 4 us = 24 us
    TIMSK2 = _BV(OCIE2A);
}

void loop() {
    echo_done = false;
    started = false;
    digitalWrite(kTrig, HIGH);
    delayMicroseconds(10);
    digitalWrite(kTrig, LOW);
    waiting = true;
    const unsigned long start = millis();
    while (!echo_done && millis() - start < 50) {
    }
    waiting = false;
    distance_cm = echo_done ? echo_us / 58 : 0;
    ++pings;
    delay(60);
}
