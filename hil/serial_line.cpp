#include "hil/serial_line.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace ddmr::hil {

SerialLine::SerialLine(double rx_bit_cycles) : rx_bit_(rx_bit_cycles) {
    if (!(rx_bit_cycles > 0.0) || !std::isfinite(rx_bit_cycles)) {
        throw std::invalid_argument("serial line: receiver bit time must be > 0 cycles");
    }
}

bool SerialLine::level_at(double t) const {
    for (const Frame& f : frames_) {
        if (t < f.start) return true;  // idle before this frame (frames are in order)
        if (t < f.end()) {
            const auto bit = static_cast<int>(std::floor((t - f.start) / f.bit));
            if (bit == 0) return false;                  // start bit
            if (bit >= 9) return true;                   // stop bit
            return ((f.value >> (bit - 1)) & 1U) != 0U;  // data bit bit-1
        }
    }
    return true;
}

bool SerialLine::next_falling_edge(double t, double horizon, double& edge) const {
    for (const Frame& f : frames_) {
        if (f.end() <= t) continue;
        if (f.start >= horizon) return false;
        // Falling edges of a frame: its start, and every 1 -> 0 between bits.
        bool previous = true;  // the line is high before a start bit
        for (int bit = 0; bit < 10; ++bit) {
            const bool level = bit == 0 ? false : bit == 9 ? true : ((f.value >> (bit - 1)) & 1U) != 0U;
            const double at = f.start + bit * f.bit;
            if (previous && !level && at >= t) {
                if (at >= horizon) return false;
                edge = at;
                return true;
            }
            previous = level;
        }
    }
    return false;
}

void SerialLine::decode(double horizon, std::vector<LineByte>& out) {
    double edge = 0.0;
    while (next_falling_edge(search_from_, horizon, edge)) {
        const double stop_sample = edge + 9.5 * rx_bit_;
        if (stop_sample >= horizon) return;  // later frames may still change the samples
        LineByte b;
        for (int k = 0; k < 8; ++k) {
            if (level_at(edge + (k + 1.5) * rx_bit_)) b.value = static_cast<uint8_t>(b.value | (1U << k));
        }
        b.framing_error = !level_at(stop_sample);
        b.cycle = stop_sample;
        if (b.framing_error) ++framing_errors_;
        out.push_back(b);
        search_from_ = stop_sample;
        while (!frames_.empty() && frames_.front().end() <= search_from_) frames_.pop_front();
    }
}

void SerialLine::push(double start, uint8_t value, double tx_bit_cycles, std::vector<LineByte>& out) {
    if (!(tx_bit_cycles > 0.0) || !std::isfinite(tx_bit_cycles)) {
        throw std::invalid_argument("serial line: sender bit time must be > 0 cycles");
    }
    if (!frames_.empty()) start = std::max(start, frames_.back().end());
    start = std::max(start, settled_);
    // Everything the receiver samples before this frame starts is settled.
    decode(start, out);
    frames_.push_back(Frame{start, tx_bit_cycles, value});
}

void SerialLine::settle(double now, std::vector<LineByte>& out) {
    settled_ = std::max(settled_, now);
    decode(settled_, out);
}

void SerialLine::flush(std::vector<LineByte>& out) {
    decode(std::numeric_limits<double>::infinity(), out);
    frames_.clear();
}

}  // namespace ddmr::hil
