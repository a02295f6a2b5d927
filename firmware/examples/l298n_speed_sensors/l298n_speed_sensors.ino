// l298n_speed_sensors: drive straight for a set number of encoder slots,
// brake, and print the counts.
//
// Wiring (the usual "smart robot car" kit):
//   L298N module, ENA/ENB jumpers removed
//     ENA -> D5  left motor speed     IN1 -> D7, IN2 -> D8   left motor
//     ENB -> D6  right motor speed    IN3 -> D9, IN4 -> D11  right motor
//   two slotted speed sensors (LM393 modules), 20-slot discs on the wheel shafts
//     left OUT -> D2 (INT0)           right OUT -> D3 (INT1)
//
// D5 and D6 are Timer0's PWM pins (fast PWM, 976.6 Hz). analogWrite() only
// sets their compare registers: Timer0 keeps the setup the Arduino core gave
// it, so millis() and delay() still count real milliseconds.

// L298N pins
const byte ENA = 5;
const byte IN1 = 7;
const byte IN2 = 8;
const byte ENB = 6;
const byte IN3 = 9;
const byte IN4 = 11;

// speed sensor outputs
const byte LEFT_SENSOR = 2;
const byte RIGHT_SENSOR = 3;

const unsigned int TARGET_SLOTS = 100;   // 5 wheel turns of 20 slots: 5 x 202 mm = 1.01 m
const int DRIVE_SPEED = 180;             // analogWrite value, 0..255
const unsigned long TIMEOUT_MS = 5000;   // stop anyway if a sensor never counts

// Both edges of every slot are counted (CHANGE): one slot = 2 counts.
volatile unsigned int leftCount = 0;
volatile unsigned int rightCount = 0;

void leftPulse() {
  leftCount++;
}

void rightPulse() {
  rightCount++;
}

// Both counters at once: an interrupt cannot change them half-way through.
void readCounts(unsigned int &left, unsigned int &right) {
  noInterrupts();
  left = leftCount;
  right = rightCount;
  interrupts();
}

void leftForward(int speed) {
  digitalWrite(IN1, HIGH);
  digitalWrite(IN2, LOW);
  analogWrite(ENA, speed);
}

void rightForward(int speed) {
  digitalWrite(IN3, HIGH);
  digitalWrite(IN4, LOW);
  analogWrite(ENB, speed);
}

// Brake: both inputs low with the enable high short the motor through the
// L298's lower transistors, so the wheel stops in a few centimetres.
void leftBrake() {
  digitalWrite(IN1, LOW);
  digitalWrite(IN2, LOW);
  digitalWrite(ENA, HIGH);
}

void rightBrake() {
  digitalWrite(IN3, LOW);
  digitalWrite(IN4, LOW);
  digitalWrite(ENB, HIGH);
}

// Drives both wheels forward; each wheel brakes when its own sensor has
// counted the slots.
void driveSlots(unsigned int slots) {
  const unsigned int target = 2 * slots;
  noInterrupts();
  leftCount = 0;
  rightCount = 0;
  interrupts();

  unsigned long start = millis();
  bool leftDone = false;
  bool rightDone = false;
  leftForward(DRIVE_SPEED);
  rightForward(DRIVE_SPEED);
  Serial.println(F("go"));

  while (!leftDone || !rightDone) {
    unsigned int left, right;
    readCounts(left, right);
    if (!leftDone && left >= target) {
      leftBrake();
      leftDone = true;
    }
    if (!rightDone && right >= target) {
      rightBrake();
      rightDone = true;
    }
    if (millis() - start > TIMEOUT_MS) {
      leftBrake();
      rightBrake();
      Serial.println(F("timeout: a speed sensor did not count"));
      break;
    }
  }
  Serial.print(F("stopped after "));
  Serial.print(millis() - start);
  Serial.println(F(" ms"));
}

void setup() {
  Serial.begin(9600);

  pinMode(ENA, OUTPUT);
  pinMode(IN1, OUTPUT);
  pinMode(IN2, OUTPUT);
  pinMode(ENB, OUTPUT);
  pinMode(IN3, OUTPUT);
  pinMode(IN4, OUTPUT);
  digitalWrite(ENA, LOW);   // motors off until we start
  digitalWrite(ENB, LOW);

  pinMode(LEFT_SENSOR, INPUT);
  pinMode(RIGHT_SENSOR, INPUT);
  attachInterrupt(digitalPinToInterrupt(LEFT_SENSOR), leftPulse, CHANGE);
  attachInterrupt(digitalPinToInterrupt(RIGHT_SENSOR), rightPulse, CHANGE);

  Serial.println(F("l298n_speed_sensors ready"));
  delay(500);               // time to put the robot down

  driveSlots(TARGET_SLOTS);
  delay(500);               // let it come to rest

  unsigned int left, right;
  readCounts(left, right);
  Serial.print(F("counts left "));
  Serial.print(left);
  Serial.print(F(" right "));
  Serial.println(right);
}

void loop() {
}
