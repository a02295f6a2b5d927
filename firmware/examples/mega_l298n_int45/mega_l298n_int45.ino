// mega_l298n_int45: an Arduino Mega 2560 and an L298N module drive two wheel
// turns straight, stop, and keep the counts in the EEPROM's last bytes.
//
// Wiring:
//   L298N module (enable jumpers removed):
//     left motor:  ENA -> D5 (OC3A, Timer3), IN1 -> D22, IN2 -> D23
//     right motor: ENB -> D6 (OC4A, Timer4), IN3 -> D24, IN4 -> D25
//   Single-channel Hall encoders on the motor shafts:
//     left OUT -> D2 (INT4)      right OUT -> D3 (INT5)
//   (attachInterrupt(digitalPinToInterrupt(2)) is interrupt 0 on the Mega:
//   the ATmega2560's INT4, PE4.)
//
// analogWrite on Timer3/Timer4 is phase-correct 8-bit PWM at 16e6 / 64 / 510
// = 490 Hz (the Arduino core's init() sets WGMn0 and clock/64).

#include <EEPROM.h>

const byte ENA = 5;
const byte IN1 = 22;
const byte IN2 = 23;
const byte ENB = 6;
const byte IN3 = 24;
const byte IN4 = 25;
const byte LEFT_ENC = 2;
const byte RIGHT_ENC = 3;

const int SPEED = 180;
const long TARGET = 768;  // two wheel turns: 2 x 384 counts

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

void setup() {
  pinMode(IN1, OUTPUT);
  pinMode(IN2, OUTPUT);
  pinMode(IN3, OUTPUT);
  pinMode(IN4, OUTPUT);
  pinMode(ENA, OUTPUT);
  pinMode(ENB, OUTPUT);
  pinMode(LEFT_ENC, INPUT);
  pinMode(RIGHT_ENC, INPUT);
  attachInterrupt(digitalPinToInterrupt(LEFT_ENC), leftEncoder, CHANGE);
  attachInterrupt(digitalPinToInterrupt(RIGHT_ENC), rightEncoder, CHANGE);
  Serial.begin(115200);
  Serial.println("mega_l298n_int45 ready");

  digitalWrite(IN1, HIGH);
  digitalWrite(IN2, LOW);
  digitalWrite(IN3, HIGH);
  digitalWrite(IN4, LOW);
  analogWrite(ENA, SPEED);
  analogWrite(ENB, SPEED);
  Serial.println("forward");
  bool leftDone = false;
  bool rightDone = false;
  while (!leftDone || !rightDone) {
    if (!leftDone && readTicks(leftTicks) >= TARGET) {
      digitalWrite(IN1, LOW);  // brake: both inputs low, enable high
      digitalWrite(IN2, LOW);
      digitalWrite(ENA, HIGH);
      leftDone = true;
    }
    if (!rightDone && readTicks(rightTicks) >= TARGET) {
      digitalWrite(IN3, LOW);
      digitalWrite(IN4, LOW);
      digitalWrite(ENB, HIGH);
      rightDone = true;
    }
  }
  delay(500);  // at rest
  const long left = readTicks(leftTicks);
  const long right = readTicks(rightTicks);
  // The counts in the last four bytes of the 4 KiB EEPROM (4092..4095).
  EEPROM.update(4092, lowByte(left));
  EEPROM.update(4093, highByte(left));
  EEPROM.update(4094, lowByte(right));
  EEPROM.update(4095, highByte(right));
  Serial.print("ticks ");
  Serial.print(left);
  Serial.print(" ");
  Serial.println(right);
  Serial.println("done");
}

void loop() {
}
