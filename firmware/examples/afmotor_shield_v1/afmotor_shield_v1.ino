// afmotor_shield_v1: an Adafruit Motor Shield v1 on an Uno, driven the way the
// AFMotor library drives it (written here from the datasheets, no library):
// both motors FORWARD at speed 200 for 2 s, print the encoder counts, then
// RELEASE both.
//
// Sources (as in /work/shared/DRIVERS.md and SENSORS.md):
//   [L293] TI L293/L293D, SLRS008B/C     [595] NXP 74HC595/74HCT595 rev. 6
//   [M328] Atmel ATmega328P 7810D        [AFM] the shield's pin assignment
//
// Wiring (the shield; pins as [AFM] names them):
//   74HCT595 shift register: DS (serial data)     <- D8  (MOTORDATA)
//                            SHCP (shift clock)   <- D4  (MOTORCLK)
//                            STCP (storage clock) <- D12 (MOTORLATCH)
//                            /OE (output enable)  <- D7  (MOTORENABLE)
//   Its outputs Q0..Q7 are the L293D's direction inputs (A, B):
//     M1 (right wheel): A = Q2, B = Q3, enable 1,2EN <- D11 = OC2A (Timer2)
//     M2 (left wheel):  A = Q1, B = Q4, enable 3,4EN <- D3  = OC2B (Timer2)
//   (Q0, Q5..Q7 belong to M3/M4, which this robot does not use.)
//   Single-channel Hall encoders on the motor shafts, on pins the shield
//   leaves free: right OUT -> A0 (PCINT8), left OUT -> A1 (PCINT9), both on
//   port C's pin-change interrupt PCINT1. D3 carries M2's PWM, so INT1 is not
//   available; D2 (INT0) alone would serve only one wheel.
//
// The 74HC595 ([595] §1, §7 Table 3):
//   - DS is shifted into stage 0 on the LOW-to-HIGH edge of SHCP; the earlier
//     stages move up one place. After eight clocks the bit sent first sits in
//     stage 7: sending bit 7 first puts bit n of the byte on Qn.
//   - The LOW-to-HIGH edge of STCP copies the shift register into the storage
//     register, which drives Q0..Q7: the outputs change once per byte, never
//     while bits are shifting through.
//   - Q0..Q7 follow the storage register while /OE is LOW and are high-Z while
//     it is HIGH. The register's contents at power-up are not defined, so the
//     sketch latches 0x00 before it pulls /OE low.
//   - Timing: 74HCT minimum pulse width 16 ns, set-up 16 ns, hold 3 ns
//     ([595] Table 7); digitalWrite() takes microseconds, so no delays are
//     needed between the edges.
//
// The L293D ([L293] function table, Figure 5 "Bidirectional DC motor control"):
//   EN = H: each output follows its input: A = 1, B = 0 drives the motor one
//   way (FORWARD), A = 0, B = 1 the other (BACKWARD), A = B (both 0 here:
//   RELEASE) drives both ends low: "fast motor stop", a brake.
//   EN = L: the outputs are high-Z; a current still flowing returns through
//   the built-in clamp diodes (VOKH/VOKL 1.3 V typ at 0.6 A). PWM on EN
//   therefore alternates drive and free-running (fast decay). Drop while
//   driving at 0.6 A: VOH VCC2 - 1.4 V + VOL 1.2 V = 2.6 V typ (3.6 V max).
//
// Timer2 ([M328] Table 17-8, Tables 17-3/17-6, Table 17-9, §17.7.3):
//   WGM22:0 = 011: fast PWM, TOP = 0xFF. COM2A1:0 = COM2B1:0 = 10: clear OC2x
//   on compare match, set at BOTTOM (non-inverting). CS22:0 = 010: clk/8.
//   f = 16 MHz / (8 x 256) = 7812.5 Hz; duty = (OCR2x + 1) / 256, so speed
//   200 -> 201/256 = 0.785. OCR2x = 0 still gives a one-timer-clock spike each
//   period (§17.7.3). OCR2x is double-buffered: a new value takes effect at
//   the next BOTTOM. The OC2x signal reaches the pin only with its DDR bit set.
//
// Traceable globals (ddmr-hil --trace, scenario expect-var):
//   latch_state            uint8_t: the byte last latched into the 595
//   rightTicks, leftTicks  volatile uint16_t: every level change of each
//                          encoder (384 per wheel turn on the default robot;
//                          65535 = 170 wheel turns, far more than this run).
//                          No direction: a single-channel encoder cannot tell.

#include <avr/interrupt.h>
#include <avr/io.h>

// Shield pins
const uint8_t MOTORLATCH = 12;   // 595 STCP
const uint8_t MOTORCLK = 4;      // 595 SHCP
const uint8_t MOTORENABLE = 7;   // 595 /OE (active low)
const uint8_t MOTORDATA = 8;     // 595 DS
const uint8_t M1_PWM = 11;       // OC2A -> L293D 1,2EN
const uint8_t M2_PWM = 3;        // OC2B -> L293D 3,4EN

