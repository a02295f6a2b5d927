// pro_mini_8mhz_tb6612: a 3.3 V Arduino Pro Mini (ATmega328P at 8 MHz) and a
// TB6612FNG drive straight for 1.5 s by millis(), brake, and report.
//
// Wiring:
//   TB6612FNG module (logic at 3.3 V, motors from the 6 V pack):
//     left motor:  PWMA -> D9 (OC1A), AIN1 -> D7, AIN2 -> D8
//     right motor: PWMB -> D10 (OC1B), BIN1 -> D4, BIN2 -> D5
//     STBY -> D6 (high: driver on)
//   Single-channel Hall encoders on the motor shafts:
//     left OUT -> D2 (INT0)      right OUT -> D3 (INT1)
//
// At 8 MHz everything the Arduino core times runs from the 8 MHz clock:
// analogWrite on Timer1 is phase-correct PWM at 8e6 / 64 / 510 = 245 Hz
// (490 Hz on a 16 MHz board), millis() counts Timer0 overflows every
// 64 x 256 / 8 MHz = 2.048 ms, and Serial.begin(38400) sets UBRR0 = 25 with
// U2X0 (8e6 / (8 x 26) = 38462 baud, +0.16 %).

const byte PWMA = 9;
const byte AIN1 = 7;
const byte AIN2 = 8;
const byte PWMB = 10;
const byte BIN1 = 4;
const byte BIN2 = 5;
const byte STBY = 6;
const byte LEFT_ENC = 2;
const byte RIGHT_ENC = 3;

const int SPEED = 200;                   // of 255
const unsigned long DRIVE_MS = 1500;

volatile long leftTicks = 0;
volatile long rightTicks = 0;

void leftEncoder() { leftTicks++; }
void rightEncoder() { rightTicks++; }

long readTicks(volatile long &ticks) {
  noInterrupts();
  long value = ticks;
  interrupts();
  return value;
}

void forward(int speed) {
  digitalWrite(AIN1, HIGH);
  digitalWrite(AIN2, LOW);
  digitalWrite(BIN1, HIGH);
  digitalWrite(BIN2, LOW);
  analogWrite(PWMA, speed);
  analogWrite(PWMB, speed);
}

// Short brake (TB6612FNG truth table: IN1 = IN2 = H, PWM don't care).
void brake() {
  digitalWrite(AIN1, HIGH);
  digitalWrite(AIN2, HIGH);
  digitalWrite(BIN1, HIGH);
  digitalWrite(BIN2, HIGH);
  analogWrite(PWMA, 255);
  analogWrite(PWMB, 255);
}

void setup() {
  pinMode(AIN1, OUTPUT);
  pinMode(AIN2, OUTPUT);
  pinMode(BIN1, OUTPUT);
  pinMode(BIN2, OUTPUT);
  pinMode(PWMA, OUTPUT);
  pinMode(PWMB, OUTPUT);
  pinMode(STBY, OUTPUT);
  digitalWrite(STBY, HIGH);
  pinMode(LEFT_ENC, INPUT);
  pinMode(RIGHT_ENC, INPUT);
  attachInterrupt(digitalPinToInterrupt(LEFT_ENC), leftEncoder, CHANGE);
  attachInterrupt(digitalPinToInterrupt(RIGHT_ENC), rightEncoder, CHANGE);
  Serial.begin(38400);
  Serial.println("pro_mini_8mhz_tb6612 ready");

  const unsigned long start = millis();
  forward(SPEED);
  Serial.println("forward");
  while (millis() - start < DRIVE_MS) {
  }
  const unsigned long driven = millis() - start;
  brake();
  Serial.print("stop after ");
  Serial.print(driven);
  Serial.println(" ms");
  delay(500);  // at rest
  Serial.print("ticks ");
  Serial.print(readTicks(leftTicks));
  Serial.print(" ");
  Serial.println(readTicks(rightTicks));
  Serial.println("done");
}

void loop() {
}
