#include "hil/host_adapter.hpp"

#include <stdexcept>

#include "hil/atmega328p.hpp"

namespace ddmr::hil {

namespace reg = atmega328p::reg;

namespace {
double adapter_bit_cycles(const AvrCore& core, uint32_t baud) {
    if (baud == 0) throw std::invalid_argument("HostAdapter: the baud rate must be > 0");
    return static_cast<double>(core.clock_hz()) / baud;
}
}  // namespace

HostAdapter::HostAdapter(AvrCore& core, uint32_t baud)
    : core_(core), baud_(baud), line_(adapter_bit_cycles(core, baud)) {}

double HostAdapter::firmware_bit_cycles() const {
    const auto ubrr = static_cast<uint16_t>(((core_.data(reg::kUbrr0H) & 0x0F) << 8) | core_.data(reg::kUbrr0L));
    const bool u2x = (core_.data(reg::kUcsr0A) & 0x02) != 0;  // U2X0
    return SerialLine::avr_bit_cycles(ubrr, u2x);
}

bool HostAdapter::receiver_enabled() const { return (core_.data(reg::kUcsr0B) & (1U << 4)) != 0; }  // RXEN0

void HostAdapter::on_firmware_byte(const UartByte& b, std::vector<LineByte>& out) {
    line_.push(static_cast<double>(b.cycle), b.value, firmware_bit_cycles(), out);
}

void HostAdapter::settle(Cycles cycle, std::vector<LineByte>& out) { line_.settle(static_cast<double>(cycle), out); }

void HostAdapter::flush(std::vector<LineByte>& out) { line_.flush(out); }

std::string HostAdapter::as_firmware_receives(const std::string& text) const {
    SerialLine firmware_rx(firmware_bit_cycles());
    std::vector<LineByte> got;
    double t = 0.0;
    const double bit = line_.rx_bit_cycles();
    for (const char c : text) {
        firmware_rx.push(t, static_cast<uint8_t>(c), bit, got);
        t += 10.0 * bit;
    }
    firmware_rx.flush(got);
    std::string out;
    for (const auto& b : got) out.push_back(static_cast<char>(b.value));
    return out;
}

}  // namespace ddmr::hil
