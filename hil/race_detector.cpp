#include "hil/race_detector.hpp"

#include <sim_avr.h>
#include <sim_interrupts.h>
#include <sim_irq.h>

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "hil/avr_decode.hpp"

namespace ddmr::hil {
namespace {

/// Pointer registers with a "known" flag each, as the walks track them.
struct Pointers {
    std::array<uint16_t, 3> value{};  ///< X, Y, Z
    std::array<bool, 3> known{true, true, true};
};

std::size_t index_of(avr::Pointer p) { return static_cast<std::size_t>(p) - 1; }

/// The pointer pair a register belongs to (r26..r31), if any.
std::optional<std::size_t> pair_of(uint8_t reg) {
    if (reg < 26) return std::nullopt;
    return static_cast<std::size_t>((reg - 26) / 2);
}

uint32_t bit(unsigned n) { return 1U << n; }
VectorMask vector_bit(int vector) { return VectorMask{1} << static_cast<unsigned>(vector); }

/// Flash byte address of the instruction that ends just before `pc`, or
/// nullopt at the start of flash. Unambiguous on the ATmega328P: the second
/// word of a two-word instruction (an LDS/STS address <= RAMEND, a CALL/JMP
/// word address < 0x4000) is never the first word of a two-word one.
std::optional<uint32_t> previous_instruction(const AvrCore& core, uint32_t pc) {
    if (pc >= 4 && avr::instruction_words(core.flash_word(pc - 4)) == 2) return pc - 4;
    if (pc >= 2) return pc - 2;
    return std::nullopt;
}

}  // namespace

namespace {

/// The walks of walk_accesses into a fixed array (callbacks do not allocate).
struct Walk {
    std::array<WalkAccess, static_cast<std::size_t>(2 * RaceDetector::kMaxWalk)> items{};
    std::size_t count = 0;
    bool seen(uint16_t address) const {
        for (std::size_t i = 0; i < count; ++i) {
            if (items[i].address == address) return true;
        }
        return false;
    }
};

Walk walk(const AvrCore& core, uint32_t resume_pc, const PointerRegs& regs, bool stores) {
    Walk w;
    // Forward: what runs after RETI. State = pointers before the instruction.
    {
        Pointers p;
        p.value = {regs.x, regs.y, regs.z};
        uint32_t pc = resume_pc;
        for (int n = 0; n < RaceDetector::kMaxWalk; ++n) {
            const auto a = avr::decode_data_access(core.flash_word(pc), core.flash_word(pc + 2));
            if (!a || a->store != stores) break;
            uint16_t address = a->k;
            if (a->pointer != avr::Pointer::kNone) {
                const std::size_t b = index_of(a->pointer);
                if (!p.known[b]) break;
                p.value[b] = static_cast<uint16_t>(p.value[b] + a->pre);
                address = static_cast<uint16_t>(p.value[b] + a->q);
                p.value[b] = static_cast<uint16_t>(p.value[b] + a->post);
            }
            if (w.seen(address)) break;  // the next access to the same byte
            w.items[w.count++] = WalkAccess{address, pc, a->reg, false};
            if (!a->store) {
                if (const auto pair = pair_of(a->reg)) p.known[*pair] = false;
            }
            pc += 2 * a->words;
        }
    }
    // Backward: what just ran. State = pointers after the instruction.
    {
        Pointers p;
        p.value = {regs.x, regs.y, regs.z};
        uint32_t pc = resume_pc;
        for (int n = 0; n < RaceDetector::kMaxWalk; ++n) {
            const auto start = previous_instruction(core, pc);
            if (!start) break;
            const auto a = avr::decode_data_access(core.flash_word(*start), core.flash_word(*start + 2));
            if (!a || a->store != stores || *start + 2 * a->words != pc) break;
            // A load overwrote its destination: a pointer it belongs to is
            // unknown before it (and for its own address).
            if (!a->store) {
                if (const auto pair = pair_of(a->reg)) p.known[*pair] = false;
            }
            uint16_t address = a->k;
            if (a->pointer != avr::Pointer::kNone) {
                const std::size_t b = index_of(a->pointer);
                if (!p.known[b]) break;
                p.value[b] = static_cast<uint16_t>(p.value[b] - a->post);  // undo X+
                address = static_cast<uint16_t>(p.value[b] + a->q);
                p.value[b] = static_cast<uint16_t>(p.value[b] - a->pre);  // undo -X
            }
            if (w.seen(address)) break;  // an earlier access to the same byte
            w.items[w.count++] = WalkAccess{address, *start, a->reg, true};
            pc = *start;
        }
    }
    return w;
}

}  // namespace

std::vector<WalkAccess> walk_accesses(const AvrCore& core, uint32_t resume_pc, const PointerRegs& regs,
                                      bool stores) {
    const Walk w = walk(core, resume_pc, regs, stores);
    std::vector<WalkAccess> out;
    // Backward items first (nearest first), then forward ones.
    for (std::size_t i = 0; i < w.count; ++i) {
        if (w.items[i].before) out.push_back(w.items[i]);
    }
    for (std::size_t i = 0; i < w.count; ++i) {
        if (!w.items[i].before) out.push_back(w.items[i]);
    }
    return out;
}

ReadSplit find_read_split(const AvrCore& core, uint32_t resume_pc, const PointerRegs& regs, uint16_t address,
                          uint16_t size) {
    ReadSplit split;
    const Walk w = walk(core, resume_pc, regs, false);
    for (std::size_t i = 0; i < w.count; ++i) {
        const WalkAccess& a = w.items[i];
        if (a.address < address || a.address >= address + size) continue;
        const auto b = static_cast<uint8_t>(1U << (a.address - address));
        (a.before ? split.before : split.after) |= b;
    }
    return split;
}

std::optional<StaleLoop> find_stale_loop(const AvrCore& core, const DataObjects& objects, uint32_t resume_pc) {
    using Kind = avr::Flow::Kind;
    // The loop: a backward branch or jump ahead of the resume address whose
    // target is at or before it.
    std::optional<uint32_t> begin;
    uint32_t end = 0;
    {
        uint32_t pc = resume_pc;
        for (int n = 0; n < RaceDetector::kMaxLoop && !begin; ++n) {
            const uint16_t w0 = core.flash_word(pc);
            const avr::Flow f = avr::decode_flow(w0, core.flash_word(pc + 2), pc);
            switch (f.kind) {
                case Kind::kJump:
                case Kind::kBranch:
                    if (*f.target <= resume_pc && *f.target + 2 * RaceDetector::kMaxLoop >= resume_pc) {
                        begin = *f.target;
                        end = pc;
                    } else if (f.kind == Kind::kJump) {
                        return std::nullopt;  // leaves: not a loop around the resume address
                    }
                    break;
                case Kind::kCall:
                case Kind::kIndirectJump:
                case Kind::kReturn:
                    return std::nullopt;
                case Kind::kNext:
                case Kind::kSkip:
                    break;
            }
            pc += 2 * avr::instruction_words(w0);
        }
    }
    if (!begin) return std::nullopt;
    // The body reads no data memory, calls nothing, and uses only registers.
    uint32_t body_reads = 0;
    uint32_t body_writes = 0;
    for (uint32_t pc = *begin; pc <= end;) {
        const uint16_t w0 = core.flash_word(pc);
        if (avr::reads_data_memory(w0)) return std::nullopt;
        const Kind k = avr::decode_flow(w0, core.flash_word(pc + 2), pc).kind;
        if (k == Kind::kCall || k == Kind::kIndirectJump || k == Kind::kReturn) return std::nullopt;
        const avr::RegisterUse use = avr::register_use(w0);
        if (!use.known) return std::nullopt;
        body_reads |= use.reads;
        body_writes |= use.writes;
        pc += 2 * avr::instruction_words(w0);
    }
    // Backwards from the loop's entry: an LDS whose register is still live
    // there (read by the branch into the loop or by the loop) and that the
    // body never writes (so the loop cannot change what it tests).
    uint32_t live = body_reads;
    uint32_t pc = *begin;
    for (int n = 0; n < RaceDetector::kMaxWalk; ++n) {
        const auto start = previous_instruction(core, pc);
        if (!start) break;
        const uint16_t w0 = core.flash_word(*start);
        const uint16_t w1 = core.flash_word(*start + 2);
        const avr::Flow f = avr::decode_flow(w0, w1, *start);
        if (f.kind == Kind::kJump) {
            // Only a jump that a skip instruction just before it jumps over
            // leads into what follows it.
            const auto skip = previous_instruction(core, *start);
            if (!skip || avr::decode_flow(core.flash_word(*skip), core.flash_word(*skip + 2), *skip).kind != Kind::kSkip) {
                break;
            }
            pc = *start;
            continue;
        }
        if (f.kind == Kind::kCall || f.kind == Kind::kIndirectJump || f.kind == Kind::kReturn) break;
        if (const auto a = avr::decode_data_access(w0, w1);
            a && !a->store && a->pointer == avr::Pointer::kNone && (live & bit(a->reg)) != 0 &&
            (body_writes & bit(a->reg)) == 0) {
            if (const auto o = objects.at(a->k)) return StaleLoop{*o, *start, a->reg, *begin, end};
        }
        const avr::RegisterUse use = avr::register_use(w0);
        if (!use.known) break;
        // Only what the loop depends on stays live: an instruction's inputs
        // when it computes a live register, a skip's or branch's operands
        // (they decide whether the loop is entered).
        if ((use.writes & live) != 0 || f.kind == Kind::kSkip || f.kind == Kind::kBranch) {
            live = (live & ~use.writes) | use.reads;
        }
        pc = *start;
    }
    return std::nullopt;
}

uint64_t SplitAccess::total_splits() const {
    uint64_t n = 0;
    for (const uint64_t s : splits) n += s;
    return n;
}

RaceDetector::RaceDetector(AvrCore& core, const ElfImage& elf, std::size_t record_capacity)
    : core_(core),
      objects_(elf, core.mcu()),
      isr_writers_(objects_.size(), 0),
      isr_readers_(objects_.size(), 0),
      written_in_(objects_.size(), 0),
      isr_pcs_((core.mcu().flash_bytes / 2 + 63) / 64, 0) {
    pending_.reserve(2 * static_cast<std::size_t>(kMaxWalk));
    accesses_.reserve(record_capacity);
    stale_.reserve(record_capacity);
    avr_t* avr = core_.raw();
    const int vectors = core_.mcu().vector_count();
    if (vectors > kMaxVectors) throw std::logic_error("RaceDetector: more vectors than a VectorMask holds");
    hooks_.reserve(static_cast<std::size_t>(vectors));
    for (int vec = 1; vec < vectors; ++vec) {
        avr_irq_t* irqs = avr_get_interrupt_irq(avr, static_cast<uint8_t>(vec));
        if (irqs == nullptr) continue;  // a vector simavr's core does not declare is never raised
        hooks_.push_back(Hook{this, vec, irqs + AVR_INT_IRQ_RUNNING});
    }
    for (Hook& h : hooks_) avr_irq_register_notify(h.irq, &RaceDetector::on_running, &h);
    core_.add_reset_listener(this, [this] {
        depth_ = 0;
        pending_.clear();
        pending_stale_.reset();
        core_.set_step_watch(nullptr, nullptr);
    });
}

RaceDetector::~RaceDetector() {
    for (Hook& h : hooks_) avr_irq_unregister_notify(h.irq, &RaceDetector::on_running, &h);
    core_.remove_reset_listener(this);
    if (depth_ > 0) core_.set_step_watch(nullptr, nullptr);
}

void RaceDetector::on_running(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    const auto* h = static_cast<const Hook*>(param);
    if (value != 0) {
        h->self->enter(h->vector);
    } else {
        h->self->leave(h->vector);
    }
}

void RaceDetector::on_step(void* self) { static_cast<RaceDetector*>(self)->step(); }

void RaceDetector::enter(int vector) {
    const int level = depth_++;
    if (level < kMaxNesting) vectors_[static_cast<std::size_t>(level)] = vector;
    if (level != 0) return;
    ++entry_serial_;
    entry_cycle_ = core_.cycle();
    entry_from_main();
    core_.set_step_watch(&RaceDetector::on_step, this);
}

void RaceDetector::leave(int /*vector*/) {
    if (depth_ == 0) return;  // a RETI whose entry came before the detector
    if (--depth_ != 0) return;
    core_.set_step_watch(nullptr, nullptr);
    finish_entry(vectors_[0]);
}

uint64_t RaceDetector::value_of(std::size_t object) const {
    const DataObject& o = objects_[object];
    uint64_t v = 0;
    for (uint16_t b = o.size; b-- > 0;) v = (v << 8) | core_.data(static_cast<uint16_t>(o.address + b));
    return v;
}

void RaceDetector::entry_from_main() {
    ++stats_.entries_checked;
    pending_.clear();
    pending_stale_.reset();
    // The vector entry pushed the return word address, high byte first, at SP+1.
    const uint16_t sp = core_.stack_pointer();
    if (sp + core_.mcu().pc_bytes > core_.mcu().ram_end) return;
    const uint32_t resume_pc = core_.return_address_at(sp + 1U);
    const auto reg16 = [&](uint16_t lo) {
        return static_cast<uint16_t>(core_.data(lo) | (core_.data(static_cast<uint16_t>(lo + 1)) << 8));
    };
    const PointerRegs regs{reg16(26), reg16(28), reg16(30)};
    for (const bool stores : {false, true}) {
        const Walk w = walk(core_, resume_pc, regs, stores);
        for (std::size_t i = 0; i < w.count; ++i) {
            const auto object = objects_.at(w.items[i].address);
            if (!object) continue;
            const DataObject& o = objects_[*object];
            if (o.size < 2 || o.size > kMaxVariableBytes) continue;
            bool done = false;  // grouped with an earlier item of the same object
            for (std::size_t j = 0; j < i && !done; ++j) done = objects_.at(w.items[j].address) == object;
            if (done) continue;
            uint8_t before = 0;
            uint8_t after = 0;
            uint32_t first_pc = w.items[i].pc;
            Pending p;
            p.object = *object;
            p.kind = stores ? AccessKind::kWrite : AccessKind::kRead;
            for (uint16_t b = 0; b < o.size; ++b) p.bytes[b] = core_.data(static_cast<uint16_t>(o.address + b));
            for (std::size_t j = i; j < w.count; ++j) {
                const WalkAccess& a = w.items[j];
                if (objects_.at(a.address) != object) continue;
                const auto byte = static_cast<unsigned>(a.address - o.address);
                (a.before ? before : after) |= static_cast<uint8_t>(1U << byte);
                first_pc = std::min(first_pc, a.pc);
                if (stores && !a.before) p.bytes[byte] = core_.data(a.reg);  // still in its register
            }
            if (before == 0 || after == 0) continue;
            p.pc = first_pc;
            p.before_mask = before;
            pending_.push_back(p);
        }
    }
    const auto cached = loop_cache_.find(resume_pc);
    if (cached != loop_cache_.end()) {
        pending_stale_ = cached->second;
    } else {
        pending_stale_ = find_stale_loop(core_, objects_, resume_pc);
        loop_cache_.emplace(resume_pc, pending_stale_);
    }
}

void RaceDetector::step() {
    const uint32_t pc = core_.pc();
    if (pc / 2 / 64 < isr_pcs_.size()) isr_pcs_[pc / 2 / 64] |= uint64_t{1} << ((pc / 2) % 64);
    const auto a = avr::decode_data_access(core_.flash_word(pc), core_.flash_word(pc + 2));
    if (!a) return;
    uint16_t address = a->k;
    if (a->pointer != avr::Pointer::kNone) {
        const auto lo = static_cast<uint16_t>(26 + 2 * index_of(a->pointer));
        const auto ptr = static_cast<uint16_t>(core_.data(lo) | (core_.data(static_cast<uint16_t>(lo + 1)) << 8));
        address = static_cast<uint16_t>(ptr + a->pre + a->q);
    }
    const auto object = objects_.at(address);
    if (!object) return;
    const int vector = vectors_[static_cast<std::size_t>(std::min(depth_, kMaxNesting) - 1)];
    if (a->store) {
        isr_writers_[*object] |= vector_bit(vector);
        written_in_[*object] = entry_serial_;
        return;
    }
    isr_readers_[*object] |= vector_bit(vector);
    for (Pending& p : pending_) {
        if (p.kind != AccessKind::kWrite || p.object != *object || p.isr_read) continue;
        p.isr_read = true;
        p.seen = value_of(p.object);
        uint64_t written = 0;
        for (uint16_t b = objects_[p.object].size; b-- > 0;) written = (written << 8) | p.bytes[b];
        p.seen_differs = p.seen != written;
    }
}

SplitAccess* RaceDetector::record(std::size_t object, AccessKind kind, uint32_t pc) {
    for (SplitAccess& a : accesses_) {
        if (a.object == object && a.kind == kind && a.pc == pc) return &a;
    }
    if (accesses_.size() == accesses_.capacity()) return nullptr;
    SplitAccess a;
    a.object = object;
    a.kind = kind;
    a.pc = pc;
    a.first_cycle = entry_cycle_;
    accesses_.push_back(a);
    return &accesses_.back();
}

void RaceDetector::finish_entry(int vector) {
    const auto v = static_cast<std::size_t>(vector);
    for (const Pending& p : pending_) {
        SplitAccess* a = record(p.object, p.kind, p.pc);
        if (a == nullptr) {
            ++stats_.dropped;
            continue;
        }
        ++a->splits[v];
        const uint16_t size = objects_[p.object].size;
        if (p.kind == AccessKind::kRead) {
            uint64_t before = 0;
            uint64_t read = 0;
            uint64_t after = 0;
            for (uint16_t b = size; b-- > 0;) {
                const uint8_t now = core_.data(static_cast<uint16_t>(objects_[p.object].address + b));
                before = (before << 8) | p.bytes[b];
                after = (after << 8) | now;
                read = (read << 8) | (((p.before_mask >> b) & 1U) != 0 ? p.bytes[b] : now);
            }
            if (before == after) continue;
            ++a->torn;
            if (read == before || read == after) continue;
            if (a->observed++ == 0) {
                a->example_before = before;
                a->example_seen = read;
                a->example_after = after;
            }
        } else if (p.isr_read) {
            ++a->torn;
            if (!p.seen_differs) continue;
            if (a->observed++ == 0) {
                uint64_t written = 0;
                for (uint16_t b = size; b-- > 0;) written = (written << 8) | p.bytes[b];
                a->example_seen = p.seen;
                a->example_after = written;
            }
        }
    }
    pending_.clear();
    if (pending_stale_ && written_in_[pending_stale_->object] == entry_serial_) {
        const StaleLoop& s = *pending_stale_;
        StaleRead* found = nullptr;
        for (StaleRead& r : stale_) {
            if (r.where.object == s.object && r.where.load_pc == s.load_pc && r.where.loop_begin == s.loop_begin) {
                found = &r;
            }
        }
        if (found == nullptr && stale_.size() < stale_.capacity()) {
            stale_.push_back(StaleRead{s, 0, 0, entry_cycle_});
            found = &stale_.back();
        }
        if (found != nullptr) {
            ++found->writes_missed;
            found->vectors |= vector_bit(vector);
        } else {
            ++stats_.dropped;
        }
    }
    pending_stale_.reset();
}

std::vector<SharedVariable> RaceDetector::shared() const {
    std::vector<SharedVariable> out;
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        if ((isr_writers_[i] | isr_readers_[i]) == 0) continue;
        out.push_back(SharedVariable{i, isr_writers_[i], isr_readers_[i]});
    }
    std::sort(out.begin(), out.end(), [this](const SharedVariable& a, const SharedVariable& b) {
        return objects_[a.object].address < objects_[b.object].address;
    });
    return out;
}

