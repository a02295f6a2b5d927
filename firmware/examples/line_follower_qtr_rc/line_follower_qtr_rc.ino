// line_follower_qtr_rc: a line follower with a three-sensor QTR-RC style
// reflectance array, read the RC way, and a PD controller.
//
// Wiring:
//   QTR-3RC style array, 75 mm ahead of the wheel axle, sensors 9.525 mm
//   (0.375") apart across the robot:
//     left OUT -> D4      middle OUT -> D7      right OUT -> D8
//   DRV8833 motor driver module (nSLEEP pulled up on the module):
//     AIN1 -> D5, AIN2 -> D6   left motor  (Timer0 PWM, 976.6 Hz)
//     BIN1 -> D9, BIN2 -> D10  right motor (Timer1 PWM, 490 Hz)
//   Hall encoders on the motors (not used by this sketch):
//     left OUT -> D2, right OUT -> D3
//
// The sensors: each QTR-RC sensor is a phototransistor that discharges a
// small capacitor. To read it (Pololu QTR application note 0J13, section 2):
//   1. drive the line HIGH to charge the capacitor, for at least 10 us;
//   2. make the pin an input (pinMode INPUT also turns the pull-up off);
//   3. time how long the pin stays HIGH.
// More reflected light discharges it faster: a short time means white, a
// long one black. The note (2009 edition, p. 3) measured 780 us over white
// and 10 ms over black with a QTR-1RC 3/8" above the floor; we stop waiting
// at 2500 us (the timeout Pololu uses by default) and count anything slower
// as black. micros() counts in steps of 4 us.
//
// Each time is scaled to 0 (white, WHITE_US or faster) .. 1000 (black, the
// timeout). WHITE_US is what this robot's sensors read over the white floor:
// the sketch prints one reading of all three in setup(); reset it with the
// array over plain floor and set WHITE_US a little above what it prints.
//
// The line's position is the mean of the sensor numbers weighted by these
// values, times 1000: 0 = under the left sensor, 1000 = under the middle
// one, 2000 = under the right one. When no sensor reads over 200 the line is
// lost and the position is 0 or 2000, the side where it was last seen.
//
// Steering: a PD controller every 5 ms. error = position - 1000 (negative:
// the line is to the left);
//   turn = KP * error + KD * (error - previous error)
//   left wheel = BASE_SPEED + turn, right wheel = BASE_SPEED - turn
// Three sensors give a coarse position that changes in steps; a much larger
// KD turns each step into a kick from full forward to reverse, and the
// wheels chatter and the robot slows down.
// The DRV8833 drives forward with PWM on IN1 and IN2 low (it coasts in the
// PWM's off time), backward with IN1 low and PWM on IN2.

// DRV8833 pins
const byte LEFT_IN1 = 5;
const byte LEFT_IN2 = 6;
const byte RIGHT_IN1 = 9;
const byte RIGHT_IN2 = 10;

// the sensors, left to right
const byte NUM_SENSORS = 3;
const byte SENSOR_PINS[NUM_SENSORS] = {4, 7, 8};
const unsigned int TIMEOUT_US = 2500;   // no fall by then: black
const unsigned int WHITE_US = 800;      // a reading over the white floor

// controller
const int BASE_SPEED = 200;             // analogWrite value on a straight line
const float KP = 0.20;                  // PWM steps per unit of position error
const float KD = 1.0;                   // PWM steps per unit of error change in one period
const unsigned long PERIOD_MS = 5;

unsigned int sensorTime[NUM_SENSORS];   // the last decay times [us]
int sensorValue[NUM_SENSORS];           // the same, 0 (white) .. 1000 (black)
long lastPosition = 1000;

// One motor: -255 (full reverse) .. 255 (full forward).
void setMotor(byte in1, byte in2, int speed) {
  speed = constrain(speed, -255, 255);
  if (speed >= 0) {
    digitalWrite(in2, LOW);
    analogWrite(in1, speed);
  } else {
    digitalWrite(in1, LOW);
    analogWrite(in2, -speed);
  }
}

void setMotors(int left, int right) {
  setMotor(LEFT_IN1, LEFT_IN2, left);
  setMotor(RIGHT_IN1, RIGHT_IN2, right);
}

// Reads all sensors at once the RC way into sensorTime[].
void readSensorsRC() {
  for (byte i = 0; i < NUM_SENSORS; i++) {
    sensorTime[i] = TIMEOUT_US;
    pinMode(SENSOR_PINS[i], OUTPUT);
    digitalWrite(SENSOR_PINS[i], HIGH);   // charge the capacitor
  }
  delayMicroseconds(10);

  for (byte i = 0; i < NUM_SENSORS; i++) {
    pinMode(SENSOR_PINS[i], INPUT);       // let it discharge, pull-up off
  }
  unsigned long start = micros();
  byte done = 0;
  while (done < NUM_SENSORS) {
    unsigned long elapsed = micros() - start;
    if (elapsed >= TIMEOUT_US) {
      break;                              // the rest stay at TIMEOUT_US
    }
    for (byte i = 0; i < NUM_SENSORS; i++) {
      if (sensorTime[i] == TIMEOUT_US && digitalRead(SENSOR_PINS[i]) == LOW) {
        sensorTime[i] = elapsed;
        done++;
      }
    }
  }
}

// The line's position, 0 (under the left sensor) .. 2000 (right sensor).
long readLine() {
  readSensorsRC();
  bool onLine = false;
  long weightedSum = 0;
  long sum = 0;
  for (byte i = 0; i < NUM_SENSORS; i++) {
    long value = ((long)sensorTime[i] - WHITE_US) * 1000 / (TIMEOUT_US - WHITE_US);
    value = constrain(value, 0, 1000);
    sensorValue[i] = value;
    if (value > 200) {
      onLine = true;
    }
    if (value > 50) {
      weightedSum += value * 1000 * i;
      sum += value;
    }
  }
  if (!onLine) {
    // lost: say it is past the sensor on the side where it was last seen
    if (lastPosition < (NUM_SENSORS - 1) * 1000 / 2) {
      return 0;
    }
    return (NUM_SENSORS - 1) * 1000;
  }
  lastPosition = weightedSum / sum;
  return lastPosition;
}

void setup() {
  Serial.begin(9600);

  pinMode(LEFT_IN1, OUTPUT);
  pinMode(LEFT_IN2, OUTPUT);
  pinMode(RIGHT_IN1, OUTPUT);
  pinMode(RIGHT_IN2, OUTPUT);
  setMotors(0, 0);

  // one reading, to see what the sensors give here
  readSensorsRC();
  Serial.print(F("decay us:"));
  for (byte i = 0; i < NUM_SENSORS; i++) {
    Serial.print(' ');
    Serial.print(sensorTime[i]);
  }
  Serial.println();

  delay(500);               // time to put the robot down on the line
  Serial.println(F("line_follower_qtr_rc go"));
}

void loop() {
  static unsigned long lastTime = 0;
  static long lastError = 0;

  unsigned long now = millis();
  if (now - lastTime < PERIOD_MS) {
    return;
  }
  lastTime = now;

  long position = readLine();
  long error = position - 1000;
  float turn = KP * error + KD * (error - lastError);
  lastError = error;

  setMotors(BASE_SPEED + (int)turn, BASE_SPEED - (int)turn);
}
