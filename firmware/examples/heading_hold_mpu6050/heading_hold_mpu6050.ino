// heading_hold_mpu6050: a kit robot car holds its heading with the Z gyro of
// an MPU-6050 (GY-521 board), turning on the spot to undo any turn it is
// given. No MPU-6050 library: the registers are read and written with the
// Arduino core's Wire library, as many sketches do.
//
// Wiring:
//   L298N module, ENA/ENB jumpers removed
//     ENA -> D5  left motor speed     IN1 -> D7, IN2 -> D8   left motor
//     ENB -> D6  right motor speed    IN3 -> D9, IN4 -> D11  right motor
//   GY-521 (MPU-6050) on the I2C bus, VCC 5 V (the board's regulator), GND
//     SDA -> A4    SCL -> A5    AD0 -> GND (address 0x68)    INT not used
//   mounted flat, component side up, its X axis pointing forward: a turn to
//   the left (counter-clockwise seen from above) reads as positive GYRO_Z
//   Hall encoders on the motors (not used by this sketch):
//     left OUT -> D2               right OUT -> D3
//
// The MPU-6050 (InvenSense register map RM-MPU-6000A-00 rev. 4.2 [RM],
// product specification PS-MPU-6000A-00 rev. 3.4 [PS]):
//   address      0x68 with AD0 low, 0x69 high ([PS] 6.4, 9.2)
//   0x6B PWR_MGMT_1   resets to 0x40: asleep. 0x01 wakes it (SLEEP = 0) and
//                     clocks it from the X gyro's PLL (CLKSEL = 1), which
//                     the datasheet recommends over the 8 MHz RC ([RM] 4.28)
//   0x75 WHO_AM_I     reads 0x68 whatever AD0 is ([RM] 4.32)
//   0x1B GYRO_CONFIG  FS_SEL = 0: +-250 deg/s, 131 LSB per deg/s ([RM] 4.4, 4.19)
//   0x1A CONFIG       DLPF_CFG = 3: gyro low-pass 42 Hz, 4.8 ms delay, and
//                     a gyro output rate of 1 kHz ([RM] 4.3)
//   0x19 SMPLRT_DIV   0: sample rate = 1 kHz / (1 + 0) = 1 kHz ([RM] 4.2),
//                     so each 5 ms read gets a sample at most 1 ms old
//   0x47/0x48 GYRO_ZOUT_H/L  16-bit two's complement, high byte first ([RM] 4.19)
//   A read is: START, 0x68+W, the register's address, repeated START,
//   0x68+R, the bytes, STOP ([PS] 9.3): Wire.endTransmission(false) keeps
//   the bus for Wire.requestFrom(), which then reads with a repeated START.
//   Its zero-rate output (bias) may be up to +-20 deg/s ([PS] 6.1): the
//   sketch measures it at rest and subtracts it. It settles within 30 ms of
//   power-on ([PS] 6.1); the sketch waits 100 ms before measuring.
//
// Heading: heading += (GYRO_ZOUT - bias) / 131 * dt every 5 ms, dt from
// micros(). Nothing corrects the integral (no compass, no accelerometer
// helps with yaw): an error in the bias turns into a steadily growing
// heading error. 200 reads average the bias to about 0.01 deg/s (the
// gyro's 0.05 deg/s RMS noise, [PS] 6.1, over ~50 independent samples:
// the 42 Hz filter makes neighbouring 2 ms samples alike): 0.6 degrees a
// minute, a few hundredths of a degree over a run of seconds. The noise
// itself integrates to 0.05 x sqrt(0.005 s x t): 0.01 degrees after 4 s.
//
// Control, every 5 ms (the heading to hold is 0, the heading at the end of
// the calibration):
//   error = 0 - heading                       [deg], positive: turn left
//   u     = KP * error - KD * rate            rate: the gyro's [deg/s]
//   |error| < DEAD_BAND_DEG: brake both motors (EN high, IN1 = IN2 = LOW,
//                             the L298's "fast motor stop")
//   else: turn on the spot, left if u > 0, the two wheels in opposite
//         directions at PWM = MIN_PWM + |u|, at most MAX_PWM.
// Where the numbers come from (the default plant: 6.1 V, L298 with 1.4 V
// drop, 48:1 gear, 64.4 mm wheels 128 mm apart; our estimates from its
// motor equations, to be checked against a run):
//   MIN_PWM 65: the geared motors do not start below ~60 (the dry friction
//     of the gearbox, 0.06 A of motor current); 65 turns the robot on the
//     spot at ~65 deg/s. Adding |u| to it compensates that dead zone.
//   MAX_PWM 85: ~190 deg/s on the spot. The gyro reads at most 250 deg/s at
//     FS_SEL 0; 100 would turn at ~270 deg/s, and what is clipped is lost
//     from the heading for good.
//   KP 2 per degree: u reaches MAX_PWM - MIN_PWM = 20 at 10 degrees of
//     error; beyond that the turn runs at MAX_PWM.
//   KD 0.1 per deg/s = KP x 50 ms: u changes sign (the motors reverse and
//     brake) once the robot would reach the heading within 50 ms at its
//     present rate: about the time the braked motors take to stop from the
//     MIN_PWM speed (mechanical time constant 64 ms when braked).
//   DEAD_BAND_DEG 1: inside it the motors brake. The braked motors still
//     carry the robot 1 to 1.5 degrees from the MIN_PWM speed, so a much
//     smaller band would be crossed and the robot would hunt back and forth;
//     the gyro's noise alone never takes the heading out of it.
//
// D5 and D6 are Timer0's PWM pins (976.6 Hz); analogWrite() leaves
// Timer0's setup alone, so millis() and micros() keep working.