// Bits of the 595 byte (bit n = Qn)
const uint8_t M1_A = 2;
const uint8_t M1_B = 3;
const uint8_t M2_A = 1;
const uint8_t M2_B = 4;

enum Direction : uint8_t { FORWARD, BACKWARD, RELEASE };

const uint8_t DRIVE_SPEED = 200;         // OCR2x: duty 201/256
const unsigned long DRIVE_MS = 2000;
const unsigned long SETTLE_MS = 500;

uint8_t latch_state = 0;                 // the byte the 595's storage register holds

volatile uint16_t rightTicks = 0;        // A0 level changes
volatile uint16_t leftTicks = 0;         // A1 level changes
volatile uint8_t lastEncoderPins = 0;    // PINC bits 0 (right) and 1 (left)

// Any level change on A0 or A1 ([M328] §12: the pin-change group has one
// flag and one vector, no edge choice): compare with the last levels seen.
ISR(PCINT1_vect) {
  uint8_t pins = PINC & 0x03;
  uint8_t changed = pins ^ lastEncoderPins;
  lastEncoderPins = pins;
  if (changed & 0x01) rightTicks++;
  if (changed & 0x02) leftTicks++;
}

uint16_t readTicks(volatile uint16_t &ticks) {
  noInterrupts();                        // two bytes: keep the ISR out between them
  uint16_t value = ticks;
  interrupts();
  return value;
}

// Shift `value` into the 595, bit 7 first, and latch it onto Q0..Q7.
void latchByte(uint8_t value) {
  digitalWrite(MOTORLATCH, LOW);
  for (int8_t bit = 7; bit >= 0; bit--) {
    digitalWrite(MOTORCLK, LOW);
    digitalWrite(MOTORDATA, (value >> bit) & 1 ? HIGH : LOW);
    digitalWrite(MOTORCLK, HIGH);        // rising SHCP: DS -> stage 0
  }
  digitalWrite(MOTORLATCH, HIGH);        // rising STCP: shift -> storage register
  latch_state = value;
}

void shieldBegin() {
  pinMode(MOTORLATCH, OUTPUT);
  pinMode(MOTORENABLE, OUTPUT);
  pinMode(MOTORDATA, OUTPUT);
  pinMode(MOTORCLK, OUTPUT);
  latchByte(0x00);                       // all direction inputs low ...
  digitalWrite(MOTORENABLE, LOW);        // ... before the outputs are enabled

  // Timer2: fast PWM, non-inverting on OC2A and OC2B, clk/8 (7812.5 Hz).
  OCR2A = 0;
  OCR2B = 0;
  TCCR2A = _BV(COM2A1) | _BV(COM2B1) | _BV(WGM21) | _BV(WGM20);
  TCCR2B = _BV(CS21);
  pinMode(M1_PWM, OUTPUT);
  pinMode(M2_PWM, OUTPUT);
}

// One motor's two direction bits, then latch the whole byte.
void run(uint8_t bitA, uint8_t bitB, Direction dir) {
  uint8_t value = latch_state;
  switch (dir) {
    case FORWARD:
      value |= _BV(bitA);
      value &= ~_BV(bitB);
      break;
    case BACKWARD:
      value &= ~_BV(bitA);
      value |= _BV(bitB);
      break;
    case RELEASE:
      value &= ~(_BV(bitA) | _BV(bitB));
      break;
  }
  latchByte(value);
}

void printTicks(const __FlashStringHelper *label) {
  Serial.print(label);
  Serial.print(F(" right "));
  Serial.print(readTicks(rightTicks));
  Serial.print(F(" left "));
  Serial.println(readTicks(leftTicks));
}

void setup() {
  Serial.begin(115200);

  // Encoders: A0, A1 inputs, pin-change interrupts PCINT8, PCINT9.
  DDRC &= ~0x03;
  lastEncoderPins = PINC & 0x03;
  PCMSK1 |= _BV(PCINT8) | _BV(PCINT9);
  PCIFR = _BV(PCIF1);                    // forget any change before now
  PCICR |= _BV(PCIE1);

  shieldBegin();
  Serial.println(F("afmotor_shield_v1 ready"));

  OCR2A = DRIVE_SPEED;                   // M1 speed
  OCR2B = DRIVE_SPEED;                   // M2 speed
  run(M1_A, M1_B, FORWARD);              // latches 0x04
  run(M2_A, M2_B, FORWARD);              // latches 0x06
  Serial.println(F("forward"));
  delay(DRIVE_MS);

  printTicks(F("ticks"));
  Serial.println(F("done"));
  run(M1_A, M1_B, RELEASE);              // latches 0x02
  run(M2_A, M2_B, RELEASE);              // latches 0x00: EN still pulses, both ends low: brake
  delay(SETTLE_MS);
  printTicks(F("released"));
}

void loop() {
}