uint64_t RaceDetector::race_splits(const SplitAccess& a) const {
    const VectorMask sharers = a.kind == AccessKind::kRead ? isr_writers_[a.object] : isr_readers_[a.object];
    uint64_t n = 0;
    for (std::size_t v = 0; v < a.splits.size(); ++v) {
        if ((sharers & vector_bit(static_cast<int>(v))) != 0) n += a.splits[v];
    }
    return n;
}

bool RaceDetector::is_race(const SplitAccess& a) const { return race_splits(a) > 0; }

bool RaceDetector::ran_in_isr(uint32_t pc) const {
    const uint32_t word = pc / 2;
    if (word / 64 >= isr_pcs_.size()) return false;
    return ((isr_pcs_[word / 64] >> (word % 64)) & 1U) != 0;
}

}  // namespace ddmr::hil

namespace ddmr::hil {

std::vector<uint32_t> RaceDetector::main_sites(std::size_t object, bool stores, const FunctionMap& functions) const {
    std::vector<uint32_t> out;
    const DataObject& o = objects_[object];
    for (const FunctionInfo& f : functions.functions()) {
        if (f.name == FunctionMap::kOutsideName) continue;
        for (uint32_t pc = f.address; pc < f.end;) {
            const uint16_t w0 = core_.flash_word(pc);
            const auto a = avr::decode_data_access(w0, core_.flash_word(pc + 2));
            if (a && a->store == stores && a->pointer == avr::Pointer::kNone && a->k >= o.address &&
                a->k < o.address + o.size && !ran_in_isr(pc)) {
                out.push_back(pc);
            }
            pc += 2 * avr::instruction_words(w0);
        }
    }
    return out;
}

}  // namespace ddmr::hil