#include <Wire.h>

// L298N pins
const byte ENA = 5;
const byte IN1 = 7;
const byte IN2 = 8;
const byte ENB = 6;
const byte IN3 = 9;
const byte IN4 = 11;

// MPU-6050: address (AD0 low) and registers. An int, so that
// Wire.requestFrom(MPU_ADDR, 2) picks requestFrom(int, int) unambiguously.
const int MPU_ADDR = 0x68;
const byte REG_SMPLRT_DIV = 0x19;
const byte REG_CONFIG = 0x1A;
const byte REG_GYRO_CONFIG = 0x1B;
const byte REG_GYRO_ZOUT_H = 0x47;
const byte REG_PWR_MGMT_1 = 0x6B;
const byte REG_WHO_AM_I = 0x75;
const byte WHO_AM_I_VALUE = 0x68;

const float GYRO_LSB_PER_DPS = 131.0;   // FS_SEL 0
const int CAL_SAMPLES = 200;            // gyro bias: reads at rest, 2 ms apart

// control
const unsigned long LOOP_US = 5000;     // 5 ms
const unsigned long PRINT_MS = 200;
const float TARGET_DEG = 0.0;
const float KP = 2.0;                   // PWM steps per degree of error
const float KD = 0.1;                   // PWM steps per deg/s
const float DEAD_BAND_DEG = 1.0;
const int MIN_PWM = 65;                 // analogWrite values 0..255
const int MAX_PWM = 85;

float gyroBiasRaw = 0.0;                // GYRO_ZOUT at rest [LSB]
float headingDeg = 0.0;                 // integrated yaw, counter-clockwise positive
int turnCommand = 0;                    // -MAX_PWM..MAX_PWM, positive: turn left
unsigned long lastLoopUs = 0;
unsigned long lastPrintMs = 0;
unsigned int readErrors = 0;

// left and right motor: -255 (full reverse) .. 255 (full forward); 0 brakes
void setMotors(int left, int right) {
  if (left > 0) {
    digitalWrite(IN1, HIGH);
    digitalWrite(IN2, LOW);
  } else if (left < 0) {
    digitalWrite(IN1, LOW);
    digitalWrite(IN2, HIGH);
    left = -left;
  } else {
    digitalWrite(IN1, LOW);             // brake: IN1 = IN2 with EN high
    digitalWrite(IN2, LOW);
    left = 255;
  }
  if (right > 0) {
    digitalWrite(IN3, HIGH);
    digitalWrite(IN4, LOW);
  } else if (right < 0) {
    digitalWrite(IN3, LOW);
    digitalWrite(IN4, HIGH);
    right = -right;
  } else {
    digitalWrite(IN3, LOW);
    digitalWrite(IN4, LOW);
    right = 255;
  }
  analogWrite(ENA, left);
  analogWrite(ENB, right);
}

// turn on the spot: positive = left (counter-clockwise), 0 = brake
void setTurn(int command) {
  turnCommand = command;
  setMotors(-command, command);
}

bool writeRegister(byte reg, byte value) {
  Wire.beginTransmission(MPU_ADDR);
  Wire.write(reg);
  Wire.write(value);
  return Wire.endTransmission() == 0;
}

