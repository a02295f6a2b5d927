#pragma once
// UartLink: the host end of one of the firmware's USARTs, like a USB-serial
// adapter: the board's console (USART0: Serial) by default, or another USART
// of the MCU (USART1 = Serial1 on the Mega 2560, where a Bluetooth module
// often sits).
//
// Signals (simavr UART IRQs of that USART, '0' for USART0):
//   in  UART_IRQ_OUTPUT    each byte the firmware writes to UDR0, captured with
//                          the cycle of the write (the start of its frame);
//   in  UART_IRQ_OUT_XON   the receive FIFO has room: queued bytes are sent;
//   in  UART_IRQ_OUT_XOFF  the receive FIFO is full (63 bytes): sending pauses;
//   out UART_IRQ_INPUT     a byte delivered to the firmware's receiver.
// Bytes sent while the receiver is off (before Serial.begin) wait in the queue
// until simavr signals XON, so nothing is silently dropped.
//
// Frame timing: simavr 1.6 counts a parity bit in every frame (11 bit times
// for 8N1: 18,304 cycles per byte at the Uno's 9600 baud setting, UBRR0 = 207
// with U2X0). With UartTiming::kChip (the default) the link recomputes the
// frame time from UBRR0, U2X0, UCSZ0, UPM0 and USBS0 as the datasheet does
// (8N1: 10 bit times = 16,640 cycles) whenever the firmware writes them.

#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "hil/avr_core.hpp"

struct avr_irq_t;
struct avr_uart_t;

namespace ddmr::hil {

struct UartByte {
    Cycles cycle = 0;   ///< AVR cycle at which the firmware wrote UDR0
    uint8_t value = 0;
};

enum class UartTiming {
    kChip,    ///< frame time as on the ATmega328P (datasheet section 19)
    kSimavr,  ///< simavr 1.6's own frame time (one extra parity bit)
};

/// Bit time of `u` in asynchronous mode from its UBRR and U2X [cycles]:
/// (UBRR + 1) x 16, or x 8 with U2X (ATmega328P datasheet 19.3.1; every
/// megaAVR USART has the same rule and bit positions).
unsigned usart_cycles_per_bit(const AvrCore& core, const UsartDesc& u);
/// RXEN of `u` is set.
bool usart_receiver_enabled(const AvrCore& core, const UsartDesc& u);

class UartLink {
public:
    /// On the board's console USART (Serial).
    explicit UartLink(AvrCore& core, UartTiming timing = UartTiming::kChip);
    /// On `usart`, one of core.mcu().usarts.
    UartLink(AvrCore& core, const UsartDesc& usart, UartTiming timing);
    ~UartLink();
    UartLink(const UartLink&) = delete;
    UartLink& operator=(const UartLink&) = delete;

    /// Queues bytes for the firmware's receiver; they are delivered as soon as
    /// (and while) simavr signals XON.
    void send(std::string_view bytes);
    /// Bytes queued by send() and not yet delivered.
    std::size_t pending() const { return queue_.size(); }

    /// The first kRecordedBytes bytes the firmware transmitted, in order,
    /// with their cycles (for tests): long runs keep their memory flat.
    /// Whoever needs every byte takes them from the listener as they come.
    static constexpr std::size_t kRecordedBytes = 16384;
    const std::vector<UartByte>& received() const { return received_; }
    /// The recorded bytes as text (verbatim, including \r\n).
    std::string text() const;
    /// Every byte the firmware transmitted so far, counted (recorded or not).
    uint64_t bytes_received() const { return bytes_received_; }

    /// Called for every byte the firmware transmits, as it is written to UDR0
    /// (inside the simulation: keep it short, do not throw).
    void set_listener(std::function<void(const UartByte&)> listener) { listener_ = std::move(listener); }

    /// The USART the link is on.
    const UsartDesc& usart() const { return usart_; }
    /// The frame time simavr is currently using [cycles per byte].
    Cycles cycles_per_byte() const;
    /// One bit time on the line as the registers set it (UBRR0, U2X0;
    /// datasheet 19.3.1) [cycles per bit]: 1664 at the Uno's 9600 baud.
    Cycles cycles_per_bit() const;

private:
    static void on_output(avr_irq_t* irq, uint32_t value, void* param);
    static void on_xon(avr_irq_t* irq, uint32_t value, void* param);
    static void on_xoff(avr_irq_t* irq, uint32_t value, void* param);
    static void on_frame_register(avr_irq_t* irq, uint32_t value, void* param);
    void pump();
    void apply_chip_timing();

    AvrCore& core_;
    const UsartDesc& usart_;  ///< the USART the link is on (the console: USART0)
    avr_uart_t* uart_ = nullptr;
    avr_irq_t* input_irq_ = nullptr;
    bool xon_ = false;
    bool xoff_ = false;
    bool pumping_ = false;
    std::deque<uint8_t> queue_;
    std::vector<UartByte> received_;  ///< the first kRecordedBytes
    uint64_t bytes_received_ = 0;
    std::function<void(const UartByte&)> listener_;
};

}  // namespace ddmr::hil
