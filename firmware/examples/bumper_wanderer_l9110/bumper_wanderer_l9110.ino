// bumper_wanderer_l9110: a SunFounder-style kit car wanders a closed arena.
// It drives forward. When one of its two front bumpers closes, it backs off
// for a moment and turns on the spot away from the side that hit (left
// bumper -> turn right, right bumper -> turn left, both -> either way) for a
// varied time, then drives on.
//
// Wiring (Arduino Uno):
//   L9110 (HG7881) two-channel motor driver module, one L9110 per motor
//     A-IA -> D5 (OC0B), A-IB -> D6 (OC0A)    left motor  (Timer0)
//     B-IA -> D9 (OC1A), B-IB -> D10 (OC1B)   right motor (Timer1)
//     each motor wired so that IA high / IB low turns its wheel forward
//   two lever micro-switches (snap action), each from its pin to GND, on the
//   front corners of the chassis:
//     left bumper  -> D7          right bumper -> D8
//   Hall encoders on the motors (not used by this sketch):
//     left OUT -> D2 (INT0)       right OUT -> D3 (INT1)
//   D3 and D11 (Timer2) stay free for other parts.
//
// The driver (../shared/SENSORS.md section 7; the L9110 module sheet and the
// Banana Robotics and SunFounder truth tables; the IC's own datasheet was not
// found): per channel
//     IA IB = H L forward, L H reverse, L L off/brake, H H off/stop,
// and the speed is PWM on one input with the other one low. Forward is PWM on
// IA with IB low; reverse is IA low with PWM on IB. So both inputs of a
// channel are on PWM pins: D5/D6 are Timer0's outputs, D9/D10 Timer1's
// (ATmega328P section 1 Figure 1-1; ../shared/DRIVERS.md section 5). In the
// PWM's off phase both inputs are low, which the vendors' tables call
// off/brake: both outputs to one rail, a shorted winding (derived; whether
// the IC brakes or coasts there is unverified, SENSORS.md section 7).
//
// The Arduino core (../shared/DRIVERS.md section 5, wiring_analog.c and
// wiring.c): analogWrite(pin, v) on Timer0 (D5, D6) is fast PWM at 976.6 Hz,
// duty (v + 1) / 256; on Timer1 (D9, D10) phase-correct PWM at 490.2 Hz, duty
// v / 255. analogWrite(pin, 0) is digitalWrite(pin, LOW), and digitalWrite()
// disconnects the timer from the pin first, so the low input is a true
// constant LOW. analogWrite() leaves Timer0's setup alone: millis() and
// delay() keep working.
//
// The bumpers (../shared/SENSORS.md section 4): a switch to ground on a pin
// with pinMode(pin, INPUT_PULLUP), which sets the PORT bit of an input and so
// turns on its 20-50 kOhm pull-up (ATmega328P 13.2.1, 28.2): released the
// pin reads HIGH, pressed LOW. A mechanical contact bounces for a few
// milliseconds (Omron's tactile switches: 5 ms max; no figure for lever
// switches was read), so a LOW is believed only when a second read
// DEBOUNCE_MS later still finds a bumper closed. The robot keeps pushing
// for those few milliseconds.
//
// The numbers (default plant, docs/plant.md; the L9110's drop taken near the
// L298's 1.4 V: about 1.3-1.5 V at 750 mA, SENSORS.md section 7, unverified):
// full drive gives the motors about 4.7 V and the wheels 210 RPM, 0.71 m/s.
// - CRUISE_SPEED 170: duty 0.667 -> about 0.45 m/s forward.
// - REVERSE_SPEED 150 for BACK_MS 300 ms from standstill at the wall: about
//   0.09 m, and the turn's first ~70 ms add ~0.03 m: the front corners
//   (120 mm from the axle's middle) then clear the wall they hit while the
//   robot turns on the spot.
// - TURN_SPEED 150: each wheel ~0.40 m/s, so the robot turns at
//   2 x 0.40 / 0.128 m = 6.2 rad/s (355 degrees/s); the motors' ~70 ms lag
//   at the start of the turn and their run-on at its end about cancel, so a
//   turn of TURN_MIN_MS + 0..TURN_SPAN_MS - 1 = 200..499 ms turns the robot
//   by roughly 70..180 degrees.
// - The turn's length comes from a 32-bit linear congruential generator
//   (multiplier 1664525, increment 1013904223: Numerical Recipes' "quick and
//   dirty" generator), its high 16 bits only (an LCG's low bits repeat with
//   short periods). It starts from a fixed seed: every run is the same.

