// forgot_pinmode: a sketch with a classic bug, kept on purpose so the HIL can
// show what it does.
//
// The enables get 7.8 kHz PWM (quieter than analogWrite's 490 Hz) from
// Timer1 set up by register writes. analogWrite() would have made the pins
// outputs itself; with direct register writes that is the sketch's job, and
// setup() forgets it for the right enable (D10). A timer's compare output
// reaches its pin only when the pin is an output, so OCR1B changes nothing:
// the L298N's ENB sees a floating input and the right motor never runs.
//
// Intended behaviour: drive straight until both wheels have turned 950
// encoder counts (about 50 cm), then stop; give up after 3 s.
//
// Wiring:
//   L298N module, ENA/ENB jumpers removed
//     left motor:  ENA -> D9 (OC1A),  IN1 -> D7,  IN2 -> D8
//     right motor: ENB -> D10 (OC1B), IN3 -> D12, IN4 -> D13
//   Single-channel Hall encoders on the motor shafts, 384 edges per wheel
//   turn, counted on both edges:
//     right OUT -> D2 (INT0)      left OUT -> D3 (INT1)

const byte LEFT_EN = 9;
const byte LEFT_IN1 = 7;
const byte LEFT_IN2 = 8;
const byte RIGHT_EN = 10;
const byte RIGHT_IN1 = 12;
const byte RIGHT_IN2 = 13;
const byte RIGHT_ENC = 2;
const byte LEFT_ENC = 3;

const unsigned int TARGET_COUNTS = 950;   // 950 / 384 turns x 202 mm = 50 cm
const byte DRIVE_SPEED = 230;             // OCR1x, duty (230 + 1) / 256 = 90 %
const unsigned long TIMEOUT_MS = 3000;

volatile unsigned int leftCount = 0;
volatile unsigned int rightCount = 0;

void leftEncoder() {
  leftCount++;
}

void rightEncoder() {
  rightCount++;
}

// Timer1, 8-bit fast PWM (mode 5), clk/8: 16 MHz / 8 / 256 = 7.8 kHz,
// non-inverting on OC1A (D9) and OC1B (D10).
void setupPwm() {
  TCCR1B = 0;
  TCCR1A = _BV(COM1A1) | _BV(COM1B1) | _BV(WGM10);
  TCCR1B = _BV(WGM12) | _BV(CS11);
  OCR1A = 0;
  OCR1B = 0;
}

void leftForward(byte speed) {
  digitalWrite(LEFT_IN1, HIGH);
  digitalWrite(LEFT_IN2, LOW);
  OCR1A = speed;
}

void rightForward(byte speed) {
  digitalWrite(RIGHT_IN1, HIGH);
  digitalWrite(RIGHT_IN2, LOW);
  OCR1B = speed;
}

// Enable (nearly) off and both inputs low: the motor coasts to a stop.
void leftStop() {
  OCR1A = 0;
  digitalWrite(LEFT_IN1, LOW);
  digitalWrite(LEFT_IN2, LOW);
}

void rightStop() {
  OCR1B = 0;
  digitalWrite(RIGHT_IN1, LOW);
  digitalWrite(RIGHT_IN2, LOW);
}

void setup() {
  Serial.begin(9600);
  pinMode(LEFT_EN, OUTPUT);
  // BUG: pinMode(RIGHT_EN, OUTPUT) is missing.
  pinMode(LEFT_IN1, OUTPUT);
  pinMode(LEFT_IN2, OUTPUT);
  pinMode(RIGHT_IN1, OUTPUT);
  pinMode(RIGHT_IN2, OUTPUT);
  setupPwm();
  leftStop();
  rightStop();

  pinMode(RIGHT_ENC, INPUT);
  pinMode(LEFT_ENC, INPUT);
  attachInterrupt(digitalPinToInterrupt(RIGHT_ENC), rightEncoder, CHANGE);
  attachInterrupt(digitalPinToInterrupt(LEFT_ENC), leftEncoder, CHANGE);

  Serial.println(F("forgot_pinmode ready"));
  delay(500);

  Serial.println(F("go"));
  unsigned long start = millis();
  bool leftDone = false;
  bool rightDone = false;
  leftForward(DRIVE_SPEED);
  rightForward(DRIVE_SPEED);
  while (!leftDone || !rightDone) {
    noInterrupts();
    unsigned int left = leftCount;
    unsigned int right = rightCount;
    interrupts();
    if (!leftDone && left >= TARGET_COUNTS) {
      leftStop();
      leftDone = true;
    }
    if (!rightDone && right >= TARGET_COUNTS) {
      rightStop();
      rightDone = true;
    }
    if (millis() - start > TIMEOUT_MS) {
      leftStop();
      rightStop();
      Serial.println(F("timeout: a wheel did not reach its count"));
      break;
    }
  }
  delay(1000);   // coasting
  noInterrupts();
  unsigned int left = leftCount;
  unsigned int right = rightCount;
  interrupts();
  Serial.print(F("counts left "));
  Serial.print(left);
  Serial.print(F(" right "));
  Serial.println(right);
}

void loop() {
}
