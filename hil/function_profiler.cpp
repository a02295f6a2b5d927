// FunctionProfiler: per-instruction self/inclusive cycles and a shadow call stack.
#include "hil/function_profiler.hpp"

#include <sim_avr.h>

#include <stdexcept>


namespace ddmr::hil {
namespace {

/// What an instruction does to the call stack (AVR instruction set manual).
enum Flow : uint8_t { kOther, kReturn, kCall2, kCall4 };

Flow decode(uint16_t w) {
    if (w == 0x9508 || w == 0x9518) return kReturn;      // RET, RETI
    if ((w & 0xFE0E) == 0x940E) return kCall4;           // CALL k (2 words)
    if ((w & 0xF000) == 0xD000) return kCall2;           // RCALL k
    if (w == 0x9509 || w == 0x9519) return kCall2;       // ICALL, EICALL
    return kOther;
}

/// The bottom frame's SP at entry: above any real SP, so it is never popped.
constexpr uint16_t kRootSp = 0xFFFF;

}  // namespace

FunctionProfiler::FunctionProfiler(AvrCore& core, std::size_t max_depth)
    : core_(core),
      avr_(core.raw()),
      map_(core.elf(), core.mcu()),
      word_mask_(core.mcu().flash_bytes / 2 - 1),
      vector_slot_(static_cast<uint32_t>(core.mcu().vector_bytes)),
      vectors_end_(static_cast<uint32_t>(core.mcu().vector_count()) * vector_slot_),
      ram_end_(core.mcu().ram_end),
      return_bytes_(core.mcu().pc_bytes),
      max_depth_(max_depth) {
    if (max_depth_ < 2) throw std::invalid_argument("FunctionProfiler: max_depth must be >= 2");
    const uint32_t flash = core.mcu().flash_bytes;
    if ((flash & (flash - 1)) != 0) throw std::logic_error("FunctionProfiler: the flash size is not a power of two");
    stack_.resize(max_depth_);
    level_cycles_.assign(max_depth_ + 1, 0);
    // The firmware is loaded (and flash never changes: no SPM): decode once.
    flow_.assign(flash / 2, kOther);
    for (uint32_t a = 0; a + 1 < flash; a += 2) flow_[a >> 1] = decode(core_.flash_word(a));
    whole_.functions.assign(map_.size(), FunctionCounts{});
    loop_.functions.assign(map_.size(), FunctionCounts{});
    window_start_.assign(map_.size(), FunctionCounts{});
    whole_.word_cycles.assign(flash / 2, 0);
    loop_.word_cycles.assign(flash / 2, 0);
    window_word_cycles_.assign(flash / 2, 0);
    window_words_.reserve(flash / 2);  // each word at most once per window: no reallocation
    compute_.functions.assign(map_.size(), FunctionCounts{});
    compute_.word_cycles.assign(flash / 2, 0);
    window_compute_word_cycles_.assign(flash / 2, 0);
    window_compute_words_.reserve(flash / 2);
    site_edge_.assign(flash / 2, 0);
    last_pc_ = core_.pc();
    last_sp_ = core_.stack_pointer();
    last_cycle_ = core_.cycle();
    const FunctionId root = map_.at(last_pc_);
    stack_[0] = Frame{root, kRootSp, 0, false, false, true, false, 0,
                      edge_index(CallEdge::kNoCaller, root, CallEdge::kNoSite)};
    depth_ = 1;
    max_depth_seen_ = 1;
    core_.add_instruction_hook(this, [this] { on_instruction(); }, AvrCore::HookReads::kPcSpCycle);
}

FunctionProfiler::~FunctionProfiler() { core_.remove_instruction_hook(this); }

std::vector<FunctionId> FunctionProfiler::call_stack() const {
    std::vector<FunctionId> ids;
    for (std::size_t i = 0; i < depth_; ++i) ids.push_back(stack_[i].function);
    return ids;
}

void FunctionProfiler::on_instruction() {
    const Cycles now = avr_->cycle;
    const uint32_t pc = avr_->pc;
    const uint16_t sp = core_.stack_pointer();
    // Already accounted (on_loop_boundary() may run first in the same step).
    if (now == last_cycle_ && pc == last_pc_ && sp == last_sp_) return;
    const Cycles delta = now - last_cycle_;

    // The instruction at last_pc_ ran in the context of the current stack.
    whole_.functions[map_.at(last_pc_)].self_cycles += delta;
    const uint32_t word = (last_pc_ >> 1) & word_mask_;
    whole_.word_cycles[word] += delta;
    if (delta != 0) {
        if (window_word_cycles_[word] == 0) window_words_.push_back(word);
        window_word_cycles_[word] += delta;
        if (wait_frames_ == 0) {  // outside the loop's wait: compute
            if (window_compute_word_cycles_[word] == 0) window_compute_words_.push_back(word);
            window_compute_word_cycles_[word] += delta;
            window_compute_cycles_ += delta;
            if (level_ != 0) window_compute_interrupt_cycles_ += delta;
        }
    }
    whole_.cycles += delta;
    level_cycles_[level_] += delta;  // inclusive, settled when frames close
    if (level_ != 0) whole_.interrupt_cycles += delta;

    update_stack(last_pc_, last_sp_, pc, sp);
    last_pc_ = pc;
    last_sp_ = sp;
    last_cycle_ = now;
}

void FunctionProfiler::update_stack(uint32_t prev_pc, uint16_t prev_sp, uint32_t pc, uint16_t sp) {
    // Most instructions stay in their function and touch no frame.
    const auto flow = static_cast<Flow>(flow_[(prev_pc >> 1) & word_mask_]);
    if (flow == kOther && map_.at(pc) == stack_[depth_ - 1].function && !is_interrupt_vector(pc)) {
        return;
    }
    // An interrupt taken at the end of this step pushed the address of the
    // next instruction: the instruction's own result is that PC and SP + the
    // return address's bytes (2, or 3 with a 22-bit PC).
    const bool interrupt = is_interrupt_vector(pc) && sp <= prev_sp &&
                           sp + return_bytes_ <= ram_end_;
    uint32_t next_pc = pc;
    uint16_t next_sp = sp;
    if (interrupt) {
        next_sp = static_cast<uint16_t>(sp + return_bytes_);
        next_pc = core_.return_address_at(sp + 1U);
    }

    if (flow == kReturn && next_sp > prev_sp) {
        std::size_t keep = depth_;
        while (keep > 1 && stack_[keep - 1].sp_at_entry < next_sp) --keep;
        pop_to(keep);
    } else if ((flow == kCall2 || flow == kCall4) && next_sp + return_bytes_ == prev_sp &&
               next_pc != prev_pc + (flow == kCall4 ? 4U : 2U)) {
        push(map_.at(next_pc), next_sp, /*is_interrupt=*/false, /*is_tail=*/false, /*count_call=*/true, prev_pc);
    }
    follow_transfer(prev_pc, next_pc);

    if (interrupt) {
        // Its call is counted for the handler, when the vector jumps to it.
        push(map_.at(pc), sp, /*is_interrupt=*/true, /*is_tail=*/false, /*count_call=*/false, CallEdge::kNoSite);
        stack_[depth_ - 1].awaiting_handler = true;
    }
}

void FunctionProfiler::follow_transfer(uint32_t site, uint32_t pc) {
    const FunctionId target = map_.at(pc);
    Frame& top = stack_[depth_ - 1];
    if (top.function == target) return;
    if (top.awaiting_handler) {  // the vector's JMP to its handler
        close(top);
        top.inclusive_start = level_cycles_[top.level];
        top.function = target;
        top.awaiting_handler = false;
        top.edge = edge_index(CallEdge::kNoCaller, target, CallEdge::kNoSite);
        ++whole_.functions[target].calls;
        ++whole_.edges[top.edge].calls;
        return;
    }
    // Back into a function of the current tail group?
    for (std::size_t i = depth_; i-- > 0;) {
        if (stack_[i].function == target) {
            pop_to(i + 1);
            return;
        }
        if (!stack_[i].is_tail) break;
    }
    // Into the middle of a function: not a call but a shared tail of
    // hand-written code. The tail frame keeps the stack right; no call counted.
    const bool entry = map_.is_entry(pc);
    if (!entry) ++mid_function_branches_;
    push(target, top.sp_at_entry, /*is_interrupt=*/false, /*is_tail=*/true, /*count_call=*/entry, site);
}

uint32_t FunctionProfiler::edge_index(FunctionId caller, FunctionId callee, uint32_t site) {
    const bool has_site = site != CallEdge::kNoSite;
    const uint32_t word = (site >> 1) & word_mask_;
    if (has_site && site_edge_[word] != 0) {  // most sites always call the same function
        const uint32_t cached = site_edge_[word] - 1;
        const CallEdge& e = edges_[cached];
        if (e.site == site && e.caller == caller && e.callee == callee) return cached;
    }
    const uint64_t key = (uint64_t{site} << 32) | (uint64_t{caller} << 16) | callee;
    const auto [it, added] = edge_ids_.try_emplace(key, static_cast<uint32_t>(edges_.size()));
    if (added) {
        edges_.push_back(CallEdge{caller, callee, site});
        whole_.edges.emplace_back();
    }
    if (has_site) site_edge_[word] = it->second + 1;
    return it->second;
}

void FunctionProfiler::push(FunctionId function, uint16_t sp_at_entry, bool is_interrupt, bool is_tail,
                            bool count_call, uint32_t site) {
    bool replaced_base = false;
    if (depth_ == max_depth_) {  // the new frame replaces the top one
        ++overflows_;
        --depth_;
        if (stack_[depth_].function == wait_function_) --wait_frames_;
        close(stack_[depth_]);
        replaced_base = depth_ == context_base_ && context_base_ != 0;
    }
    const uint32_t edge = is_interrupt ? edge_index(CallEdge::kNoCaller, function, CallEdge::kNoSite)
                                       : edge_index(stack_[depth_ - 1].function, function, site);
    if (count_call) {
        ++whole_.functions[function].calls;
        ++whole_.edges[edge].calls;
    }
    const uint16_t level = static_cast<uint16_t>(stack_[depth_ - 1].level + (is_interrupt ? 1 : 0));
    stack_[depth_] =
        Frame{function, sp_at_entry, level, is_interrupt, is_tail, true, false, level_cycles_[level], edge};
    ++depth_;
    if (function == wait_function_) ++wait_frames_;
    level_ = level;
    if (depth_ > max_depth_seen_) max_depth_seen_ = depth_;
    if (is_interrupt) {
        context_base_ = depth_ - 1;
    } else if (replaced_base) {
        find_context_base();
    }
    set_inclusive_flag(depth_ - 1);
}

void FunctionProfiler::pop_to(std::size_t depth) {
    while (depth_ > depth) {
        --depth_;
        if (stack_[depth_].function == wait_function_) --wait_frames_;
        close(stack_[depth_]);
    }
    level_ = stack_[depth_ - 1].level;
    if (context_base_ >= depth_) find_context_base();
}

void FunctionProfiler::close(const Frame& f) {
    if (f.counts_inclusive) {
        const Cycles cycles = level_cycles_[f.level] - f.inclusive_start;
        whole_.functions[f.function].inclusive_cycles += cycles;
        whole_.edges[f.edge].inclusive_cycles += cycles;
    }
}

void FunctionProfiler::find_context_base() {
    context_base_ = 0;
    for (std::size_t i = depth_; i-- > 1;) {
        if (stack_[i].is_interrupt) {
            context_base_ = i;
            return;
        }
    }
}

void FunctionProfiler::set_inclusive_flag(std::size_t index) {
    Frame& f = stack_[index];
    f.counts_inclusive = true;
    if (f.is_interrupt) return;
    for (std::size_t i = context_base_; i < index; ++i) {
        if (stack_[i].function == f.function) {
            f.counts_inclusive = false;
            return;
        }
    }
}

void FunctionProfiler::settle_open_frames() {
    for (std::size_t i = 0; i < depth_; ++i) {
        Frame& f = stack_[i];
        close(f);
        f.inclusive_start = level_cycles_[f.level];
    }
}

ProfileScope FunctionProfiler::whole_run() const {
    ProfileScope s = whole_;
    for (std::size_t i = 0; i < depth_; ++i) {
        const Frame& f = stack_[i];
        if (!f.counts_inclusive) continue;
        const Cycles cycles = level_cycles_[f.level] - f.inclusive_start;
        s.functions[f.function].inclusive_cycles += cycles;
        s.edges[f.edge].inclusive_cycles += cycles;
    }
    return s;
}

void FunctionProfiler::set_wait_function(FunctionId function) {
    if (function >= map_.size()) throw std::invalid_argument("FunctionProfiler: no such wait function");
    wait_function_ = function;
    wait_frames_ = 0;
    for (std::size_t i = 0; i < depth_; ++i) {
        if (stack_[i].function == function) ++wait_frames_;
    }
}

void FunctionProfiler::on_loop_boundary(bool completed) {
    on_instruction();  // account the step that returned from the mark, if not yet
    settle_open_frames();
    if (completed && window_open_) {
        for (std::size_t id = 0; id < whole_.functions.size(); ++id) {
            const FunctionCounts& now = whole_.functions[id];
            const FunctionCounts& start = window_start_[id];
            FunctionCounts& acc = loop_.functions[id];
            acc.calls += now.calls - start.calls;
            acc.self_cycles += now.self_cycles - start.self_cycles;
            acc.inclusive_cycles += now.inclusive_cycles - start.inclusive_cycles;
        }
        loop_.edges.resize(whole_.edges.size());
        for (std::size_t e = 0; e < whole_.edges.size(); ++e) {
            const EdgeCounts start = e < window_start_edges_.size() ? window_start_edges_[e] : EdgeCounts{};
            loop_.edges[e].calls += whole_.edges[e].calls - start.calls;
            loop_.edges[e].inclusive_cycles += whole_.edges[e].inclusive_cycles - start.inclusive_cycles;
        }
        for (const uint32_t word : window_words_) loop_.word_cycles[word] += window_word_cycles_[word];
        if (has_wait_function()) {
            for (const uint32_t word : window_compute_words_) {
                const Cycles c = window_compute_word_cycles_[word];
                compute_.word_cycles[word] += c;
                compute_.functions[map_.at(word << 1)].self_cycles += c;
            }
            compute_.cycles += window_compute_cycles_;
            compute_.interrupt_cycles += window_compute_interrupt_cycles_;
            ++compute_.iterations;
        }
        loop_.cycles += whole_.cycles - window_start_cycles_;
        loop_.interrupt_cycles += whole_.interrupt_cycles - window_start_interrupt_cycles_;
        ++loop_.iterations;
    }
    for (const uint32_t word : window_words_) window_word_cycles_[word] = 0;
    window_words_.clear();
    for (const uint32_t word : window_compute_words_) window_compute_word_cycles_[word] = 0;
    window_compute_words_.clear();
    window_compute_cycles_ = 0;
    window_compute_interrupt_cycles_ = 0;
    window_start_ = whole_.functions;  // same size: no allocation
    window_start_edges_ = whole_.edges;  // reallocates only when edges were added
    window_start_cycles_ = whole_.cycles;
    window_start_interrupt_cycles_ = whole_.interrupt_cycles;
    window_open_ = true;
}

}  // namespace ddmr::hil
