// line_follower_analog5: a line follower with five analog reflectance sensors
// and a PD controller on the line's position under the array.
//
// Wiring:
//   five QTR-1A style analog sensors in a row across the front, 70 mm ahead
//   of the wheel axle, 10 mm apart; each OUT on an analog input:
//     leftmost A0, A1, middle A2, A3, rightmost A4
//   TB6612FNG motor driver module:
//     PWMA -> D5 (Timer0 PWM), AIN1 -> D7, AIN2 -> D8     left motor
//     PWMB -> D6 (Timer0 PWM), BIN1 -> D9, BIN2 -> D10    right motor
//     STBY -> D4
//   Hall encoders on the motors (not used by this sketch):
//     left OUT -> D2, right OUT -> D3
//
// The sensors: a QTR-A is an IR LED and a phototransistor with a pull-up;
// its output goes toward 0 V over a white surface and toward VIN over black
// (Pololu QTR application note 0J13, 2009 edition, p. 4). analogRead() gives
// 0..1023 for 0..5 V (ATmega328P datasheet 7810D, section 23.7). Sensors
// differ, so the sketch first calibrates: it swings the array across the
// tape on the spot and keeps each sensor's lowest and highest reading, then
// scales every reading to 0 (white) .. 1000 (black). It turns back until the
// middle sensor sees the tape again, and sets off.
//
// The line's position is the mean of the sensor numbers weighted by these
// values, times 1000: 0 = under the leftmost sensor, 2000 = under the middle
// one, 4000 = under the rightmost (the scale Pololu's readLine() uses).
// Readings under 50 are left out as noise; when no sensor reads over 200 the
// line is lost and the position says on which side it was last seen (0 or
// 4000), so the robot turns back toward it.
//
// Steering: a PD controller every 5 ms. error = position - 2000 (negative:
// the line is to the left);
//   turn = KP * error + KD * (error - previous error)
//   left wheel = BASE_SPEED + turn, right wheel = BASE_SPEED - turn
// The TB6612 runs a motor forward with IN1 high, IN2 low and PWM on PWM.

// TB6612FNG pins
const byte PWMA = 5;
const byte AIN1 = 7;
const byte AIN2 = 8;
const byte PWMB = 6;
const byte BIN1 = 9;
const byte BIN2 = 10;
const byte STBY = 4;

// the sensors, left to right
const byte NUM_SENSORS = 5;
const byte SENSOR_PINS[NUM_SENSORS] = {A0, A1, A2, A3, A4};
const byte MIDDLE = 2;

// controller
const int BASE_SPEED = 200;         // analogWrite value on a straight line
const int MAX_SPEED = 255;
const float KP = 0.10;              // PWM steps per unit of position error
const float KD = 1.5;               // PWM steps per unit of error change in one period
const unsigned long PERIOD_MS = 5;
const int CALIBRATE_SPEED = 70;     // turning on the spot while calibrating

// calibration: the lowest and highest reading of each sensor
int sensorMin[NUM_SENSORS];
int sensorMax[NUM_SENSORS];
int sensorValue[NUM_SENSORS];       // the last reading, 0 (white) .. 1000 (black)
long lastPosition = 2000;

// left and right motor: -255 (full reverse) .. 255 (full forward)
void setMotor(byte pwmPin, byte in1, byte in2, int speed) {
  if (speed >= 0) {
    digitalWrite(in1, HIGH);
    digitalWrite(in2, LOW);
  } else {
    digitalWrite(in1, LOW);
    digitalWrite(in2, HIGH);
    speed = -speed;
  }
  if (speed > 255) {
    speed = 255;
  }
  analogWrite(pwmPin, speed);
}

void setMotors(int left, int right) {
  setMotor(PWMA, AIN1, AIN2, left);
  setMotor(PWMB, BIN1, BIN2, right);
}

// Reads every sensor and widens its calibration range.
void calibrateOnce() {
  for (byte i = 0; i < NUM_SENSORS; i++) {
    int raw = analogRead(SENSOR_PINS[i]);
    if (raw < sensorMin[i]) {
      sensorMin[i] = raw;
    }
    if (raw > sensorMax[i]) {
      sensorMax[i] = raw;
    }
  }
}

// Turns on the spot for a while, calibrating all the time.
void spinAndCalibrate(int speed, unsigned long ms) {
  setMotors(-speed, speed);         // positive: turn left
  unsigned long start = millis();
  while (millis() - start < ms) {
    calibrateOnce();
  }
}

// Swings the array across the tape, left, then right, calibrating; then
// turns back left until the middle sensor is over the tape again.
void calibrate() {
  for (byte i = 0; i < NUM_SENSORS; i++) {
    sensorMin[i] = 1023;
    sensorMax[i] = 0;
  }
  spinAndCalibrate(CALIBRATE_SPEED, 180);
  spinAndCalibrate(-CALIBRATE_SPEED, 360);
  setMotors(-CALIBRATE_SPEED, CALIBRATE_SPEED);
  unsigned long start = millis();
  do {
    readCalibrated();
  } while (sensorValue[MIDDLE] < 500 && millis() - start < 1000);
  setMotors(0, 0);
}

// Reads the sensors into sensorValue[], scaled 0 (white) .. 1000 (black).
void readCalibrated() {
  for (byte i = 0; i < NUM_SENSORS; i++) {
    long raw = analogRead(SENSOR_PINS[i]);
    long range = sensorMax[i] - sensorMin[i];
    long value = 0;
    if (range > 0) {
      value = (raw - sensorMin[i]) * 1000 / range;
    }
    if (value < 0) {
      value = 0;
    }
    if (value > 1000) {
      value = 1000;
    }
    sensorValue[i] = value;
  }
}

// The line's position, 0 (under the leftmost sensor) .. 4000 (rightmost).
long readLine() {
  readCalibrated();
  bool onLine = false;
  long weightedSum = 0;
  long sum = 0;
  for (byte i = 0; i < NUM_SENSORS; i++) {
    int value = sensorValue[i];
    if (value > 200) {
      onLine = true;
    }
    if (value > 50) {
      weightedSum += (long)value * 1000 * i;
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

  pinMode(PWMA, OUTPUT);
  pinMode(AIN1, OUTPUT);
  pinMode(AIN2, OUTPUT);
  pinMode(PWMB, OUTPUT);
  pinMode(BIN1, OUTPUT);
  pinMode(BIN2, OUTPUT);
  pinMode(STBY, OUTPUT);
  digitalWrite(STBY, HIGH);
  setMotors(0, 0);

  delay(500);               // time to put the robot down on the line
  calibrate();
  for (byte i = 0; i < NUM_SENSORS; i++) {
    Serial.print(sensorMin[i]);
    Serial.print('-');
    Serial.print(sensorMax[i]);
    Serial.print(' ');
  }
  Serial.println();
  Serial.println(F("line_follower_analog5 go"));
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
  long error = position - 2000;
  float turn = KP * error + KD * (error - lastError);
  lastError = error;

  int left = BASE_SPEED + (int)turn;
  int right = BASE_SPEED - (int)turn;
  left = constrain(left, -MAX_SPEED, MAX_SPEED);
  right = constrain(right, -MAX_SPEED, MAX_SPEED);
  setMotors(left, right);
}
