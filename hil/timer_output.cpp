#include "hil/timer_output.hpp"

#include <algorithm>
#include <cassert>
#include <stdexcept>
#include <string>
#include <tuple>

#include "hil/atmega328p.hpp"

namespace ddmr::hil {
namespace {

// TCCRnA: COMnA1:0 = bits 7:6, COMnB1:0 = bits 5:4, COMnC1:0 = bits 3:2
// (ATmega2560 Timer1/3/4/5; reserved on the ATmega328P), WGMn1:0 = bits 1:0;
// TCCRnB: WGMn3:2 = bits 4:3 (Timer0/2: WGMn2 = bit 3), CSn2:0 = bits 2:0.
constexpr std::array<unsigned, kMaxOcChannels> kComShift = {6, 4, 2};
constexpr unsigned kComMask = 0x03;
constexpr unsigned kWgmLowMask = 0x03;
constexpr unsigned kWgmHighMask = 0x0C;  ///< TCCRnB bits 4:3 shifted right by 1
constexpr uint8_t kComToggle = 1;
constexpr uint8_t kComClear = 2;

uint8_t wgm_of(const TimerRegisters& regs, int modes) {
    const unsigned wgm = (regs.tccra & kWgmLowMask) | ((static_cast<unsigned>(regs.tccrb) >> 1U) & kWgmHighMask);
    return static_cast<uint8_t>(wgm & static_cast<unsigned>(modes - 1));
}

uint8_t com_of(uint8_t tccra, unsigned shift) {
    return static_cast<uint8_t>((static_cast<unsigned>(tccra) >> shift) & kComMask);
}

bool is_pwm(WaveKind kind) {
    return kind == WaveKind::kFastPwm || kind == WaveKind::kPhaseCorrect || kind == WaveKind::kPhaseFreqCorrect;
}

void validate(const TimerDesc& desc) {
    if (desc.bits != 8 && desc.bits != 16) {
        throw std::invalid_argument("TimerDesc of timer " + std::to_string(desc.index) + ": bits = " +
                                    std::to_string(desc.bits) + ", expected 8 or 16");
    }
    if (desc.channels != 2 && desc.channels != kMaxOcChannels) {
        throw std::invalid_argument("TimerDesc of timer " + std::to_string(desc.index) + ": channels = " +
                                    std::to_string(desc.channels) + ", expected 2 or 3");
    }
    if (desc.wgm_modes != 8 && desc.wgm_modes != 16) {
        throw std::invalid_argument("TimerDesc of timer " + std::to_string(desc.index) + ": wgm_modes = " +
                                    std::to_string(desc.wgm_modes) + ", expected 8 or 16");
    }
}

}  // namespace

bool TimerOutputDecoder::Shape::operator==(const Shape& o) const {
    return std::tie(running, wgm, com, ocr, prescaler, top) ==
           std::tie(o.running, o.wgm, o.com, o.ocr, o.prescaler, o.top);
}

TimerOutputDecoder::TimerOutputDecoder(const TimerDesc& desc, const TimerOutputOptions& options)
    : desc_(desc), options_(options), max_(desc.max()) {
    validate(desc_);
    configure(TimerRegisters{});
    refresh_top();
    rebase(0, Count{});
}

// ---- register writes and buffered updates ----------------------------------

bool TimerOutputDecoder::on_write(Cycles cycle, const TimerRegisters& regs, bool tcnt_written) {
    apply_due(cycle);
    const Shape before = shape();
    snapshot_levels(cycle);  // (old configuration, cycle) => OCnx levels, count
    Count count = count_at(cycle);
    const bool was_ticking = ticking();
    const uint8_t old_wgm = wgm_;

    configure(regs);
    take_ocr_writes(regs);
    if (!running() || mode_.update == OcrUpdate::kImmediate) apply_buffers();
    refresh_top();
    if (!ticking() && any_pending()) {  // dual slope with TOP = 0: the count cannot move
        apply_buffers();
        refresh_top();
    }
    if (tcnt_written) {
        count = Count{regs.tcnt & max_, count.down, 0};
    } else if (!was_ticking) {
        count.sub = 0;  // the clock starts: a fresh count
    }
    rebase(cycle, count);
    if (wgm_ != old_wgm) reset_latches();
    schedule_pending(cycle);
    return tcnt_written || !(shape() == before);
}

std::optional<Cycles> TimerOutputDecoder::advance_to(Cycles cycle) {
    apply_due(cycle);
    const std::optional<Cycles> first = unreported_update_;
    unreported_update_.reset();
    return first;
}

void TimerOutputDecoder::configure(const TimerRegisters& regs) {
    wgm_ = wgm_of(regs, desc_.wgm_modes);
    mode_ = desc_.modes[wgm_];
    prescaler_ = desc_.prescaler[regs.tccrb & atmega328p::kClockSelectMask];
    icr_ = regs.icr & max_;
    for (std::size_t c = 0; c < static_cast<std::size_t>(desc_.channels); ++c) {
        ch_[c].com = com_of(regs.tccra, kComShift[c]);
    }
}

void TimerOutputDecoder::take_ocr_writes(const TimerRegisters& regs) {
    const std::array<uint16_t, kMaxOcChannels> written = {regs.ocra, regs.ocrb, regs.ocrc};
    for (std::size_t i = 0; i < static_cast<std::size_t>(desc_.channels); ++i) {
        Channel& h = ch_[i];
        Cycles value = written[i] & max_;
        if (options_.mask_ocr_to_fixed_top && mode_.top_source == TopSource::kFixed) value &= mode_.fixed_top;
        if (value == h.ocr_written) continue;  // not this register (or the same value again)
        h.ocr_written = static_cast<uint16_t>(value);
        h.pending = h.ocr_written != h.ocr;
    }
}

void TimerOutputDecoder::apply_buffers() {
    for (Channel& h : ch_) {
        if (!h.pending) continue;
        update_latch(h);
        h.ocr = h.ocr_written;
        h.pending = false;
    }
}

void TimerOutputDecoder::update_latch(Channel& h) const {
    if (h.ocr > top_) return;  // it never matched: the level stays
    // The level of the OCR in effect at the update point: at TOP (count TOP >=
    // any OCR < TOP: low; OCR = TOP: high); at BOTTOM (high unless OCR = 0).
    h.latch = mode_.update == OcrUpdate::kAtTop ? h.ocr >= top_ : h.ocr > 0;
}

void TimerOutputDecoder::refresh_top() {
    switch (mode_.top_source) {
        case TopSource::kFixed: top_ = mode_.fixed_top; break;
        case TopSource::kOcrA: top_ = ch_[0].ocr; break;
        case TopSource::kIcr: top_ = icr_; break;
    }
    // Dual slope with TOP = 0 gives 0: the count stays at BOTTOM (treated as stopped).
    period_ = dual_slope() ? 2 * top_ * prescaler_ : (top_ + 1) * prescaler_;
}

void TimerOutputDecoder::rebase(Cycles cycle, Count count) {
    if (!dual_slope()) count.down = false;
    ref_ = cycle;
    regime_start_ = cycle;
    regime_pos_ = 0;
    match_from_ = cycle + 1;  // a match at the write's own cycle is not counted
    if (!ticking()) {
        ref_count_ = count;
        return;
    }
    const Cycles n = prescaler_;
    count.sub = std::min(count.sub, n - 1);
    ref_count_ = count;
    if (count.value <= top_) {
        regime_pos_ = position_of(count);
        return;
    }
    // Above TOP: up to MAX and wrap to BOTTOM, or (dual slope, down) down to TOP.
    if (count.down) {
        regime_start_ = cycle + (count.value - top_) * n - count.sub;
        regime_pos_ = top_ * n;
    } else {
        regime_start_ = cycle + (max_ + 1 - count.value) * n - count.sub;
    }
    match_from_ = regime_start_;
}

void TimerOutputDecoder::snapshot_levels(Cycles cycle) {
    for (int c = 0; c < desc_.channels; ++c) ch_[static_cast<std::size_t>(c)].oc = level_at(c, cycle);
}

void TimerOutputDecoder::reset_latches() {
    for (Channel& h : ch_) h.latch = h.oc != (h.com == 3);  // the pin keeps its level
}

void TimerOutputDecoder::schedule_pending(Cycles cycle) {
    pending_cycle_ = kNever;
    if (!any_pending()) return;
    const Cycles at = mode_.update == OcrUpdate::kAtTop ? top_ * prescaler_ : 0;
    pending_cycle_ = next_at_or_after(at, std::max(cycle + 1, regime_start_));
}

void TimerOutputDecoder::apply_due(Cycles cycle) {
    if (pending_cycle_ <= cycle) apply_update(pending_cycle_);
}

void TimerOutputDecoder::apply_update(Cycles cycle) {
    snapshot_levels(cycle);
    const Count count = count_at(cycle);  // TOP (PC) or BOTTOM: no cycles into the count
    apply_buffers();
    refresh_top();
    rebase(cycle, count);
    pending_cycle_ = kNever;
    if (!unreported_update_) unreported_update_ = cycle;
}

TimerOutputDecoder::Shape TimerOutputDecoder::shape() const {
    Shape s;
    s.running = running();
    s.wgm = wgm_;
    s.com = {ch_[0].com, ch_[1].com, ch_[2].com};
    s.ocr = {ch_[0].ocr, ch_[1].ocr, ch_[2].ocr};
    s.prescaler = prescaler_;
    s.top = top_;
    return s;
}

bool TimerOutputDecoder::dual_slope() const {
    return mode_.kind == WaveKind::kPhaseCorrect || mode_.kind == WaveKind::kPhaseFreqCorrect;
}

// ---- the counter ---------------------------------------------------------------

Cycles TimerOutputDecoder::pos_at(Cycles cycle) const {
    return (regime_pos_ + (cycle - regime_start_)) % period_;
}

Cycles TimerOutputDecoder::position_of(const Count& count) const {
    if (!dual_slope() || !count.down) return count.value * prescaler_ + count.sub;
    return ((2 * top_ - count.value) * prescaler_ + count.sub) % period_;
}

TimerOutputDecoder::Count TimerOutputDecoder::count_from_pos(Cycles pos) const {
    Count c{pos / prescaler_, false, pos % prescaler_};
    if (dual_slope() && c.value >= top_) {
        c.value = 2 * top_ - c.value;
        c.down = true;
    }
    return c;
}

TimerOutputDecoder::Count TimerOutputDecoder::count_at(Cycles cycle) const {
    if (!ticking()) return ref_count_;
    if (cycle >= regime_start_) return count_from_pos(pos_at(cycle));
    // Still above TOP, moving from ref_count_ towards MAX (up) or TOP (down).
    const Cycles elapsed = cycle - ref_ + ref_count_.sub;
    Count c = ref_count_;
    c.sub = elapsed % prescaler_;
    c.value = c.down ? c.value - elapsed / prescaler_ : c.value + elapsed / prescaler_;
    return c;
}

// ---- the outputs -----------------------------------------------------------------

const TimerOutputDecoder::Channel& TimerOutputDecoder::chan(int ch) const {
    assert(ch >= 0 && ch < desc_.channels);
    return ch_[static_cast<std::size_t>(ch)];
}

bool TimerOutputDecoder::connected(int ch) const {
    const uint8_t com = chan(ch).com;
    if (com == 0 || mode_.kind == WaveKind::kReserved) return false;
    if (com != kComToggle || !is_pwm(mode_.kind)) return true;
    return ch == 0 && mode_.com01_toggles_a;
}

TimerOutputDecoder::Action TimerOutputDecoder::action(int ch) const {
    if (!ticking() || !connected(ch)) return Action::kHold;
    const uint8_t com = chan(ch).com;
    if (com == kComToggle) return Action::kToggle;
    switch (mode_.kind) {
        case WaveKind::kNormal:
        case WaveKind::kCtc: return com == kComClear ? Action::kClear : Action::kSet;
        case WaveKind::kFastPwm: return Action::kFastPwm;
        case WaveKind::kPhaseCorrect:
        case WaveKind::kPhaseFreqCorrect: return Action::kPhasePwm;
        case WaveKind::kReserved: break;
    }
    return Action::kHold;
}

bool TimerOutputDecoder::pwm_level(const Channel& h, Action a, Cycles pos) const {
    const Cycles ocr = h.ocr;
    if (a == Action::kFastPwm) return ocr >= top_ || pos < (ocr + 1) * prescaler_;
    if (ocr > top_) return h.latch;
    const Cycles half = ocr * prescaler_;  // PhaseCorrectPwm::level_at
    return pos < half || pos >= period_ - half;
}

TimerOutputDecoder::Matches TimerOutputDecoder::matches_of(int ch) const {
    Matches m;
    const Cycles ocr = chan(ch).ocr;
    if (ocr > top_) return m;
    m.pos[0] = ocr * prescaler_;  // up-count: the count reaches OCR
    m.n = 1;
    if (!dual_slope()) return m;
    const Cycles down = (period_ - m.pos[0]) % period_;  // down-count (one match at 0 and TOP)
    if (down != m.pos[0]) {
        m.pos[1] = down;
        m.n = 2;
    }
    return m;
}

Cycles TimerOutputDecoder::matches_through(const Matches& m, Cycles cycle) const {
    if (cycle < match_from_) return 0;
    // Unwrapped positions (cycles from a BOTTOM before regime_start_) of
    // [match_from_, cycle]; a match at position q counts as many times as
    // q + k·period lies in [from, to).
    const Cycles from = regime_pos_ + (match_from_ - regime_start_);
    const Cycles to = regime_pos_ + (cycle - regime_start_) + 1;
    Cycles count = 0;
    for (std::size_t i = 0; i < m.n; ++i) {
        const Cycles shift = period_ - 1 - m.pos[i];
        count += (to + shift) / period_ - (from + shift) / period_;
    }
    return count;
}

Cycles TimerOutputDecoder::next_at_or_after(Cycles pos, Cycles cycle) const {
    return cycle + (pos + period_ - pos_at(cycle)) % period_;
}

Cycles TimerOutputDecoder::next_match_after(const Matches& m, Cycles cycle) const {
    Cycles next = kNever;
    for (std::size_t i = 0; i < m.n; ++i) next = std::min(next, next_at_or_after(m.pos[i], cycle + 1));
    return next;
}

Cycles TimerOutputDecoder::next_position_after(Cycles pos, Cycles cycle) const {
    if (!ticking()) return kNever;
    return next_at_or_after(pos, std::max(cycle + 1, regime_start_));
}

Cycles TimerOutputDecoder::next_bottom_after(Cycles cycle) const { return next_position_after(0, cycle); }

Cycles TimerOutputDecoder::next_top_after(Cycles cycle) const {
    return next_position_after(top_ * prescaler_, cycle);
}

Cycles TimerOutputDecoder::next_compare_match_after(int ch, Cycles cycle) const {
    if (!ticking()) return kNever;
    const Matches m = matches_of(ch);
    Cycles next = kNever;
    for (std::size_t i = 0; i < m.n; ++i) next = std::min(next, next_position_after(m.pos[i], cycle));
    return next;
}

bool TimerOutputDecoder::level_at(int ch, Cycles cycle) const {
    const Channel& h = chan(ch);
    const Action a = action(ch);
    if (a == Action::kHold || cycle < regime_start_) return h.oc;
    switch (a) {
        case Action::kFastPwm:
        case Action::kPhasePwm: return pwm_level(h, a, pos_at(cycle)) != inverting(ch);
        case Action::kToggle: return h.oc != (matches_through(matches_of(ch), cycle) % 2 == 1);
        case Action::kClear:
        case Action::kSet: return matches_through(matches_of(ch), cycle) > 0 ? a == Action::kSet : h.oc;
        case Action::kHold: break;
    }
    return h.oc;
}

Cycles TimerOutputDecoder::next_change_after(int ch, Cycles cycle) const {
    const Action a = action(ch);
    if (a == Action::kHold) return kNever;
    Cycles from = cycle;
    if (cycle < regime_start_) {  // held until the count is back in range
        if (level_at(ch, regime_start_) != chan(ch).oc) return regime_start_;
        from = regime_start_;
    }
    return next_change_in_regime(ch, a, from);
}

Cycles TimerOutputDecoder::next_change_in_regime(int ch, Action a, Cycles cycle) const {
    const Channel& h = chan(ch);
    switch (a) {
        case Action::kFastPwm: return next_fast_edge(h, cycle);
        case Action::kPhasePwm: return next_phase_edge(h, cycle);
        case Action::kToggle: return next_match_after(matches_of(ch), cycle);
        case Action::kClear:
        case Action::kSet:
            if (level_at(ch, cycle) == (a == Action::kSet)) return kNever;
            return next_match_after(matches_of(ch), cycle);
        case Action::kHold: break;
    }
    return kNever;
}

Cycles TimerOutputDecoder::next_fast_edge(const Channel& h, Cycles cycle) const {
    if (h.ocr >= top_) return kNever;
    const Cycles p = pos_at(cycle);
    const Cycles high = (Cycles{h.ocr} + 1) * prescaler_;
    return p < high ? cycle + (high - p) : cycle + (period_ - p);
}

Cycles TimerOutputDecoder::next_phase_edge(const Channel& h, Cycles cycle) const {
    // PhaseCorrectPwm::next_edge_after, for any TOP and N.
    if (h.ocr == 0 || h.ocr >= top_) return kNever;
    const Cycles p = pos_at(cycle);
    const Cycles half = Cycles{h.ocr} * prescaler_;
    if (p < half) return cycle + (half - p);                         // falling (up-count match)
    if (p < period_ - half) return cycle + (period_ - half - p);     // rising (down-count match)
    return cycle + (period_ - p) + half;                             // falling, next period
}

double TimerOutputDecoder::duty(int ch) const {
    const Channel& h = chan(ch);
    const Action a = action(ch);
    const double held = h.oc ? 1.0 : 0.0;
    switch (a) {
        case Action::kFastPwm:
        case Action::kPhasePwm: {
            const double d = pwm_duty(h, a);
            return inverting(ch) ? 1.0 - d : d;
        }
        case Action::kToggle: return matches_of(ch).n > 0 ? 0.5 : held;
        case Action::kClear:
        case Action::kSet:
            if (matches_of(ch).n == 0) return held;
            return a == Action::kSet ? 1.0 : 0.0;
        case Action::kHold: break;
    }
    return held;
}

double TimerOutputDecoder::pwm_duty(const Channel& h, Action a) const {
    if (a == Action::kFastPwm) {
        if (h.ocr >= top_) return 1.0;
        return static_cast<double>(h.ocr + 1) / static_cast<double>(top_ + 1);
    }
    if (h.ocr > top_) return h.latch ? 1.0 : 0.0;
    return static_cast<double>(h.ocr) / static_cast<double>(top_);  // today's ocr / 255.0 for TOP 255
}

Cycles TimerOutputDecoder::period_cycles(int ch) const {
    const Channel& h = chan(ch);
    switch (action(ch)) {
        case Action::kFastPwm: return h.ocr >= top_ ? 0 : period_;
        case Action::kPhasePwm: return h.ocr == 0 || h.ocr >= top_ ? 0 : period_;
        case Action::kToggle: {
            const Matches m = matches_of(ch);
            return m.n == 0 ? 0 : 2 * period_ / m.n;  // two toggles make a period
        }
        case Action::kHold:
        case Action::kClear:
        case Action::kSet: break;
    }
    return 0;
}

}  // namespace ddmr::hil
