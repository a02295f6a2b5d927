// drv8833_nano_mirrored: an Arduino Nano and a DRV8833 drive 50 cm straight,
// then turn 90 degrees left on the spot.
//
// Wiring:
//   DRV8833 module (nSLEEP pulled up on the module):
//     left motor:  AIN1 -> D9, AIN2 -> D10 (Timer1, 490 Hz)
//     right motor: BIN1 -> D5, BIN2 -> D6  (Timer0, 976.6 Hz)
//   The motors face each other, so the right one is mounted mirrored: the
//   drive that turns the left wheel forward turns the right wheel backward.
//   setMotor() below takes the wheel's direction and flips the right side.
//   Single-channel Hall encoders on the motor shafts (8 edges per motor turn,
//   48:1 gear: 384 edges per wheel turn):
//     left OUT -> D2 (INT0)      right OUT -> D3 (INT1)
//   They cannot tell the direction, so each count takes the sign of the
//   direction the wheel was last told to turn.
//
// Speed: PWM on one input, the other low (fast decay: the motor coasts while
// the PWM is low).

const byte LEFT_IN1 = 9;
const byte LEFT_IN2 = 10;
const byte RIGHT_IN1 = 5;
const byte RIGHT_IN2 = 6;
const byte LEFT_ENC = 2;
const byte RIGHT_ENC = 3;

const bool RIGHT_MIRRORED = true;

const long COUNTS_PER_TURN = 384;
const long FORWARD_COUNTS = 960;    // 2.5 turns x 202 mm = 50.6 cm
// 90 degrees on the spot: each wheel rolls pi/2 x 64 mm = 100.5 mm = 191 counts.
// The wheels roll on about 19 counts after the brake, so stop 19 early.
const long TURN_COUNTS = 191 - 19;
const int DRIVE_SPEED = 150;
const int TURN_SPEED = 70;
const int BALANCE = 2;              // PWM steps per count the wheels differ by

volatile long leftTicks = 0;
volatile long rightTicks = 0;
volatile int leftDir = 1;           // +1 forward, -1 backward
volatile int rightDir = 1;

void leftEncoder() {
  leftTicks += leftDir;
}

void rightEncoder() {
  rightTicks += rightDir;
}

long readTicks(volatile long &ticks) {
  noInterrupts();
  long value = ticks;
  interrupts();
  return value;
}

// One motor, speed -255..255 (negative: backward): fast decay.
void driveMotor(byte in1, byte in2, int speed) {
  if (speed >= 0) {
    analogWrite(in1, speed);
    digitalWrite(in2, LOW);
  } else {
    digitalWrite(in1, LOW);
    analogWrite(in2, -speed);
  }
}

// Both inputs high: brake.
void brakeMotor(byte in1, byte in2) {
  digitalWrite(in1, HIGH);
  digitalWrite(in2, HIGH);
}

// speed > 0 turns the wheel forward.
void setLeft(int speed) {
  leftDir = speed >= 0 ? 1 : -1;
  driveMotor(LEFT_IN1, LEFT_IN2, speed);
}

void setRight(int speed) {
  rightDir = speed >= 0 ? 1 : -1;
  driveMotor(RIGHT_IN1, RIGHT_IN2, RIGHT_MIRRORED ? -speed : speed);
}

// Turns the left wheel by leftSign * counts and the right wheel by
// rightSign * counts at the same speed. The wheel that is ahead is slowed
// and the other sped up, so both arrive together; each brakes at its target.
void move(int leftSign, int rightSign, long counts, int speed) {
  long leftStart = readTicks(leftTicks);
  long rightStart = readTicks(rightTicks);
  bool leftDone = false;
  bool rightDone = false;
  while (!leftDone || !rightDone) {
    long left = (readTicks(leftTicks) - leftStart) * leftSign;
    long right = (readTicks(rightTicks) - rightStart) * rightSign;
    int correction = BALANCE * (left - right);
    if (!leftDone && left >= counts) {
      brakeMotor(LEFT_IN1, LEFT_IN2);
      leftDone = true;
    }
    if (!rightDone && right >= counts) {
      brakeMotor(RIGHT_IN1, RIGHT_IN2);
      rightDone = true;
    }
    if (!leftDone) setLeft(leftSign * constrain(speed - correction, 0, 255));
    if (!rightDone) setRight(rightSign * constrain(speed + correction, 0, 255));
  }
}

void printTicks() {
  Serial.print(F("ticks "));
  Serial.print(readTicks(leftTicks));
  Serial.print(' ');
  Serial.println(readTicks(rightTicks));
}

void setup() {
  Serial.begin(9600);
  pinMode(LEFT_IN1, OUTPUT);
  pinMode(LEFT_IN2, OUTPUT);
  pinMode(RIGHT_IN1, OUTPUT);
  pinMode(RIGHT_IN2, OUTPUT);
  brakeMotor(LEFT_IN1, LEFT_IN2);
  brakeMotor(RIGHT_IN1, RIGHT_IN2);

  pinMode(LEFT_ENC, INPUT);
  pinMode(RIGHT_ENC, INPUT);
  attachInterrupt(digitalPinToInterrupt(LEFT_ENC), leftEncoder, CHANGE);
  attachInterrupt(digitalPinToInterrupt(RIGHT_ENC), rightEncoder, CHANGE);

  Serial.println(F("drv8833_nano_mirrored ready"));
  delay(500);

  Serial.println(F("forward"));
  move(1, 1, FORWARD_COUNTS, DRIVE_SPEED);
  delay(500);
  printTicks();

  Serial.println(F("turn left"));
  move(-1, 1, TURN_COUNTS, TURN_SPEED);
  delay(500);
  printTicks();
  Serial.println(F("done"));
}

void loop() {
}
