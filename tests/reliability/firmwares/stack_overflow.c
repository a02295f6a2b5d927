/* Unbounded recursion: the stack grows down through .bss until it wraps. */
#include "common.h"

volatile unsigned char sink[64];

static unsigned char deeper(unsigned char n) {
    volatile unsigned char frame[16];
    frame[0] = n;
    sink[n % 64] = frame[0];
    return (unsigned char)(deeper((unsigned char)(n + 1)) + frame[0]);
}

int main(void) {
    uart_init();
    uart_puts("recursing\r\n");
    return deeper(0);
}
