// VcdWriter: buffered, time-ordered value-change dump (see vcd_writer.hpp).
#include "hil/vcd_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <stdexcept>
#include <utility>

namespace ddmr::hil {
namespace {

constexpr uint64_t kNsPerS = 1'000'000'000;
/// Text kept before it is handed to the sink [bytes].
constexpr std::size_t kChunkBytes = std::size_t{64} * 1024;
/// Printable identifier characters: '!' (33) .. '~' (126).
constexpr std::size_t kIdAlphabet = 94;

bool valid_token(const std::string& s) {
    if (s.empty()) return false;
    return std::none_of(s.begin(), s.end(), [](char c) { return c <= ' ' || c == '\x7f'; });
}

void append_uint(std::string& out, uint64_t v) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

uint64_t width_mask(unsigned width) { return width >= 64 ? ~uint64_t{0} : (uint64_t{1} << width) - 1; }

}  // namespace

VcdWriter::VcdWriter(VcdSink sink, VcdConfig config) : sink_(std::move(sink)), config_(std::move(config)) {
    if (config_.clock_hz == 0) throw std::invalid_argument("VcdWriter: clock_hz must be > 0");
    if (!valid_token(config_.top_scope)) {
        throw std::invalid_argument("VcdWriter: top scope '" + config_.top_scope + "' is empty or has blanks");
    }
    if (config_.window.end_cycle < config_.window.begin_cycle) {
        throw std::invalid_argument("VcdWriter: window ends (cycle " + std::to_string(config_.window.end_cycle) +
                                    ") before it begins (cycle " + std::to_string(config_.window.begin_cycle) + ")");
    }
    pending_.reserve(4096);
    out_.reserve(kChunkBytes + 4096);
}

uint64_t VcdWriter::cycles_to_ns(Cycles cycle, uint32_t clock_hz) {
    // Split so that the product stays below 2^64: r < clock_hz < 2^32.
    const Cycles q = cycle / clock_hz;
    const Cycles r = cycle % clock_hz;
    return q * kNsPerS + r * kNsPerS / clock_hz;
}

std::string VcdWriter::identifier(std::size_t index) {
    std::string id;
    for (;;) {
        id.push_back(static_cast<char>('!' + index % kIdAlphabet));
        if (index < kIdAlphabet) break;
        index = index / kIdAlphabet - 1;
    }
    return id;
}

VcdWriter::SignalId VcdWriter::add(const std::string& scope, const std::string& name, unsigned width,
                                   uint64_t initial) {
    if (started_) throw std::logic_error("VcdWriter: signal '" + name + "' declared after the first flush");
    if (!valid_token(scope) || !valid_token(name)) {
        throw std::invalid_argument("VcdWriter: signal '" + scope + "." + name + "': empty or blank in the name");
    }
    if (width == 0 || width > 64) {
        throw std::invalid_argument("VcdWriter: signal '" + name + "' has width " + std::to_string(width) +
                                    ", not 1..64");
    }
    for (const Signal& s : signals_) {
        if (s.scope == scope && s.name == name) {
            throw std::invalid_argument(fmt::format("VcdWriter: signal '{}.{}' declared twice", scope, name));
        }
    }
    signals_.push_back(Signal{scope, name, width, initial & width_mask(width), identifier(signals_.size())});
    return static_cast<SignalId>(signals_.size() - 1);
}

VcdWriter::SignalId VcdWriter::add_wire(const std::string& scope, const std::string& name, bool initial) {
    return add(scope, name, 1, initial ? 1 : 0);
}

VcdWriter::SignalId VcdWriter::add_vector(const std::string& scope, const std::string& name, unsigned width,
                                          uint64_t initial) {
    return add(scope, name, width, initial);
}

void VcdWriter::add_comment(std::string line) {
    if (started_) throw std::logic_error("VcdWriter: comment added after the first flush");
    comments_.push_back(std::move(line));
}

void VcdWriter::change(SignalId signal, Cycles cycle, uint64_t value) {
    if (finished_) throw std::logic_error("VcdWriter: change after finish()");
    if (signal >= signals_.size()) {
        throw std::logic_error("VcdWriter: unknown signal " + std::to_string(signal));
    }
    if (started_ && cycle < flushed_) {
        throw std::logic_error("VcdWriter: event on '" + signals_[signal].name + "' at cycle " +
                               std::to_string(cycle) + " arrived after cycles before " + std::to_string(flushed_) +
                               " were written");
    }
    pending_.push_back(Event{cycle, signal, seq_++, value & width_mask(signals_[signal].width)});
}

void VcdWriter::flush(Cycles up_to) {
    if (finished_) return;
    started_ = true;
    if (up_to <= flushed_) return;
    const auto by_time = [](const Event& a, const Event& b) {
        if (a.cycle != b.cycle) return a.cycle < b.cycle;
        if (a.signal != b.signal) return a.signal < b.signal;
        return a.seq < b.seq;
    };
    // Only the events before up_to leave: partition them to the front, then order them.
    const auto ready_end =
        std::partition(pending_.begin(), pending_.end(), [up_to](const Event& e) { return e.cycle < up_to; });
    std::sort(pending_.begin(), ready_end, by_time);
    for (auto it = pending_.begin(); it != ready_end; ++it) {
        if (tail_mode()) {
            retained_.push_back(*it);
        } else {
            process(*it);
        }
    }
    pending_.erase(pending_.begin(), ready_end);
    flushed_ = up_to;
    if (tail_mode()) {
        // Nothing before up_to - N can be inside the last N cycles of a run
        // that ends at or after up_to: it only sets the initial values.
        const Cycles n = config_.window.last_cycles;
        while (!retained_.empty() && up_to > n && retained_.front().cycle < up_to - n) {
            fold(retained_.front());
            retained_.pop_front();
        }
    } else if (!header_written_ && up_to > config_.window.begin_cycle) {
        write_header(config_.window.begin_cycle);  // every event before begin has been folded
    }
    drain(false);
}

void VcdWriter::finish(Cycles end_cycle) {
    if (finished_) return;
    if (started_ && end_cycle + 1 < flushed_) {
        throw std::logic_error("VcdWriter: finish at cycle " + std::to_string(end_cycle) + " before the flushed " +
                               std::to_string(flushed_));
    }
    // Everything up to end_cycle is final now.
    flush(end_cycle + 1);
    pending_.clear();  // stamped after the end: dropped
    const VcdWindow& w = config_.window;
    const Cycles last = std::min(end_cycle, w.end_cycle);
    if (tail_mode()) {
        Cycles start = end_cycle >= w.last_cycles ? end_cycle - w.last_cycles : 0;
        start = std::min(std::max(start, w.begin_cycle), last);
        for (const Event& e : retained_) {
            if (e.cycle < start) {
                fold(e);
            } else if (e.cycle <= last) {
                if (!header_written_) write_header(start);
                write_event(e);
            }
        }
        retained_.clear();
        if (!header_written_) write_header(start);
    } else if (!header_written_) {
        write_header(std::min(w.begin_cycle, last));
    }
    write_time(last);
    finished_ = true;
    drain(true);
}

void VcdWriter::process(const Event& e) {
    const VcdWindow& w = config_.window;
    if (e.cycle < w.begin_cycle) {
        fold(e);
        return;
    }
    if (e.cycle > w.end_cycle) return;
    if (!header_written_) write_header(w.begin_cycle);
    write_event(e);
}

void VcdWriter::write_event(const Event& e) {
    Signal& s = signals_[e.signal];
    if (s.value == e.value) return;
    s.value = e.value;
    write_time(e.cycle);
    write_value(s);
}

void VcdWriter::write_time(Cycles cycle) {
    const uint64_t ns = cycles_to_ns(cycle, config_.clock_hz);
    if (have_time_ && ns <= last_ns_) return;
    have_time_ = true;
    last_ns_ = ns;
    out_.push_back('#');
    append_uint(out_, ns);
    out_.push_back('\n');
}

void VcdWriter::write_value(const Signal& s) {
    if (s.width == 1) {
        out_.push_back(s.value != 0 ? '1' : '0');
    } else {
        out_.push_back('b');
        int top = 63;
        while (top > 0 && ((s.value >> top) & 1U) == 0) --top;
        for (int b = top; b >= 0; --b) out_.push_back(((s.value >> b) & 1U) != 0 ? '1' : '0');
        out_.push_back(' ');
    }
    out_ += s.id;
    out_.push_back('\n');
}

void VcdWriter::write_header(Cycles start) {
    header_written_ = true;
    if (!comments_.empty()) {
        out_ += "$comment\n";
        for (const std::string& c : comments_) out_ += "  " + c + "\n";
        out_ += "$end\n";
    }
    out_ += "$timescale 1ns $end\n";
    out_ += "$scope module " + config_.top_scope + " $end\n";
    // One $scope per scope name, in the order of first declaration.
    std::vector<std::string> scopes;
    for (const Signal& s : signals_) {
        if (std::find(scopes.begin(), scopes.end(), s.scope) == scopes.end()) scopes.push_back(s.scope);
    }
    for (const std::string& scope : scopes) {
        out_ += "$scope module " + scope + " $end\n";
        for (const Signal& s : signals_) {
            if (s.scope != scope) continue;
            out_ += "$var wire " + std::to_string(s.width) + " " + s.id + " " + s.name;
            if (s.width > 1) out_ += " [" + std::to_string(s.width - 1) + ":0]";
            out_ += " $end\n";
        }
        out_ += "$upscope $end\n";
    }
    out_ += "$upscope $end\n$enddefinitions $end\n";
    write_time(start);
    out_ += "$dumpvars\n";
    for (const Signal& s : signals_) write_value(s);
    out_ += "$end\n";
}

void VcdWriter::drain(bool force) {
    if (out_.empty() || (!force && out_.size() < kChunkBytes)) return;
    if (sink_) sink_(out_);
    out_.clear();
}

}  // namespace ddmr::hil
