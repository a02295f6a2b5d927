// l298n_inpwm_pcint_quad: hold both wheels at a set speed with a PI loop on
// quadrature encoder counts, drive 5 wheel turns (about 1 m), then brake.
//
// Wiring:
//   L298N module with both ENA/ENB jumpers fitted (enables always high), so
//   the speed is set by PWM on the IN pins:
//     left motor:  IN1 -> D9 (Timer1), IN2 -> D10 (Timer1)
//     right motor: IN3 -> D3 (Timer2), IN4 -> D11 (Timer2)
//   Forward is IN1 = PWM, IN2 = LOW: the bridge drives while the PWM is high
//   and brakes (both outputs low) while it is low.
//   Quadrature encoders on the motor shafts, all four channels on port C's
//   pin-change interrupt (PCINT1):
//     left  A -> A0, B -> A1        right A -> A2, B -> A3
//   Channel A leads B when the wheel turns forward.

const byte LEFT_IN1 = 9;
const byte LEFT_IN2 = 10;
const byte RIGHT_IN1 = 3;
const byte RIGHT_IN2 = 11;

const long COUNTS_PER_TURN = 768;             // 2 channels x 384 edges per wheel turn
const long TARGET_COUNTS = 5 * COUNTS_PER_TURN;   // 5 turns of a 64.4 mm wheel = 1.01 m
const int TARGET_SPEED = 60;                  // counts per 50 ms = 1.56 turns/s = 0.32 m/s
const unsigned long PERIOD_MS = 50;
const float KP = 1.5;                         // PWM per count/period of error
const float KI = 0.5;                         // PWM per count of accumulated error
const unsigned long TIMEOUT_MS = 6000;

// Quadrature decoding: index = previous state * 4 + new state, state = B * 2 + A.
// Forward (A leads B) runs 0 -> 1 -> 3 -> 2 -> 0 and counts +1 per step.
const int8_t QUAD_STEP[16] = {0, 1, -1, 0, -1, 0, 0, 1, 1, 0, 0, -1, 0, -1, 1, 0};

volatile long leftTicks = 0;
volatile long rightTicks = 0;
volatile byte lastEncoderPins = 0;

int leftSpeed = 0;     // counts in the last period
int rightSpeed = 0;
long leftErrorSum = 0;
long rightErrorSum = 0;

// Any change on A0..A3. PINC bits 0..3 are left A, left B, right A, right B.
ISR(PCINT1_vect) {
  byte pins = PINC & 0x0F;
  byte last = lastEncoderPins;
  leftTicks += QUAD_STEP[((last & 0x03) << 2) | (pins & 0x03)];
  rightTicks += QUAD_STEP[(last & 0x0C) | (pins >> 2)];
  lastEncoderPins = pins;
}

long readTicks(volatile long &ticks) {
  noInterrupts();
  long value = ticks;
  interrupts();
  return value;
}

// pwm 0..255, forward; IN2 stays low.
void setLeft(int pwm) {
  analogWrite(LEFT_IN1, pwm);
  digitalWrite(LEFT_IN2, LOW);
}

void setRight(int pwm) {
  analogWrite(RIGHT_IN1, pwm);
  digitalWrite(RIGHT_IN2, LOW);
}

void brakeBoth() {
  digitalWrite(LEFT_IN1, LOW);
  digitalWrite(LEFT_IN2, LOW);
  digitalWrite(RIGHT_IN1, LOW);
  digitalWrite(RIGHT_IN2, LOW);
}

// PI speed control: feed-forward (about 2 PWM steps per count/period) plus
// the proportional and integral terms.
int speedControl(int measured, long &errorSum) {
  int error = TARGET_SPEED - measured;
  errorSum += error;
  float pwm = 2.0 * TARGET_SPEED + KP * error + KI * errorSum;
  return constrain((int)pwm, 0, 255);
}

void setup() {
  Serial.begin(9600);
  pinMode(LEFT_IN1, OUTPUT);
  pinMode(LEFT_IN2, OUTPUT);
  pinMode(RIGHT_IN1, OUTPUT);
  pinMode(RIGHT_IN2, OUTPUT);
  brakeBoth();

  // encoder inputs A0..A3, pin-change interrupts PCINT8..PCINT11
  DDRC &= ~0x0F;
  lastEncoderPins = PINC & 0x0F;
  PCMSK1 |= _BV(PCINT8) | _BV(PCINT9) | _BV(PCINT10) | _BV(PCINT11);
  PCIFR = _BV(PCIF1);     // forget any change before now
  PCICR |= _BV(PCIE1);

  Serial.println(F("l298n_inpwm_pcint_quad ready"));
  delay(500);

  Serial.println(F("go"));
  unsigned long start = millis();
  unsigned long lastControl = start - PERIOD_MS;   // first control step at once
  long lastLeft = 0;
  long lastRight = 0;
  int report = 0;
  while (true) {
    long left = readTicks(leftTicks);
    long right = readTicks(rightTicks);
    if ((left + right) / 2 >= TARGET_COUNTS) break;
    if (millis() - start > TIMEOUT_MS) {
      Serial.println(F("timeout"));
      break;
    }
    if (millis() - lastControl < PERIOD_MS) continue;
    lastControl += PERIOD_MS;

    leftSpeed = left - lastLeft;
    rightSpeed = right - lastRight;
    lastLeft = left;
    lastRight = right;
    setLeft(speedControl(leftSpeed, leftErrorSum));
    setRight(speedControl(rightSpeed, rightErrorSum));
    if (++report == 4) {   // every 200 ms
      report = 0;
      Serial.print(F("speed "));
      Serial.print(leftSpeed);
      Serial.print(' ');
      Serial.println(rightSpeed);
    }
  }
  brakeBoth();
  Serial.print(F("done after "));
  Serial.print(millis() - start);
  Serial.println(F(" ms"));
  delay(500);
  Serial.print(F("ticks "));
  Serial.print(readTicks(leftTicks));
  Serial.print(' ');
  Serial.println(readTicks(rightTicks));
}

void loop() {
}
