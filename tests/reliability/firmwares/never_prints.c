/* Runs forever and says nothing: only a time limit ends it. */
int main(void) {
    volatile unsigned long n = 0;
    for (;;) ++n;
}
