#include "hil/isr_monitor.hpp"

#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_interrupts.h>
#include <sim_irq.h>

#include <fmt/format.h>

#include <stdexcept>

namespace ddmr::hil {
namespace {

/// The flash byte address a vector's JMP (or RJMP) leads to, if it is one.
std::optional<uint32_t> vector_target(const AvrCore& core, int vector) {
    const auto at = static_cast<uint32_t>(vector * core.mcu().vector_bytes);
    const uint16_t w0 = core.flash_word(at);
    if ((w0 & 0xFE0E) == 0x940C) {  // JMP k: 1001 010k kkkk 110k, kkkk kkkk kkkk kkkk
        const uint32_t k = ((static_cast<uint32_t>(w0 & 0x01F0) >> 3) | (w0 & 0x0001U)) << 16 |
                           core.flash_word(at + 2);
        return k * 2;
    }
    if ((w0 & 0xF000) == 0xC000) {  // RJMP k: 1100 kkkk kkkk kkkk, k signed words
        int64_t k = w0 & 0x0FFF;
        if (k & 0x0800) k -= 0x1000;
        return static_cast<uint32_t>(static_cast<int64_t>(at) + 2 + 2 * k);
    }
    return std::nullopt;
}

std::string min_mean_max(const CycleStats& s) {
    if (s.count == 0) return "–";
    return fmt::format("{} / {:.1f} / {}", s.min, s.mean(), s.max);
}

}  // namespace

std::string vector_handler_name(const AvrCore& core, const ElfImage& elf, int vector) {
    const auto target = vector_target(core, vector);
    if (!target) return "?";
    const auto bad = elf.find(kNoHandler);
    if (bad && bad->address == *target) return kNoHandler;
    const auto own = elf.find("__vector_" + std::to_string(vector));
    if (own && own->address == *target) return own->name;
    if (const auto f = elf.function_at(*target)) return f->name;
    return fmt::format("0x{:04x}", *target);
}

std::size_t CycleHistogram::bin_of(Cycles cycles) {
    std::size_t bin = 0;
    while (cycles != 0 && bin < kBins - 1) {
        cycles >>= 1;
        ++bin;
    }
    return bin;
}

Cycles CycleHistogram::lower_bound(std::size_t bin) { return bin == 0 ? 0 : Cycles{1} << (bin - 1); }

std::string CycleHistogram::label(std::size_t bin) {
    if (bin == 0) return "0";
    if (bin == 1) return "1";
    if (bin == kBins - 1) return ">=" + std::to_string(lower_bound(bin));
    return std::to_string(lower_bound(bin)) + "-" + std::to_string(lower_bound(bin + 1) - 1);
}

void CycleStats::add(Cycles cycles) {
    if (count == 0 || cycles < min) min = cycles;
    if (count == 0 || cycles > max) max = cycles;
    sum += cycles;
    ++count;
}

IsrMonitor::IsrMonitor(AvrCore& core, const ElfImage& elf, const IsrMonitorConfig& config)
    : core_(core),
      config_(config),
      start_cycle_(core.cycle()),
      mcu_(core.mcu()),
      vectors_(static_cast<std::size_t>(mcu_.vector_count())),
      handlers_(static_cast<std::size_t>(mcu_.vector_count())) {
    events_.reserve(config_.event_capacity);
    avr_t* avr = core_.raw();
    for (int v = 1; v < mcu_.vector_count(); ++v) {
        VectorState& s = vectors_[static_cast<std::size_t>(v)];
        handlers_[static_cast<std::size_t>(v)] = vector_handler_name(core_, elf, v);
        // A vector simavr's core does not declare (the ATmega2560's PCINT1/2
        // in 1.6) is never raised: nothing to watch.
        s.irqs = avr_get_interrupt_irq(avr, static_cast<uint8_t>(v));
        if (s.irqs == nullptr) continue;
        s.hook = Hook{this, v};
        avr_irq_register_notify(s.irqs + AVR_INT_IRQ_PENDING, &IsrMonitor::on_pending, &s.hook);
        avr_irq_register_notify(s.irqs + AVR_INT_IRQ_RUNNING, &IsrMonitor::on_running, &s.hook);
    }
    if (config_.precise) {
        i_flag_ = avr->sreg[S_I] != 0;
        last_cycle_ = avr->cycle;
        avr_cycle_timer_register(avr, 1, &IsrMonitor::on_instruction, this);
    }
    // A reset leaves every ISR without its RETI and cancels the precise-mode
    // timer: nothing is running any more.
    core_.add_reset_listener(this, [this] {
        for (VectorState& v : vectors_) v.depth = 0;
        nesting_ = 0;
        if (config_.precise) {
            last_cycle_ = core_.cycle();
            i_flag_ = false;
            avr_cycle_timer_register(core_.raw(), 1, &IsrMonitor::on_instruction, this);
        }
    });
}

IsrMonitor::~IsrMonitor() {
    core_.remove_reset_listener(this);
    avr_t* avr = core_.raw();
    for (int v = 1; v < mcu_.vector_count(); ++v) {
        VectorState& s = vectors_[static_cast<std::size_t>(v)];
        if (s.irqs == nullptr) continue;
        avr_irq_unregister_notify(s.irqs + AVR_INT_IRQ_PENDING, &IsrMonitor::on_pending, &s.hook);
        avr_irq_unregister_notify(s.irqs + AVR_INT_IRQ_RUNNING, &IsrMonitor::on_running, &s.hook);
    }
    if (config_.precise) avr_cycle_timer_cancel(avr, &IsrMonitor::on_instruction, this);
}

void IsrMonitor::on_pending(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    const auto* hook = static_cast<const Hook*>(param);
    VectorState& v = hook->self->vectors_[static_cast<std::size_t>(hook->vector)];
    if (value != 0) {
        // simavr reports a raise only when the vector is not already queued;
        // the latest report is the one the entry serves.
        v.raise = hook->self->core_.cycle();
        ++v.raised;
    } else {
        v.raise.reset();  // taken (reported just after RUNNING = 1) or flag cleared
    }
}

void IsrMonitor::on_running(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    const auto* hook = static_cast<const Hook*>(param);
    VectorState& v = hook->self->vectors_[static_cast<std::size_t>(hook->vector)];
    if (value != 0) {
        hook->self->enter(v, hook->vector);
    } else {
        hook->self->leave(v);
    }
}

void IsrMonitor::enter(VectorState& v, int vector) {
    const Cycles now = core_.cycle();
    ++v.count;
    if (v.depth > 0) ++v.reentries;
    std::optional<Cycles> latency;
    if (v.raise && *v.raise <= now) latency = now - *v.raise;
    if (latency) {
        v.latency.add(*latency);
        v.latency_histogram.add(*latency);
    }
    std::size_t event = kNoEvent;
    if (events_.size() < events_.capacity()) {
        event = events_.size();
        events_.push_back(IsrEvent{vector, v.raise, now, std::nullopt});
    }
    if (v.depth < kMaxNesting) {
        v.frames[static_cast<std::size_t>(v.depth)] = Frame{now, event};
    } else {
        ++untimed_;
    }
    ++v.depth;
    if (nesting_ == 0) outermost_entry_ = now;
    ++nesting_;
    if (nesting_ > max_nesting_) max_nesting_ = nesting_;
    i_flag_ = false;  // simavr cleared I before reporting the entry
}

void IsrMonitor::leave(VectorState& v) {
    if (v.depth == 0) return;  // a RETI whose entry came before the monitor
    // simavr reports RETI before it charges RETI's cycles.
    const Cycles end = core_.cycle() + mcu_.reti_cycles;
    --v.depth;
    if (v.depth < kMaxNesting) {
        const Frame& f = v.frames[static_cast<std::size_t>(v.depth)];
        const Cycles d = end - f.entry;
        v.duration.add(d);
        v.duration_histogram.add(d);
        if (f.event != kNoEvent) events_[f.event].exit_cycle = end;
    }
    if (nesting_ > 0 && --nesting_ == 0) isr_cycles_ += end - outermost_entry_;
}

uint64_t IsrMonitor::on_instruction(struct avr_t* avr, uint64_t /*when*/, void* param) {
    auto* self = static_cast<IsrMonitor*>(param);
    // The instruction(s) since the last call started with i_flag_ (an entry
    // in between already set it to 0); charge them, then sample I for the next.
    if (!self->i_flag_) self->disabled_cycles_ += avr->cycle - self->last_cycle_;
    self->last_cycle_ = avr->cycle;
    self->i_flag_ = avr->sreg[S_I] != 0;
    return avr->cycle + 1;
}

std::optional<Cycles> IsrMonitor::pending_since(int vector) const {
    if (vector < 1 || vector >= mcu_.vector_count()) return std::nullopt;
    return vectors_[static_cast<std::size_t>(vector)].raise;
}

IsrSummary IsrMonitor::summary() const {
    IsrSummary s;
    s.start_cycle = start_cycle_;
    s.end_cycle = core_.cycle();
    s.clock_hz = core_.clock_hz();
    s.precise = config_.precise;
    s.max_nesting = max_nesting_;
    s.untimed_entries = untimed_;
    s.isr_cycles = isr_cycles_ + (nesting_ > 0 ? s.end_cycle - outermost_entry_ : 0);
    if (config_.precise) {
        s.interrupts_disabled_cycles = disabled_cycles_ + (i_flag_ ? 0 : s.end_cycle - last_cycle_);
    }
    const Cycles observed = s.observed_cycles();
    for (int n = 1; n < mcu_.vector_count(); ++n) {
        const auto i = static_cast<std::size_t>(n);
        const VectorState& v = vectors_[i];
        if (v.count == 0) {
            if (v.raised != 0) s.raised_not_entered.push_back(mcu_.vector_name(n));
            continue;
        }
        VectorSummary out;
        out.vector = n;
        out.name = mcu_.vector_name(n);
        out.handler = handlers_[i];
        out.count = v.count;
        out.raised = v.raised;
        out.reentries = v.reentries;
        out.latency = v.latency;
        out.duration = v.duration;
        out.latency_histogram = v.latency_histogram;
        out.duration_histogram = v.duration_histogram;
        out.cpu_share = observed == 0 ? 0.0 : static_cast<double>(v.duration.sum) / static_cast<double>(observed);
        s.vectors.push_back(std::move(out));
    }
    return s;
}

std::string to_markdown(const IsrSummary& s) {
    std::string md;
    md += fmt::format("ISR timing over {} cycles ({:.3f} s at {:g} MHz); latency = raise to vector entry, "
                      "duration = vector JMP to end of RETI (simavr charges no interrupt-response cycles).\n\n",
                      s.observed_cycles(), cycles_to_s(s.observed_cycles(), s.clock_hz), s.clock_hz / 1e6);
    md += "| vector | source | handler | count | latency min / mean / max [cycles] | "
          "duration min / mean / max [cycles] | CPU share |\n";
    md += "|---:|---|---|---:|---:|---:|---:|\n";
    for (const auto& v : s.vectors) {
        md += fmt::format("| {} | {} | `{}` | {} | {} | {} | {:.3f} % |\n", v.vector, v.name, v.handler, v.count,
                          min_mean_max(v.latency), min_mean_max(v.duration), 100.0 * v.cpu_share);
    }
    const double observed = static_cast<double>(s.observed_cycles() == 0 ? 1 : s.observed_cycles());
    md += fmt::format("\nCycles in ISRs: {} ({:.3f} %), deepest nesting {}.", s.isr_cycles,
                      100.0 * static_cast<double>(s.isr_cycles) / observed, s.max_nesting);
    if (s.interrupts_disabled_cycles) {
        md += fmt::format(" Cycles with interrupts disabled (SREG.I clear): {} ({:.3f} %).\n",
                          *s.interrupts_disabled_cycles,
                          100.0 * static_cast<double>(*s.interrupts_disabled_cycles) / observed);
    } else {
        md += " Cycles with interrupts disabled: not measured (needs precise mode); at least the ISR cycles.\n";
    }
    if (!s.raised_not_entered.empty()) {
        md += "Raised but never entered (interrupt not enabled):";
        for (const auto& n : s.raised_not_entered) md += " " + n;
        md += ".\n";
    }
    md += "\n| vector | histogram | bins [cycles]: count |\n|---|---|---|\n";
    for (const auto& v : s.vectors) {
        for (const auto* which : {"latency", "duration"}) {
            const CycleHistogram& h = std::string(which) == "latency" ? v.latency_histogram : v.duration_histogram;
            std::string bins;
            for (std::size_t b = 0; b < CycleHistogram::kBins; ++b) {
                if (h.counts[b] == 0) continue;
                if (!bins.empty()) bins += ", ";
                bins += fmt::format("{}: {}", CycleHistogram::label(b), h.counts[b]);
            }
            md += fmt::format("| {} | {} | {} |\n", v.name, which, bins.empty() ? "–" : bins);
        }
    }
    return md;
}

}  // namespace ddmr::hil
