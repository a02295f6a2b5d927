#include "hil/host_adapter.hpp"

#include <stdexcept>

#include "hil/uart_link.hpp"

namespace ddmr::hil {

namespace {
double adapter_bit_cycles(const AvrCore& core, uint32_t baud) {
    if (baud == 0) throw std::invalid_argument("HostAdapter: the baud rate must be > 0");
    return static_cast<double>(core.clock_hz()) / baud;
}
}  // namespace

HostAdapter::HostAdapter(AvrCore& core, const UsartDesc& usart, uint32_t baud)
    : core_(core), usart_(usart), baud_(baud), line_(adapter_bit_cycles(core, baud)) {}

double HostAdapter::firmware_bit_cycles() const { return static_cast<double>(usart_cycles_per_bit(core_, usart_)); }

bool HostAdapter::receiver_enabled() const { return usart_receiver_enabled(core_, usart_); }

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
