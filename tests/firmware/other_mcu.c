/* A minimal AVR program, compiled for MCUs other than the ATmega328P so the
 * tests can check that such firmware is refused. */
volatile unsigned char counter;

int main(void) {
    for (;;) ++counter;
}