// L9110 inputs: IA forward, IB reverse (both on PWM pins)
const byte LEFT_IA = 5;     // A-IA, Timer0
const byte LEFT_IB = 6;     // A-IB, Timer0
const byte RIGHT_IA = 9;    // B-IA, Timer1
const byte RIGHT_IB = 10;   // B-IB, Timer1

// bumpers: switch to GND, LOW while pressed
const byte BUMP_LEFT = 7;
const byte BUMP_RIGHT = 8;

// speeds, analogWrite values 0..255
const int CRUISE_SPEED = 170;
const int REVERSE_SPEED = 150;
const int TURN_SPEED = 150;

// times [ms]
const unsigned long DEBOUNCE_MS = 8;     // longer than a contact's bounce (~5 ms)
const unsigned long BACK_MS = 300;
const unsigned long TURN_MIN_MS = 200;
const unsigned long TURN_SPAN_MS = 300;  // turns last 200..499 ms

uint32_t rngState = 20240607UL;          // fixed seed: a repeatable run

// The next pseudo-random number, 0..65535 (the LCG's high 16 bits).
uint16_t nextRandom() {
  rngState = rngState * 1664525UL + 1013904223UL;
  return (uint16_t)(rngState >> 16);
}

// One L9110 channel: speed -255 (full reverse) .. 255 (full forward).
// The input that is to go low is set first, so the channel never sees
// both inputs high on the way (that would only brake, but needlessly).
void setMotor(byte ia, byte ib, int speed) {
  if (speed >= 0) {
    digitalWrite(ib, LOW);      // also disconnects ib's PWM
    analogWrite(ia, speed);     // 0 gives a plain LOW: both low, off/brake
  } else {
    digitalWrite(ia, LOW);
    analogWrite(ib, -speed);
  }
}

void setMotors(int left, int right) {
  setMotor(LEFT_IA, LEFT_IB, left);
  setMotor(RIGHT_IA, RIGHT_IB, right);
}

void setup() {
  Serial.begin(115200);

  pinMode(LEFT_IA, OUTPUT);
  pinMode(LEFT_IB, OUTPUT);
  pinMode(RIGHT_IA, OUTPUT);
  pinMode(RIGHT_IB, OUTPUT);
  setMotors(0, 0);

  pinMode(BUMP_LEFT, INPUT_PULLUP);
  pinMode(BUMP_RIGHT, INPUT_PULLUP);

  Serial.println(F("bumper_wanderer ready"));
}

void loop() {
  setMotors(CRUISE_SPEED, CRUISE_SPEED);

  bool left = digitalRead(BUMP_LEFT) == LOW;
  bool right = digitalRead(BUMP_RIGHT) == LOW;
  if (!left && !right) return;

  // Debounce: read again once the contact has settled. The second read
  // decides (on a square hit the second switch may close a moment after
  // the first); if neither is closed now, it was a glitch: drive on.
  delay(DEBOUNCE_MS);
  left = digitalRead(BUMP_LEFT) == LOW;
  right = digitalRead(BUMP_RIGHT) == LOW;
  if (!left && !right) return;

  unsigned long at = millis();
  bool turnRight;
  if (left && right) {
    turnRight = (nextRandom() & 0x8000) != 0;    // head-on: either way
  } else {
    turnRight = left;                            // away from the side that hit
  }
  unsigned long turnMs = TURN_MIN_MS + nextRandom() % TURN_SPAN_MS;

  setMotors(-REVERSE_SPEED, -REVERSE_SPEED);     // back off

  if (left && right) {
    Serial.print(F("bump both"));
  } else if (left) {
    Serial.print(F("bump left"));
  } else {
    Serial.print(F("bump right"));
  }
  Serial.print(F(" at "));
  Serial.print(at);
  Serial.print(F(" ms: back "));
  Serial.print(BACK_MS);
  Serial.print(F(" ms, turn "));
  if (turnRight) {
    Serial.print(F("right "));
  } else {
    Serial.print(F("left "));
  }
  Serial.print(turnMs);
  Serial.println(F(" ms"));

  delay(BACK_MS);

  if (turnRight) {
    setMotors(TURN_SPEED, -TURN_SPEED);          // clockwise on the spot
  } else {
    setMotors(-TURN_SPEED, TURN_SPEED);          // counter-clockwise
  }
  delay(turnMs);
  // loop() starts over: forward again
}
