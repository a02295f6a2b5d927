/* Prints what a Unity test run prints (ThrowTheSwitch's Unity, as `pio test`
 * builds it: each result, then UNITY_END()'s summary) on USART0 at 9600 baud
 * 8N1 as Arduino sets it (U2X0, UBRR0 = 207), then idles. Built twice: all
 * three tests passing (OK), and with -DFAIL one failing (FAIL). Lines end in
 * "\r\n" as PlatformIO's Arduino Unity port ends them; the HIL must also
 * accept Unity's default "\n". */
#include "usart0.h"

#define put usart0_put

int main(void) {
    usart0_begin_9600();
    put("test/test_main.cpp:21:test_wheel_distance:PASS\r\n");
    put("test/test_main.cpp:22:test_heading:PASS\r\n");
#ifdef FAIL
    put("test/test_main.cpp:23:test_stop:FAIL: Expected 0 Was 3\r\n");
    put("\r\n-----------------------\r\n3 Tests 1 Failures 0 Ignored \r\nFAIL\r\n");
#else
    put("test/test_main.cpp:23:test_stop:PASS\r\n");
    put("\r\n-----------------------\r\n3 Tests 0 Failures 0 Ignored \r\nOK\r\n");
#endif
    put("after the summary\r\n"); /* never read: the run ends with the summary */
    for (;;) {
    }
}
