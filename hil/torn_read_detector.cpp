#include "hil/torn_read_detector.hpp"

#include <sim_avr.h>
#include <sim_interrupts.h>
#include <sim_irq.h>

#include <fmt/format.h>

#include <optional>
#include <stdexcept>

namespace ddmr::hil {
namespace {

enum class Base { kAbsolute, kX, kY, kZ };

/// A decoded data-space load (see the header for the encodings).
struct Load {
    uint32_t words = 1;
    uint8_t rd = 0;  ///< destination register
    Base base = Base::kAbsolute;
    uint16_t k = 0;      ///< LDS address
    uint16_t q = 0;      ///< LDD displacement
    int pre = 0;         ///< -1: pre-decrement
    int post = 0;        ///< +1: post-increment
};

std::optional<Load> decode_load(uint16_t w0, uint16_t w1) {
    Load l;
    l.rd = static_cast<uint8_t>((w0 >> 4) & 0x1F);
    if ((w0 & 0xFE00) == 0x9000) {
        switch (w0 & 0x000F) {
            case 0x0: l.words = 2; l.k = w1; return l;                     // LDS Rd,k
            case 0xC: l.base = Base::kX; return l;                         // LD Rd,X
            case 0xD: l.base = Base::kX; l.post = 1; return l;             // LD Rd,X+
            case 0xE: l.base = Base::kX; l.pre = -1; return l;             // LD Rd,-X
            case 0x9: l.base = Base::kY; l.post = 1; return l;             // LD Rd,Y+
            case 0xA: l.base = Base::kY; l.pre = -1; return l;             // LD Rd,-Y
            case 0x1: l.base = Base::kZ; l.post = 1; return l;             // LD Rd,Z+
            case 0x2: l.base = Base::kZ; l.pre = -1; return l;             // LD Rd,-Z
            default: return std::nullopt;  // LPM, ELPM, POP, ...: not a data load we follow
        }
    }
    if ((w0 & 0xD200) == 0x8000) {  // LDD Rd,Y+q / Z+q: 10q0 qq0d dddd yqqq
        l.base = (w0 & 0x0008) != 0 ? Base::kY : Base::kZ;
        l.q = static_cast<uint16_t>(((w0 >> 8) & 0x20) | ((w0 >> 7) & 0x18) | (w0 & 0x07));
        return l;
    }
    return std::nullopt;
}

/// Pointer registers with a "known" flag each, as the walks track them.
struct Pointers {
    std::array<uint16_t, 3> value{};  ///< X, Y, Z
    std::array<bool, 3> known{true, true, true};
};

std::size_t index_of(Base b) { return static_cast<std::size_t>(b) - 1; }

/// The pointer pair a destination register belongs to (r26..r31), if any.
std::optional<std::size_t> pair_of(uint8_t rd) {
    if (rd < 26) return std::nullopt;
    return static_cast<std::size_t>((rd - 26) / 2);
}

}  // namespace

ReadSplit find_read_split(const AvrCore& core, uint32_t resume_pc, const PointerRegs& regs, uint16_t address,
                          uint16_t size) {
    ReadSplit split;
    const auto byte_of = [&](uint16_t a) -> std::optional<unsigned> {
        if (a < address || a >= address + size) return std::nullopt;
        return static_cast<unsigned>(a - address);
    };
    // Forward: the loads that run after RETI. State = pointers before the instruction.
    {
        Pointers p;
        p.value = {regs.x, regs.y, regs.z};
        uint32_t pc = resume_pc;
        for (int n = 0; n < TornReadDetector::kMaxWalk; ++n) {
            const auto load = decode_load(core.flash_word(pc), core.flash_word(pc + 2));
            if (!load) break;
            uint16_t a = load->k;
            if (load->base != Base::kAbsolute) {
                const std::size_t b = index_of(load->base);
                if (!p.known[b]) break;
                p.value[b] = static_cast<uint16_t>(p.value[b] + load->pre);
                a = static_cast<uint16_t>(p.value[b] + load->q);
                p.value[b] = static_cast<uint16_t>(p.value[b] + load->post);
            }
            if (const auto i = byte_of(a)) {
                const auto bit = static_cast<uint8_t>(1U << *i);
                if ((split.after & bit) != 0) break;  // the next read of the variable
                split.after |= bit;
            }
            if (const auto pair = pair_of(load->rd)) p.known[*pair] = false;
            pc += 2 * load->words;
        }
    }
    // Backward: the loads that just ran. State = pointers after the instruction.
    {
        Pointers p;
        p.value = {regs.x, regs.y, regs.z};
        uint32_t pc = resume_pc;
        for (int n = 0; n < TornReadDetector::kMaxWalk; ++n) {
            std::optional<Load> load;
            if (pc >= 4) {
                load = decode_load(core.flash_word(pc - 4), core.flash_word(pc - 2));
                if (load && load->words != 2) load.reset();
            }
            if (!load && pc >= 2) {
                load = decode_load(core.flash_word(pc - 2), 0);
                if (load && load->words != 1) load.reset();
            }
            if (!load) break;
            // The load overwrote its destination: a pointer it belongs to is
            // unknown before it (and for its own address).
            if (const auto pair = pair_of(load->rd)) p.known[*pair] = false;
            uint16_t a = load->k;
            if (load->base != Base::kAbsolute) {
                const std::size_t b = index_of(load->base);
                if (!p.known[b]) break;
                p.value[b] = static_cast<uint16_t>(p.value[b] - load->post);  // undo X+
                a = static_cast<uint16_t>(p.value[b] + load->q);
                p.value[b] = static_cast<uint16_t>(p.value[b] - load->pre);  // undo -X
            }
            if (const auto i = byte_of(a)) {
                const auto bit = static_cast<uint8_t>(1U << *i);
                if (((split.before | split.after) & bit) != 0) break;  // an earlier read
                split.before |= bit;
            }
            pc -= 2 * load->words;
        }
    }
    return split;
}

TornReadDetector::TornReadDetector(AvrCore& core, const ElfImage& elf, const TornReadConfig& config)
    : core_(core), config_(config) {
    uint32_t hooked = 0;
    for (const auto& w : config_.variables) {
        const auto sym = elf.find(w.name);
        if (!sym || !sym->is_object) {
            throw std::invalid_argument(fmt::format("TornReadDetector: '{}' is not a data object in {}", w.name,
                                                    elf.path().string()));
        }
        if (sym->size < 2 || sym->size > 8) {
            throw std::invalid_argument(
                fmt::format("TornReadDetector: '{}' has {} bytes; a torn read needs 2..8", w.name, sym->size));
        }
        if (sym->address < atmega328p::kSramStart || sym->address + sym->size - 1 > atmega328p::kRamEnd) {
            throw std::invalid_argument(
                fmt::format("TornReadDetector: '{}' at 0x{:04x} is not in SRAM", w.name, sym->address));
        }
        Var v;
        v.address = static_cast<uint16_t>(sym->address);
        v.size = static_cast<uint16_t>(sym->size);
        for (const int vec : w.writers) {
            if (vec < 1 || vec >= atmega328p::kVectorCount) {
                throw std::invalid_argument(
                    fmt::format("TornReadDetector: writer vector {} of '{}' is not in 1..25", vec, w.name));
            }
            v.writer_mask |= 1U << static_cast<unsigned>(vec);
        }
        if (w.writers.empty()) v.writer_mask = ~uint32_t{0};
        hooked |= v.writer_mask;
        vars_.push_back(v);
    }
    per_variable_.resize(vars_.size());
    pending_.resize(static_cast<std::size_t>(kMaxNesting) * vars_.size());
    records_.reserve(config_.record_capacity);
    hooks_.reserve(atmega328p::kVectorCount);
    avr_t* avr = core_.raw();
    for (int vec = 1; vec < atmega328p::kVectorCount; ++vec) {
        if ((hooked & (1U << static_cast<unsigned>(vec))) == 0) continue;
        avr_irq_t* irqs = avr_get_interrupt_irq(avr, static_cast<uint8_t>(vec));
        if (irqs == nullptr) throw std::runtime_error(fmt::format("TornReadDetector: simavr has no vector {}", vec));
        hooks_.push_back(Hook{this, vec, irqs + AVR_INT_IRQ_RUNNING});
    }
    for (Hook& h : hooks_) avr_irq_register_notify(h.irq, &TornReadDetector::on_running, &h);
}

TornReadDetector::~TornReadDetector() {
    for (Hook& h : hooks_) avr_irq_unregister_notify(h.irq, &TornReadDetector::on_running, &h);
}

void TornReadDetector::on_running(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    const auto* h = static_cast<const Hook*>(param);
    if (value != 0) {
        h->self->enter(h->vector);
    } else {
        h->self->leave(h->vector);
    }
}

void TornReadDetector::enter(int vector) {
    const int level = depth_++;
    if (level >= kMaxNesting) return;
    ++stats_.entries_checked;
    Frame& f = frames_[static_cast<std::size_t>(level)];
    f.vector = vector;
    f.entry = core_.cycle();
    f.first = static_cast<std::size_t>(level) * vars_.size();
    // The vector entry pushed the return word address: high byte at SP+1, low at SP+2.
    const uint16_t sp = core_.stack_pointer();
    if (sp + 2U > atmega328p::kRamEnd) {
        for (std::size_t i = 0; i < vars_.size(); ++i) pending_[f.first + i].active = false;
        return;
    }
    const uint32_t ret_word = (static_cast<uint32_t>(core_.data(static_cast<uint16_t>(sp + 1))) << 8) |
                              core_.data(static_cast<uint16_t>(sp + 2));
    f.resume_pc = ret_word * 2;
    const auto reg16 = [&](uint16_t lo) {
        return static_cast<uint16_t>(core_.data(lo) | (core_.data(static_cast<uint16_t>(lo + 1)) << 8));
    };
    const PointerRegs regs{reg16(26), reg16(28), reg16(30)};
    for (std::size_t i = 0; i < vars_.size(); ++i) {
        Pending& p = pending_[f.first + i];
        p.active = false;
        const Var& v = vars_[i];
        if ((v.writer_mask & (1U << static_cast<unsigned>(vector))) == 0) continue;
        const ReadSplit s = find_read_split(core_, f.resume_pc, regs, v.address, v.size);
        if (!s.split()) continue;
        ++stats_.split_reads;
        ++per_variable_[i].split_reads;
        p.active = true;
        p.before_mask = s.before;
        for (uint16_t b = 0; b < v.size; ++b) p.bytes[b] = core_.data(static_cast<uint16_t>(v.address + b));
    }
}

void TornReadDetector::leave(int vector) {
    if (depth_ == 0) return;  // a RETI whose entry came before the detector
    const int level = --depth_;
    if (level >= kMaxNesting) return;
    const Frame& f = frames_[static_cast<std::size_t>(level)];
    if (f.vector != vector) return;  // cannot happen with LIFO RETIs; be safe
    for (std::size_t i = 0; i < vars_.size(); ++i) {
        const Pending& p = pending_[f.first + i];
        if (!p.active) continue;
        const Var& v = vars_[i];
        uint64_t before = 0;
        uint64_t read = 0;
        uint64_t after = 0;
        for (uint16_t b = v.size; b-- > 0;) {
            const uint8_t now = core_.data(static_cast<uint16_t>(v.address + b));
            before = (before << 8) | p.bytes[b];
            after = (after << 8) | now;
            read = (read << 8) | (((p.before_mask >> b) & 1U) != 0 ? p.bytes[b] : now);
        }
        if (before == after) continue;
        const bool visible = read != before && read != after;
        for (TornReadStats* s : {&stats_, &per_variable_[i]}) {
            ++s->torn;
            if (visible) ++s->visible;
        }
        if (records_.size() < records_.capacity()) {
            records_.push_back(TornRead{f.entry, i, vector, f.resume_pc, p.before_mask, before, read, after, visible});
        } else {
            ++stats_.dropped;
            ++per_variable_[i].dropped;
        }
    }
}

}  // namespace ddmr::hil
