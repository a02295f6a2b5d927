#include "hil/uart_link.hpp"

#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <cstring>
#include <stdexcept>

#include "hil/serial_line.hpp"
#include "hil/simavr_io.hpp"

namespace ddmr::hil {
namespace {

avr_uart_t* find_uart(avr_t* avr, char name) {
    for (avr_io_t* io : simavr_io_modules(avr, "uart")) {
        auto* uart = reinterpret_cast<avr_uart_t*>(io);  // avr_io_t is its first member
        if (uart->name == name) return uart;
    }
    return nullptr;
}

bool bit(uint8_t value, int n) { return ((static_cast<unsigned>(value) >> n) & 1U) != 0; }

/// Frame time of a USART in asynchronous mode (datasheet 19.3.1, 19.4:
/// frame = start + data + optional parity + stop bits).
Cycles chip_cycles_per_byte(const AvrCore& core, const UsartDesc& u) {
    using namespace atmega328p;
    const uint8_t ucsrb = core.data(u.ucsrb);
    const uint8_t ucsrc = core.data(u.ucsrc);
    const unsigned ucsz = ((ucsrc >> uart_bit::kUcsz00) & 0x3U) | (bit(ucsrb, uart_bit::kUcsz02) ? 4U : 0U);
    static constexpr unsigned kDataBits[8] = {5, 6, 7, 8, 8, 8, 8, 9};  // 4..6 reserved
    const unsigned data_bits = kDataBits[ucsz];
    const unsigned parity_bits = ((ucsrc >> uart_bit::kUpm00) & 0x3U) != 0 ? 1U : 0U;
    const unsigned stop_bits = bit(ucsrc, uart_bit::kUsbs0) ? 2U : 1U;
    return static_cast<Cycles>(usart_cycles_per_bit(core, u)) * (1U + data_bits + parity_bits + stop_bits);
}

}  // namespace

unsigned usart_cycles_per_bit(const AvrCore& core, const UsartDesc& u) {
    using namespace atmega328p;
    const auto ubrr = static_cast<uint16_t>(core.data(u.ubrrl) | ((core.data(u.ubrrh) & 0x0FU) << 8));
    return static_cast<unsigned>(SerialLine::avr_bit_cycles(ubrr, bit(core.data(u.ucsra), uart_bit::kU2x0)));
}

bool usart_receiver_enabled(const AvrCore& core, const UsartDesc& u) {
    return bit(core.data(u.ucsrb), atmega328p::uart_bit::kRxen0);
}

UartLink::UartLink(AvrCore& core, UartTiming timing) : UartLink(core, core.board().console(), timing) {}

UartLink::UartLink(AvrCore& core, const UsartDesc& usart, UartTiming timing) : core_(core), usart_(usart) {
    avr_t* avr = core_.raw();
    const char name = usart_irq_name(usart_);
    uart_ = find_uart(avr, name);
    if (uart_ == nullptr) throw std::runtime_error(std::string("simavr core has no USART") + name);
    avr_irq_t* irqs = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ(name), 0);
    if (irqs == nullptr) throw std::runtime_error(std::string("simavr USART") + name + " has no IRQs");
    input_irq_ = irqs + UART_IRQ_INPUT;
    received_.reserve(kRecordedBytes);
    avr_irq_register_notify(irqs + UART_IRQ_OUTPUT, &UartLink::on_output, this);
    avr_irq_register_notify(irqs + UART_IRQ_OUT_XON, &UartLink::on_xon, this);
    avr_irq_register_notify(irqs + UART_IRQ_OUT_XOFF, &UartLink::on_xoff, this);
    if (timing == UartTiming::kChip) {
        for (uint16_t addr : {usart_.ucsra, usart_.ucsrb, usart_.ucsrc, usart_.ubrrl, usart_.ubrrh}) {
            // A read changes nothing (the frame time is recomputed from the
            // same registers), so fast-forward may skip a loop reading them
            // (UCSRnA itself stays refused: simavr's read of it raises XON).
            core_.watch_io(addr, &UartLink::on_frame_register, this, AvrCore::IoReads::kIgnored);
        }
    }
    // A reset disables the USART: wait for the firmware's next XON (its
    // Serial.begin) before sending the queue on.
    core_.add_reset_listener(this, [this] {
        xon_ = false;
        xoff_ = false;
    });
}

UartLink::~UartLink() { core_.remove_reset_listener(this); }

void UartLink::on_output(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* self = static_cast<UartLink*>(param);
    const UartByte byte{self->core_.cycle(), static_cast<uint8_t>(value)};
    if (self->received_.size() < kRecordedBytes) self->received_.push_back(byte);  // memory stays flat
    ++self->bytes_received_;
    if (self->listener_) self->listener_(byte);
}

void UartLink::on_xon(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* self = static_cast<UartLink*>(param);
    self->xon_ = value != 0;
    if (self->xon_) self->xoff_ = false;
    self->pump();
}

void UartLink::on_xoff(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    static_cast<UartLink*>(param)->xoff_ = value != 0;
}

void UartLink::on_frame_register(avr_irq_t* /*irq*/, uint32_t /*value*/, void* param) {
    static_cast<UartLink*>(param)->apply_chip_timing();
}

void UartLink::apply_chip_timing() { uart_->cycles_per_byte = chip_cycles_per_byte(core_, usart_); }

void UartLink::send(std::string_view bytes) {
    queue_.insert(queue_.end(), bytes.begin(), bytes.end());
    pump();
}

void UartLink::pump() {
    if (pumping_) return;  // raising INPUT can re-enter through XON/XOFF
    pumping_ = true;
    while (!queue_.empty() && xon_ && !xoff_) {
        const uint8_t b = queue_.front();
        queue_.pop_front();
        avr_raise_irq(input_irq_, b);
    }
    pumping_ = false;
}

std::string UartLink::text() const {
    std::string s;
    s.reserve(received_.size());
    for (const auto& b : received_) s.push_back(static_cast<char>(b.value));
    return s;
}

Cycles UartLink::cycles_per_byte() const { return uart_->cycles_per_byte; }

Cycles UartLink::cycles_per_bit() const { return usart_cycles_per_bit(core_, usart_); }

}  // namespace ddmr::hil
