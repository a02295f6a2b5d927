// obstacle_avoider_servo: a kit robot car drives straight on until its
// ultrasonic ranger sees a wall ahead, stops, looks right and left with the
// ranger on a pan servo, and turns on the spot toward the side with more room.
//
// Wiring:
//   L298N module, ENA/ENB jumpers removed
//     ENA -> D5  left motor speed     IN1 -> D7, IN2 -> D8   left motor
//     ENB -> D6  right motor speed    IN3 -> D4, IN4 -> D12  right motor
//   SG90 pan servo, signal (orange) -> D9, on the front of the chassis,
//     70 mm ahead of the wheel axle; 90 degrees looks straight ahead,
//     0 degrees to the robot's right, 180 to its left
//   HC-SR04 ultrasonic ranger on the servo's horn
//     TRIG -> A1 (D15)                ECHO -> A0 (D14)
//   Hall encoders on the motors (not used by this sketch):
//     left OUT -> D2 (INT0)           right OUT -> D3 (INT1)
//
// Timers: D5 and D6 are Timer0's PWM pins. analogWrite() there only sets
// Timer0's compare registers, so millis() and delay() keep working. Timer1 is
// taken by the servo pulses (below), so no motor pin uses Timer1's outputs
// (D9, D10) for PWM; D9 is only a plain output the interrupt raises and lowers.
//
// The servo pulses, made the way the Arduino Servo library makes them on an
// Uno (arduino-libraries/Servo: src/Servo.h, src/avr/Servo.cpp,
// src/avr/ServoTimers.h; the library is not in Debian, so this sketch does it
// itself, written from that description):
//   - Timer1 in normal mode (TCCR1A = 0) at clock/8 (TCCR1B = CS11): it counts
//     0.5 us ticks, 2 per microsecond, and wraps at 65536 (32.8 ms);
//   - the compare-match A interrupt starts a frame: TCNT1 = 0, the servo pin
//     HIGH, OCR1A = TCNT1 + the pulse's ticks;
//   - at that match it lowers the pin and sets OCR1A = 40000 ticks: the next
//     frame starts 20 ms after this one did (the library's REFRESH_INTERVAL);
//   - the width is the library's: map(angle, 0, 180, 544, 2400) us
//     (MIN_PULSE_WIDTH, MAX_PULSE_WIDTH), so 90 degrees is 1472 us. The pin
//     falls a few microseconds after the match (the interrupt's entry and
//     digitalWrite()); that is under the SG90's 10 us dead band.
//   An SG90 turns 60 degrees in 0.1 s at 4.8 V (TowerPro SG90 sheet): the
//   140 degrees from right to left take 0.23 s. The sketch waits 400 ms after
//   each move before it pings, as kit sketches do with delay().
//
// The ranger (ElecFreaks HC-SR04 datasheet, pp. 1-2): a HIGH of at least
// 10 us on TRIG starts a measurement; ECHO then goes HIGH for the sound's
// round trip, "uS / 58 = centimeters". With nothing in its 4 m range a common
// module holds ECHO high for about 38 ms (seller sheets; the datasheet says
// nothing). The sketch reads ECHO with pulseIn(ECHO, HIGH, 30000), the way
// most kit sketches do: 0 means no echo within 30 ms, and that counts as far.
// The datasheet asks for "over 60 ms measurement cycle", so the sketch waits
// 60 ms after each ping.
//
// Behaviour:
//   - drive forward at analogWrite(160) ((160 + 1)/256 = 0.63 duty), pinging
//     every 60 ms;
//   - a wall nearer than 30 cm ahead (a reading of 1..29 cm): brake (the
//     L298's "fast motor stop": IN1 = IN2, enable high), print "stop <cm>",
//     look right (20 degrees), ping, look left (160 degrees), ping, look ahead
//     again, print "right <cm> left <cm>";
//   - print "turn left" or "turn right" (toward the longer reading; no echo
//     counts as far; a tie turns left) and turn on the spot in steps of
//     200 ms, braking and pinging after each, until the way ahead reads
//     at least 60 cm (or no echo); then print "forward" and drive on.
//   The 60 cm needed to leave the turn is twice the 30 cm that stops the
//   robot, so it does not stop again at once on the same wall.