// one register's value, or -1 when the chip does not answer
int readRegister(byte reg) {
  Wire.beginTransmission(MPU_ADDR);
  Wire.write(reg);
  if (Wire.endTransmission(false) != 0) return -1;   // repeated START next
  if (Wire.requestFrom(MPU_ADDR, 1) != 1) return -1;
  return Wire.read();
}

// GYRO_ZOUT (0x47 high byte, 0x48 low byte) in one burst
bool readGyroZ(int16_t &raw) {
  Wire.beginTransmission(MPU_ADDR);
  Wire.write(REG_GYRO_ZOUT_H);
  if (Wire.endTransmission(false) != 0) return false;
  if (Wire.requestFrom(MPU_ADDR, 2) != 2) return false;
  byte high = Wire.read();
  byte low = Wire.read();
  raw = (int16_t)(((uint16_t)high << 8) | low);
  return true;
}

void halt() {
  setTurn(0);
  while (true) {
  }
}

void setup() {
  Serial.begin(115200);

  pinMode(ENA, OUTPUT);
  pinMode(IN1, OUTPUT);
  pinMode(IN2, OUTPUT);
  pinMode(ENB, OUTPUT);
  pinMode(IN3, OUTPUT);
  pinMode(IN4, OUTPUT);
  setTurn(0);

  Wire.begin();                                       // 100 kHz, master
  bool configured = writeRegister(REG_PWR_MGMT_1, 0x01);   // awake, PLL clock
  int who = readRegister(REG_WHO_AM_I);
  if (who != WHO_AM_I_VALUE) {
    Serial.print(F("error: MPU-6050 not found at 0x68: WHO_AM_I "));
    if (who < 0) {
      Serial.println(F("no answer"));
    } else {
      Serial.print(F("0x"));
      Serial.print(who, HEX);
      Serial.println(F(", expected 0x68"));
    }
    halt();
  }
  configured = configured && writeRegister(REG_GYRO_CONFIG, 0x00);   // +-250 deg/s
  configured = configured && writeRegister(REG_CONFIG, 0x03);        // DLPF 42 Hz
  configured = configured && writeRegister(REG_SMPLRT_DIV, 0x00);    // 1 kHz
  if (!configured) {
    Serial.println(F("error: MPU-6050 configuration write failed"));
    halt();
  }
  delay(100);               // the zero-rate output settles; the filter fills

  // gyro bias: the robot must stand still now
  long sum = 0;
  int count = 0;
  for (int i = 0; i < CAL_SAMPLES; i++) {
    int16_t raw;
    if (readGyroZ(raw)) {
      sum += raw;
      count++;
    }
    delay(2);
  }
  if (count == 0) {
    Serial.println(F("error: MPU-6050 gyro read failed"));
    halt();
  }
  gyroBiasRaw = (float)sum / count;
  Serial.print(F("gyro Z bias "));
  Serial.print(gyroBiasRaw / GYRO_LSB_PER_DPS, 3);
  Serial.println(F(" deg/s"));

  Serial.println(F("heading_hold_mpu6050 ready"));
  headingDeg = 0.0;
  lastLoopUs = micros();
  lastPrintMs = millis();
}

void loop() {
  unsigned long now = micros();
  if (now - lastLoopUs < LOOP_US) return;
  float dt = (now - lastLoopUs) * 1e-6;
  lastLoopUs = now;

  int16_t raw;
  if (!readGyroZ(raw)) {
    readErrors++;
    setTurn(0);             // no rate this period: stop rather than guess
    return;
  }
  float rateDps = (raw - gyroBiasRaw) / GYRO_LSB_PER_DPS;
  headingDeg += rateDps * dt;

  float error = TARGET_DEG - headingDeg;
  float u = KP * error - KD * rateDps;
  if (fabs(error) < DEAD_BAND_DEG) {
    setTurn(0);
  } else {
    float magnitude = fabs(u);
    int pwm = magnitude >= MAX_PWM - MIN_PWM ? MAX_PWM : MIN_PWM + (int)magnitude;
    setTurn(u > 0 ? pwm : -pwm);
  }

  if (millis() - lastPrintMs >= PRINT_MS) {
    lastPrintMs += PRINT_MS;
    Serial.print(F("heading "));
    Serial.print(headingDeg, 2);
    Serial.print(F(" deg, turn "));
    Serial.print(turnCommand);
    Serial.print(F(", read errors "));
    Serial.println(readErrors);
  }
}
