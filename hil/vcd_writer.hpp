#pragma once
// VcdWriter: a Value Change Dump (IEEE 1364-2005, section 18) that GTKWave
// opens, written from events stamped in AVR cycles.
//
// Why our own writer and not simavr's avr_vcd: several HIL signals are
// synthesised with timestamps that are not the current simavr cycle: the PWM
// enable edges come from the phase-correct PWM triangle that simavr 1.6 does
// not emulate (they are known for a whole coupling step ahead), UART line bits
// span the frame's future, an ISR ends at the end of its RETI (4 cycles after
// simavr reports it). simavr 1.6's VCD samples IRQ values at the current cycle
// only, behaves with at most 32 signals and has its own timescale.
//
// Time: `$timescale 1ns $end`; an event at AVR cycle c is written at
//   t_ns = floor(c x 1e9 / clock_hz)   (integer arithmetic; 16 MHz: c x 125 / 2)
//
// Use: declare every signal (add_wire, add_vector) with its initial value,
// then report changes with change(signal, cycle, value). Events may arrive
// out of time order: they are buffered and written in (cycle, declaration
// order, arrival order) once the caller calls flush(up_to), promising that no
// later event will be stamped before `up_to`; an event stamped before an
// earlier flush's `up_to` is a caller bug (std::logic_error). finish(end)
// writes what is left up to `end` and closes the dump at `end`.
// A change to the value the signal already has is not written.
//
// Window (VcdWindow): only [begin_cycle, end_cycle] is written; events before
// the window set the initial values dumped at its start ($dumpvars at the
// window's first timestamp), events after it are dropped. With last_cycles =
// N the writer keeps the events of the last N cycles in memory and writes the
// whole file in finish(): "the last N cycles before the end" (e.g. before a
// crash) without knowing the end in advance.
//
// Output: text chunks to a sink (a file, a string), header first. No $date:
// the same events give the same bytes. Not thread-safe; change() does not
// allocate once the event buffer has grown to the run's steady state.

#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "hil/cycle_time.hpp"

namespace ddmr::hil {

/// Receives the VCD text in order, in chunks.
using VcdSink = std::function<void(std::string_view)>;

/// Which part of the run the VCD shows (cycles, inclusive).
struct VcdWindow {
    static constexpr Cycles kNoEnd = ~Cycles{0};
    Cycles begin_cycle = 0;     ///< first cycle shown
    Cycles end_cycle = kNoEnd;  ///< last cycle shown
    /// > 0: only the last `last_cycles` cycles before finish() (and inside
    /// [begin_cycle, end_cycle]); the file is written by finish().
    Cycles last_cycles = 0;
};

struct VcdConfig {
    uint32_t clock_hz = 0;                ///< the board's clock [Hz], > 0 (AvrCore::clock_hz())
    std::string top_scope = "ddmr_hil";  ///< enclosing $scope module
    VcdWindow window{};
};

class VcdWriter {
public:
    using SignalId = uint32_t;

    /// Throws std::invalid_argument for a zero clock, an empty top scope or
    /// a window with end before begin.
    VcdWriter(VcdSink sink, VcdConfig config = {});
    VcdWriter(const VcdWriter&) = delete;
    VcdWriter& operator=(const VcdWriter&) = delete;

    /// Declares a 1-bit signal in `scope` (a $scope module below the top
    /// one). Names and scopes: non-empty, no whitespace (std::invalid_argument).
    /// Only before the first flush (std::logic_error).
    SignalId add_wire(const std::string& scope, const std::string& name, bool initial);
    /// Declares a `width`-bit (1..64) vector signal, shown as [width-1:0].
    SignalId add_vector(const std::string& scope, const std::string& name, unsigned width, uint64_t initial);
    /// A line for the header's $comment (what the signals mean).
    void add_comment(std::string line);

    /// `signal` takes `value` (masked to its width) from `cycle` on.
    /// Throws std::logic_error if `cycle` is before what was already flushed,
    /// after finish(), or for an unknown signal.
    void change(SignalId signal, Cycles cycle, uint64_t value);
    /// Writes the buffered events stamped before `up_to`; from now on every
    /// event must be at or after it. A smaller `up_to` than before is a no-op.
    void flush(Cycles up_to);
    /// Writes the remaining events stamped at or before `end_cycle`, drops
    /// later ones, and ends the dump with a timestamp at `end_cycle` (or the
    /// window's end). Further calls do nothing.
    void finish(Cycles end_cycle);

    /// floor(cycle x 1e9 / clock_hz) without overflow for any 64-bit cycle
    /// count whose result fits.
    static uint64_t cycles_to_ns(Cycles cycle, uint32_t clock_hz);
    /// The identifier code of the signal declared `index`-th: printable ASCII
    /// '!'..'~' in bijective base 94 ("!", ..., "~", "!!", "\"!", ...).
    static std::string identifier(std::size_t index);

    std::size_t signal_count() const { return signals_.size(); }
    /// Events buffered (not yet flushed, or held for a last-cycles window).
    std::size_t buffered() const { return pending_.size() + retained_.size(); }
    Cycles flushed_up_to() const { return flushed_; }
    bool finished() const { return finished_; }

private:
    struct Signal {
        std::string scope;
        std::string name;
        unsigned width = 1;
        uint64_t value = 0;  ///< as of the last event written or folded
        std::string id;
    };
    struct Event {
        Cycles cycle = 0;
        SignalId signal = 0;
        uint64_t seq = 0;
        uint64_t value = 0;
    };
    SignalId add(const std::string& scope, const std::string& name, unsigned width, uint64_t initial);
    void process(const Event& e);   // streaming: fold, write or drop
    void fold(const Event& e) { signals_[e.signal].value = e.value; }
    void write_event(const Event& e);
    void write_header(Cycles start);
    void write_value(const Signal& s);
    void write_time(Cycles cycle);
    void drain(bool force);
    bool tail_mode() const { return config_.window.last_cycles > 0; }

    VcdSink sink_;
    VcdConfig config_;
    std::vector<Signal> signals_;
    std::vector<std::string> comments_;
    std::vector<Event> pending_;   ///< not yet flushed, any order
    std::deque<Event> retained_;   ///< last-cycles window: flushed, in order
    std::string out_;
    uint64_t seq_ = 0;
    Cycles flushed_ = 0;
    bool started_ = false;   ///< first flush done: no more declarations
    bool header_written_ = false;
    bool finished_ = false;
    bool have_time_ = false;
    uint64_t last_ns_ = 0;
};

}  // namespace ddmr::hil