// L298N pins
const byte ENA = 5;
const byte IN1 = 7;
const byte IN2 = 8;
const byte ENB = 6;
const byte IN3 = 4;
const byte IN4 = 12;

// pan servo and ranger
const byte SERVO_PIN = 9;
const byte TRIG = A1;
const byte ECHO = A0;

// Servo pulse timing (Arduino Servo library values, see above)
const unsigned int SERVO_MIN_US = 544;       // 0 degrees
const unsigned int SERVO_MAX_US = 2400;      // 180 degrees
const unsigned int SERVO_FRAME_TICKS = 40000;  // 20 ms in 0.5 us ticks

// Where the ranger looks, servo degrees
const int LOOK_AHEAD_DEG = 90;
const int LOOK_RIGHT_DEG = 20;
const int LOOK_LEFT_DEG = 160;
const unsigned long LOOK_SETTLE_MS = 400;    // a 140 degree swing takes 0.23 s

// Ranging
const unsigned long ECHO_TIMEOUT_US = 30000; // pulseIn's limit: 0 after it
const unsigned int US_PER_CM = 58;           // HC-SR04 datasheet
const unsigned int NO_ECHO_CM = 500;         // what "no echo" counts as: beyond the 4 m range
const unsigned long PING_INTERVAL_MS = 60;   // datasheet: over 60 ms a measurement

// Behaviour
const unsigned int STOP_CM = 30;             // a wall nearer than this ahead: stop and look
const unsigned int CLEAR_CM = 60;            // the way ahead is clear again
const int CRUISE_SPEED = 160;                // analogWrite value, 0..255
const int TURN_SPEED = 160;
const unsigned long TURN_STEP_MS = 200;      // one step of the turn on the spot
const unsigned long BRAKE_MS = 100;          // the wheels stop within this after a brake
const byte MAX_TURN_STEPS = 10;              // then drive on anyway

// The servo's pulse width in 0.5 us ticks; written by the main program,
// read by the interrupt (16 bits: written with interrupts off).
volatile unsigned int servoTicks = 2 * 1472;
volatile bool servoPulseHigh = false;

// Timer1 compare match A: alternately starts a frame with the pulse's rising
// edge and ends the pulse.
ISR(TIMER1_COMPA_vect) {
  if (servoPulseHigh) {
    digitalWrite(SERVO_PIN, LOW);    // the pulse ends
    servoPulseHigh = false;
    OCR1A = SERVO_FRAME_TICKS;       // the next frame, 20 ms after this one began
  } else {
    TCNT1 = 0;                       // a new frame
    digitalWrite(SERVO_PIN, HIGH);   // the pulse starts
    servoPulseHigh = true;
    OCR1A = TCNT1 + servoTicks;      // and ends this many ticks later
  }
}

void servoWrite(int degrees) {
  degrees = constrain(degrees, 0, 180);
  unsigned int us = map(degrees, 0, 180, SERVO_MIN_US, SERVO_MAX_US);
  noInterrupts();
  servoTicks = 2 * us;               // 0.5 us a tick
  interrupts();
}

void servoBegin() {
  pinMode(SERVO_PIN, OUTPUT);
  digitalWrite(SERVO_PIN, LOW);
  servoWrite(LOOK_AHEAD_DEG);
  noInterrupts();
  TCCR1A = 0;                        // normal mode, OC1A/OC1B disconnected
  TCCR1B = _BV(CS11);                // clock/8: 0.5 us a tick
  TCNT1 = 0;
  OCR1A = SERVO_FRAME_TICKS;         // the first pulse 20 ms from now
  TIFR1 = _BV(OCF1A);                // drop a match left from the core's setup
  TIMSK1 |= _BV(OCIE1A);
  interrupts();
}

