#pragma once
// HostAdapter: the host's USB-serial adapter on one of the firmware's USARTs
// (the UartLink's: USART0 = Serial, or Serial1..3 on a Mega) at a baud rate of its own, as on the bench: what the firmware sends is decoded
// by the adapter's receiver at its rate (the firmware's frames at the
// firmware's rate, from UBRR0/U2X0 when each byte left), and what the host
// types becomes what the firmware's receiver makes of frames at the adapter's
// rate. A mismatch gives garbage and framing errors, as a wrong baud rate
// does on a real robot (hil/serial_line.hpp does the bit-level decoding).
//
// Signals: none of its own; feed it the UartLink's bytes (on_firmware_byte)
// and call settle() now and then (every coupling step) to get the bytes
// whose stop bit the adapter has sampled.

#include <cstdint>
#include <string>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/serial_line.hpp"
#include "hil/uart_link.hpp"

namespace ddmr::hil {

class HostAdapter {
public:
    /// On `usart` (the UartLink's); `baud` > 0: the adapter's rate (8N1).
    HostAdapter(AvrCore& core, const UsartDesc& usart, uint32_t baud);

    /// A byte the firmware wrote (UartLink's listener): the bytes the adapter
    /// has decoded so far are appended to `out`.
    void on_firmware_byte(const UartByte& b, std::vector<LineByte>& out);
    /// Bytes whose stop bit the adapter has sampled by `cycle`.
    void settle(Cycles cycle, std::vector<LineByte>& out);
    /// Every byte still on the wire (the end of a run).
    void flush(std::vector<LineByte>& out);
    /// What the firmware's receiver makes of `text` sent at the adapter's rate.
    std::string as_firmware_receives(const std::string& text) const;
    /// The firmware's bit time on the adapter's USART now, from UBRRn and U2Xn [cycles].
    double firmware_bit_cycles() const;
    /// RXENn: the firmware listens.
    bool receiver_enabled() const;
    uint64_t framing_errors() const { return line_.framing_errors(); }
    uint32_t baud() const { return baud_; }

private:
    AvrCore& core_;
    const UsartDesc& usart_;
    uint32_t baud_;
    SerialLine line_;
};

}  // namespace ddmr::hil
