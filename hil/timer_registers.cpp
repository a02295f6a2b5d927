#include "hil/timer_registers.hpp"

namespace ddmr::hil {
namespace {

uint16_t read16(const AvrCore& core, uint16_t low, uint16_t high) {
    if (low == 0) return 0;
    uint16_t v = core.data(low);
    if (high != 0) v = static_cast<uint16_t>(v | (core.data(high) << 8));
    return v;
}

}  // namespace

TimerRegisters read_timer_registers(const AvrCore& core, const TimerDesc& d) {
    TimerRegisters r;
    r.tccra = core.data(d.tccra);
    r.tccrb = core.data(d.tccrb);
    r.ocra = read16(core, d.ocra_low, d.ocra_high);
    r.ocrb = read16(core, d.ocrb_low, d.ocrb_high);
    r.ocrc = read16(core, d.ocrc_low, d.ocrc_high);
    r.icr = read16(core, d.icr_low, d.icr_high);
    r.tcnt = read16(core, d.tcnt_low, d.tcnt_high);
    return r;
}

bool same_settings(const TimerRegisters& a, const TimerRegisters& b) {
    return a.tccra == b.tccra && a.tccrb == b.tccrb && a.ocra == b.ocra && a.ocrb == b.ocrb && a.ocrc == b.ocrc &&
           a.icr == b.icr;
}

}  // namespace ddmr::hil