// One measurement: the distance in cm, 0 when no echo came back in time.
unsigned int pingCm() {
  digitalWrite(TRIG, LOW);
  delayMicroseconds(2);
  digitalWrite(TRIG, HIGH);
  delayMicroseconds(10);
  digitalWrite(TRIG, LOW);
  unsigned long echoUs = pulseIn(ECHO, HIGH, ECHO_TIMEOUT_US);
  return echoUs / US_PER_CM;
}

// A reading as a range to compare: no echo is far.
unsigned int rangeOf(unsigned int cm) {
  return cm == 0 ? NO_ECHO_CM : cm;
}

// left and right motor: -255 (full reverse) .. 255 (full forward)
void setMotors(int left, int right) {
  if (left >= 0) {
    digitalWrite(IN1, HIGH);
    digitalWrite(IN2, LOW);
  } else {
    digitalWrite(IN1, LOW);
    digitalWrite(IN2, HIGH);
    left = -left;
  }
  if (right >= 0) {
    digitalWrite(IN3, HIGH);
    digitalWrite(IN4, LOW);
  } else {
    digitalWrite(IN3, LOW);
    digitalWrite(IN4, HIGH);
    right = -right;
  }
  analogWrite(ENA, left);
  analogWrite(ENB, right);
}

// Brake: both inputs low with the enable high short each motor through the
// L298's lower transistors ("fast motor stop", ST L298 datasheet, Figure 6),
// so the wheels stop within a few centimetres instead of coasting on.
void brake() {
  digitalWrite(IN1, LOW);
  digitalWrite(IN2, LOW);
  digitalWrite(IN3, LOW);
  digitalWrite(IN4, LOW);
  analogWrite(ENA, 255);
  analogWrite(ENB, 255);
}

// Points the ranger, waits for the servo to get there, and pings.
unsigned int lookCm(int degrees) {
  servoWrite(degrees);
  delay(LOOK_SETTLE_MS);
  return pingCm();
}

// A wall ahead: stop, look both ways, turn toward the side with more room.
void avoid(unsigned int aheadCm) {
  brake();
  Serial.print(F("stop "));
  Serial.println(aheadCm);

  unsigned int rightCm = lookCm(LOOK_RIGHT_DEG);
  unsigned int leftCm = lookCm(LOOK_LEFT_DEG);
  servoWrite(LOOK_AHEAD_DEG);
  Serial.print(F("right "));
  Serial.print(rightCm);
  Serial.print(F(" left "));
  Serial.println(leftCm);
  delay(LOOK_SETTLE_MS);             // looking ahead again before the turn

  bool turnLeft = rangeOf(leftCm) >= rangeOf(rightCm);
  Serial.println(turnLeft ? F("turn left") : F("turn right"));
  for (byte step = 0; step < MAX_TURN_STEPS; step++) {
    if (turnLeft) {
      setMotors(-TURN_SPEED, TURN_SPEED);
    } else {
      setMotors(TURN_SPEED, -TURN_SPEED);
    }
    delay(TURN_STEP_MS);
    brake();
    delay(BRAKE_MS);
    if (rangeOf(pingCm()) >= CLEAR_CM) break;
  }
  Serial.println(F("forward"));
}

void setup() {
  Serial.begin(115200);

  pinMode(ENA, OUTPUT);
  pinMode(IN1, OUTPUT);
  pinMode(IN2, OUTPUT);
  pinMode(ENB, OUTPUT);
  pinMode(IN3, OUTPUT);
  pinMode(IN4, OUTPUT);
  setMotors(0, 0);

  pinMode(TRIG, OUTPUT);
  digitalWrite(TRIG, LOW);
  pinMode(ECHO, INPUT);

  servoBegin();
  delay(500);                        // the servo centres, the robot is put down

  Serial.println(F("obstacle_avoider_servo ready"));
}

void loop() {
  unsigned int aheadCm = pingCm();
  if (rangeOf(aheadCm) < STOP_CM) {
    avoid(aheadCm);
  } else {
    setMotors(CRUISE_SPEED, CRUISE_SPEED);
  }
  delay(PING_INTERVAL_MS);
}
