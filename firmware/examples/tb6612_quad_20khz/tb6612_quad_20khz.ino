// tb6612_quad_20khz: 20 kHz PWM (no motor whine) from Timer1, quadrature
// encoders read on INT0/INT1, a P speed loop, 5 wheel turns (about 1 m), then
// a short brake and standby.
//
// Wiring (one TB6612FNG module drives both motors):
//   left motor:  PWMA -> D9 (OC1A), AIN1 -> D7,  AIN2 -> D8
//   right motor: PWMB -> D10 (OC1B), BIN1 -> D12, BIN2 -> D13
//   STBY -> D6 (both motors)
//   Quadrature encoders on the motor shafts:
//     left  A -> D2 (INT0), B -> D4       right A -> D3 (INT1), B -> D5
//   A leads B going forward: when A rises, B is still low.
//
// Timer1 mode 14 (fast PWM, TOP = ICR1 = 799) at clk/1: 16 MHz / 800 =
// 20 kHz, duty (OCR1x + 1) / 800. No analogWrite() on D9/D10 after this.

const byte PWMA = 9;
const byte AIN1 = 7;
const byte AIN2 = 8;
const byte PWMB = 10;
const byte BIN1 = 12;
const byte BIN2 = 13;
const byte STBY = 6;
const byte LEFT_A = 2;
const byte LEFT_B = 4;
const byte RIGHT_A = 3;
const byte RIGHT_B = 5;

const int PWM_TOP = 799;                  // ICR1
const long COUNTS_PER_TURN = 192;         // rising edges of A per wheel turn
const long TARGET_COUNTS = 5 * COUNTS_PER_TURN;   // 5 turns of a 64.4 mm wheel = 1.01 m
const int TARGET_SPEED = 30;              // counts per 100 ms = 1.56 turns/s = 0.32 m/s
const unsigned long PERIOD_MS = 100;
const int FEED_FORWARD = 10;              // duty steps per count/period (measured)
const int KP = 4;                         // duty steps per count/period of error
const unsigned long TIMEOUT_MS = 6000;

volatile long leftTicks = 0;
volatile long rightTicks = 0;

volatile int leftSpeed = 0;   // counts in the last period (volatile: kept in RAM for a debugger or the HIL to read)
volatile int rightSpeed = 0;

// A rose: B low means forward.
void leftEncoder() {
  if (digitalRead(LEFT_B) == LOW) leftTicks++;
  else leftTicks--;
}

void rightEncoder() {
  if (digitalRead(RIGHT_B) == LOW) rightTicks++;
  else rightTicks--;
}

long readTicks(volatile long &ticks) {
  noInterrupts();
  long value = ticks;
  interrupts();
  return value;
}

void setupPwm20kHz() {
  pinMode(PWMA, OUTPUT);
  pinMode(PWMB, OUTPUT);
  TCCR1B = 0;                                        // stopped while set up
  TCCR1A = _BV(COM1A1) | _BV(COM1B1) | _BV(WGM11);   // non-inverting on OC1A and OC1B
  ICR1 = PWM_TOP;
  OCR1A = 0;
  OCR1B = 0;
  TCCR1B = _BV(WGM13) | _BV(WGM12) | _BV(CS10);     // mode 14, clk/1
}

void forward() {
  digitalWrite(AIN1, HIGH);
  digitalWrite(AIN2, LOW);
  digitalWrite(BIN1, HIGH);
  digitalWrite(BIN2, LOW);
}

// IN1 = IN2 = HIGH: short brake, whatever the PWM input does.
void shortBrake() {
  digitalWrite(AIN1, HIGH);
  digitalWrite(AIN2, HIGH);
  digitalWrite(BIN1, HIGH);
  digitalWrite(BIN2, HIGH);
}

// P speed control: feed-forward duty for the target, plus KP per count of error.
int speedControl(int measured) {
  int duty = FEED_FORWARD * TARGET_SPEED + KP * (TARGET_SPEED - measured);
  return constrain(duty, 0, PWM_TOP);
}

void setup() {
  Serial.begin(9600);
  pinMode(AIN1, OUTPUT);
  pinMode(AIN2, OUTPUT);
  pinMode(BIN1, OUTPUT);
  pinMode(BIN2, OUTPUT);
  pinMode(STBY, OUTPUT);
  digitalWrite(STBY, LOW);      // outputs off until we start
  setupPwm20kHz();

  pinMode(LEFT_B, INPUT);       // the A pins are inputs from reset
  pinMode(RIGHT_B, INPUT);
  attachInterrupt(digitalPinToInterrupt(LEFT_A), leftEncoder, RISING);
  attachInterrupt(digitalPinToInterrupt(RIGHT_A), rightEncoder, RISING);

  Serial.println(F("tb6612_quad_20khz ready"));
  delay(500);

  Serial.println(F("go"));
  forward();
  digitalWrite(STBY, HIGH);
  unsigned long start = millis();
  unsigned long lastControl = start - PERIOD_MS;   // first control step at once
  long lastLeft = 0;
  long lastRight = 0;
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
    OCR1A = speedControl(leftSpeed);
    OCR1B = speedControl(rightSpeed);
  }
  shortBrake();
  Serial.print(F("braking after "));
  Serial.print(millis() - start);
  Serial.println(F(" ms"));
  delay(1000);
  digitalWrite(STBY, LOW);      // standby: outputs high impedance
  Serial.print(F("standby, ticks "));
  Serial.print(readTicks(leftTicks));
  Serial.print(' ');
  Serial.println(readTicks(rightTicks));
}

void loop() {
}
