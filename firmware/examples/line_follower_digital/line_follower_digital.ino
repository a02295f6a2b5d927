// line_follower_digital: a kit robot car follows a black tape line with two
// digital IR sensor modules, one either side of the tape.
//
// Wiring:
//   L298N module, ENA/ENB jumpers removed
//     ENA -> D5  left motor speed     IN1 -> D7, IN2 -> D8   left motor
//     ENB -> D6  right motor speed    IN3 -> D9, IN4 -> D11  right motor
//   two TCRT5000 line-tracking modules (LM393 comparator, digital output S),
//   70 mm ahead of the wheel axle, 12 mm either side of the robot's middle:
//     left  S -> D10              right S -> D12
//   the tape is 19 mm wide, so with the robot on the line both sensors see
//   white floor on either side of it
//   Hall encoders on the motors (not used by this sketch):
//     left OUT -> D2               right OUT -> D3
//
// The sensors: an LM393 compares the TCRT5000's phototransistor voltage with
// the module's potentiometer. Black tape sends little infrared back, the
// voltage rises and S goes HIGH; over white S is LOW ("S: normally low, high
// when a black line is detected": SunFounder 3in1-kit, Line Track module;
// Keyestudio KS0453 likewise). The TCRT5000 itself reads best 2.5 mm above
// the floor (Vishay TCRT5000 datasheet, doc. 83760).
//
// Steering (bang-bang): both sensors on white -> drive straight. The left
// sensor on black means the line has moved to the left under the robot:
// turn left hard (right wheel full forward, left wheel backwards) until the
// sensor is off the tape again. The same for the right. Both on black (a
// cross line) -> straight on. Only stopping the inner wheel turns too slowly
// for the 0.3 m bends at this speed: the line slips past the outer sensor
// and is lost.
//
// D5 and D6 are Timer0's PWM pins; analogWrite() leaves Timer0's setup alone,
// so millis() and delay() keep working.

// L298N pins
const byte ENA = 5;
const byte IN1 = 7;
const byte IN2 = 8;
const byte ENB = 6;
const byte IN3 = 9;
const byte IN4 = 11;

// line sensors: HIGH over black
const byte LEFT_IR = 10;
const byte RIGHT_IR = 12;

// speeds, analogWrite values 0..255
const int STRAIGHT_SPEED = 255;   // both wheels while the line is between the sensors
const int OUTER_SPEED = 255;      // the outer wheel while turning
const int INNER_SPEED = -150;     // the inner wheel while turning: backwards

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

void setup() {
  Serial.begin(9600);

  pinMode(ENA, OUTPUT);
  pinMode(IN1, OUTPUT);
  pinMode(IN2, OUTPUT);
  pinMode(ENB, OUTPUT);
  pinMode(IN3, OUTPUT);
  pinMode(IN4, OUTPUT);
  setMotors(0, 0);

  pinMode(LEFT_IR, INPUT);
  pinMode(RIGHT_IR, INPUT);

  Serial.println(F("line_follower_digital ready"));
  delay(500);               // time to put the robot down on the line
}

void loop() {
  bool leftOnLine = digitalRead(LEFT_IR) == HIGH;
  bool rightOnLine = digitalRead(RIGHT_IR) == HIGH;

  if (leftOnLine && !rightOnLine) {
    setMotors(INNER_SPEED, OUTER_SPEED);      // line to the left: turn left
  } else if (rightOnLine && !leftOnLine) {
    setMotors(OUTER_SPEED, INNER_SPEED);      // line to the right: turn right
  } else {
    setMotors(STRAIGHT_SPEED, STRAIGHT_SPEED);
  }
}
