// library_odometry: drives 0.5 m straight with two libraries, then brakes
// and reports. WheelOdometry (library.properties, src/ layout) turns the
// encoder counts into millimetres; SoftStart (a legacy flat library) ramps
// the PWM up over 300 ms. Neither ships with Arduino: ddmr-hil finds them in
// a --libraries folder, the scenario's libraries:, the sketch's src/ or
// ~/Arduino/libraries (docs/firmware.md).
//
// L298N: ENA D5, IN1 D7, IN2 D8 (left); ENB D6, IN3 D9, IN4 D11 (right).
// Hall encoders on the motor shafts, one channel each on INT0 (D2, left) and
// INT1 (D3, right), counted on CHANGE: 384 edges per wheel turn (8 per motor
// turn, 48:1 gear), wheels of 64.4 mm.
#include <WheelOdometry.h>
#include <SoftStart.h>

const uint8_t ENA = 5, IN1 = 7, IN2 = 8, ENB = 6, IN3 = 9, IN4 = 11;
volatile uint32_t leftCount = 0, rightCount = 0;
WheelOdometry odometry(384, 64.4);
SoftStart ramp(200, 300);
uint32_t target = 0;
bool driving = true;

void countLeft() { leftCount++; }
void countRight() { rightCount++; }

uint32_t readCount(volatile uint32_t& c) {
    noInterrupts();
    const uint32_t v = c;
    interrupts();
    return v;
}

void setup() {
    Serial.begin(9600);
    const uint8_t outputs[] = {ENA, IN1, IN2, ENB, IN3, IN4};
    for (uint8_t p : outputs) pinMode(p, OUTPUT);
    attachInterrupt(digitalPinToInterrupt(2), countLeft, CHANGE);
    attachInterrupt(digitalPinToInterrupt(3), countRight, CHANGE);
    target = odometry.counts_for_mm(500);
    Serial.print("library_odometry ready: 500 mm = ");
    Serial.print(target);
    Serial.println(" counts");
    digitalWrite(IN1, HIGH);
    digitalWrite(IN2, LOW);
    digitalWrite(IN3, HIGH);
    digitalWrite(IN4, LOW);
    ramp.begin();
}

void loop() {
    if (!driving) return;
    const uint32_t l = readCount(leftCount), r = readCount(rightCount);
    analogWrite(ENA, l < target ? ramp.duty() : 0);
    analogWrite(ENB, r < target ? ramp.duty() : 0);
    if (l >= target && r >= target) {
        digitalWrite(IN1, LOW);  // brake: IN1 = IN2 = LOW with the enables high
        digitalWrite(IN3, LOW);
        analogWrite(ENA, 255);
        analogWrite(ENB, 255);
        driving = false;
        delay(500);
        Serial.print("stopped: left ");
        Serial.print(odometry.distance_mm(readCount(leftCount)));
        Serial.print(" mm, right ");
        Serial.print(odometry.distance_mm(readCount(rightCount)));
        Serial.println(" mm");
    }
}
