#pragma once
// FastForward's private types, shared by fast_forward.cpp (jumps) and
// fast_forward_learn.cpp (learning loops); not part of the interface.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hil/fast_forward.hpp"
#include "hil/mcu.hpp"

namespace ddmr::hil::ff_detail {

/// True if simavr's SREG arrays agree on the flags in `mask`.
inline bool flags_equal(uint8_t mask, const uint8_t* a, const uint8_t* b) {
    for (unsigned f = 0; f < 8; ++f) {
        if (((mask >> f) & 1U) != 0 && (a[f] != 0) != (b[f] != 0)) return false;
    }
    return true;
}

/// The first flash byte after the interrupt vectors: a PC below it is an interrupt's entry.
inline uint32_t vector_table_end(const McuDescription& mcu) {
    return static_cast<uint32_t>(mcu.vector_count() * mcu.vector_bytes);
}

}  // namespace ddmr::hil::ff_detail

namespace ddmr::hil {

struct FastForward::Loop {
    SkippedLoop info;
    uint16_t sp = 0;
    std::vector<uint32_t> pcs;
    std::vector<uint16_t> sps;        ///< per step: SP before it
    std::vector<uint32_t> step_ends;  ///< per step: cycles from the anchor to its end
    /// Per step: the bytes it accessed through a pointer register (LD/ST X,
    /// Y, Z), checked again on the verification pass; other steps' addresses
    /// follow from the path and SP.
    std::vector<StepAccess> accesses;
    std::vector<bool> through_pointer;
    /// Per step: it writes an I/O register with a simavr handler or IRQ
    /// (write_inert is checked before it on each checked pass).
    std::vector<bool> checked_write;
    std::vector<uint16_t> carried;
    uint8_t carried_flags = 0;  ///< SREG bits read before written, and written
    LoopSpan span;
    /// When its path changes; shared by the anchors of one cycle of PCs.
    std::shared_ptr<ChangeTrack> changes;
    /// The next loop anchored at the same PC at another stack depth (delay()
    /// called from setup() and from loop()), or kUnknown.
    int32_t next_at_pc = kUnknown;
    /// >= 0: not a loop but a refusal at this PC and SP (refused_'s index).
    int32_t refusal = kUnknown;
    /// Checked passes in a row that kept the path but changed a carried byte
    /// or were about to make a write that was not inert.
    unsigned futile = 0;
};

/// The changes of path of a loop whose path changes at a steady period
/// (delay() counting down a millisecond every 16,000 cycles).
struct FastForward::ChangeTrack {
    Cycles at = 0;         ///< the last change located (or assumed passed on time)
    Cycles located = 0;    ///< the last change located
    Cycles period = 0;     ///< the period, once two intervals in a row agreed
    Cycles periods = 0;    ///< how many periods `period` was measured over
    Cycles ref_at = 0;     ///< the first change located in this phase (since the period last broke)
    Cycles candidate = 0;  ///< the last interval that matched no period
    bool held = false;     ///< predict: the last interval matched the period
    unsigned blind = 0;    ///< changes assumed since the last one located
};

struct FastForward::Snapshot {
    Cycles cycle = 0;
    uint32_t pc = 0;
    uint8_t sreg[8] = {};
    int8_t interrupt_state = 0;
};

}  // namespace ddmr::hil
