#include "hil/uart_link.hpp"

#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <cstring>
#include <stdexcept>

namespace ddmr::hil {
namespace {

constexpr char kUartName = '0';

avr_uart_t* find_uart(avr_t* avr, char name) {
    for (avr_io_t* io = avr->io_port; io != nullptr; io = io->next) {
        if (io->kind != nullptr && std::strcmp(io->kind, "uart") == 0) {
            auto* uart = reinterpret_cast<avr_uart_t*>(io);  // avr_io_t is its first member
            if (uart->name == name) return uart;
        }
    }
    return nullptr;
}

bool bit(uint8_t value, int n) { return ((static_cast<unsigned>(value) >> n) & 1U) != 0; }

/// Bit time of the ATmega328P USART in asynchronous mode (datasheet 19.3.1).
unsigned chip_cycles_per_bit(const AvrCore& core) {
    using namespace atmega328p;
    const unsigned ubrr =
        static_cast<unsigned>(core.data(reg::kUbrr0L)) | ((core.data(reg::kUbrr0H) & 0x0FU) << 8);
    return (ubrr + 1) * (bit(core.data(reg::kUcsr0A), uart_bit::kU2x0) ? 8U : 16U);
}

/// Frame time of the ATmega328P USART in asynchronous mode (datasheet 19.3.1,
/// 19.4: frame = start + data + optional parity + stop bits).
Cycles chip_cycles_per_byte(const AvrCore& core) {
    using namespace atmega328p;
    const uint8_t ucsrb = core.data(reg::kUcsr0B);
    const uint8_t ucsrc = core.data(reg::kUcsr0C);
    const unsigned ucsz = ((ucsrc >> uart_bit::kUcsz00) & 0x3U) | (bit(ucsrb, uart_bit::kUcsz02) ? 4U : 0U);
    static constexpr unsigned kDataBits[8] = {5, 6, 7, 8, 8, 8, 8, 9};  // 4..6 reserved
    const unsigned data_bits = kDataBits[ucsz];
    const unsigned parity_bits = ((ucsrc >> uart_bit::kUpm00) & 0x3U) != 0 ? 1U : 0U;
    const unsigned stop_bits = bit(ucsrc, uart_bit::kUsbs0) ? 2U : 1U;
    return static_cast<Cycles>(chip_cycles_per_bit(core)) * (1U + data_bits + parity_bits + stop_bits);
}

}  // namespace

UartLink::UartLink(AvrCore& core, UartTiming timing) : core_(core) {
    avr_t* avr = core_.raw();
    uart_ = find_uart(avr, kUartName);
    if (uart_ == nullptr) throw std::runtime_error("simavr core has no USART0");
    avr_irq_t* irqs = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ(kUartName), 0);
    if (irqs == nullptr) throw std::runtime_error("simavr USART0 has no IRQs");
    input_irq_ = irqs + UART_IRQ_INPUT;
    received_.reserve(kRecordedBytes);
    avr_irq_register_notify(irqs + UART_IRQ_OUTPUT, &UartLink::on_output, this);
    avr_irq_register_notify(irqs + UART_IRQ_OUT_XON, &UartLink::on_xon, this);
    avr_irq_register_notify(irqs + UART_IRQ_OUT_XOFF, &UartLink::on_xoff, this);
    if (timing == UartTiming::kChip) {
        using namespace atmega328p::reg;
        for (uint16_t addr : {kUcsr0A, kUcsr0B, kUcsr0C, kUbrr0L, kUbrr0H}) {
            avr_irq_t* w = avr_iomem_getirq(avr, addr, nullptr, AVR_IOMEM_IRQ_ALL);
            avr_irq_register_notify(w, &UartLink::on_frame_register, this);
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

void UartLink::apply_chip_timing() { uart_->cycles_per_byte = chip_cycles_per_byte(core_); }

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

Cycles UartLink::cycles_per_bit() const { return chip_cycles_per_bit(core_); }

}  // namespace ddmr::hil
