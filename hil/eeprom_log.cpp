#include "hil/eeprom_log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>

namespace ddmr::hil {
namespace {

constexpr int kByteValues = 256;
constexpr int kHalfByte = kByteValues / 2;

/// Sample 0: the robot starts at the origin, so the byte is a signed count.
int signed_counts(uint8_t byte) { return byte < kHalfByte ? byte : byte - kByteValues; }

}  // namespace

int unwrap_counts(uint8_t byte, int previous_counts) {
    // d = (byte - previous) mod 256 in [-128, 127]: the smallest step to a
    // value with the same low 8 bits (+128 folds to -128: the lower value).
    int d = (byte - previous_counts) % kByteValues;
    if (d < 0) d += kByteValues;
    if (d >= kHalfByte) d -= kByteValues;
    return previous_counts + d;
}

int EepromLogLayout::max_samples(int eeprom_bytes) const {
    if (stride <= 0) return 0;
    const int lo = std::min(x_address, y_address);
    const int hi = std::max(x_address, y_address);
    // The lower series must stay below the upper one, the upper below the end.
    const int below_hi = hi > lo ? (hi - lo + stride - 1) / stride : 0;
    if (hi >= eeprom_bytes) return 0;
    const int below_end = (eeprom_bytes - hi + stride - 1) / stride;
    return hi > lo ? std::min(below_hi, below_end) : 0;
}

std::vector<EepromLogSample> decode_eeprom_log(const EepromImage& image, int sample_count,
                                               const std::vector<double>& sample_times_s,
                                               const EepromLogLayout& layout) {
    const int max = layout.max_samples(static_cast<int>(image.size()));
    if (sample_count < 0 || sample_count > max) {
        throw std::invalid_argument(fmt::format(
            "EEPROM log: sample count {} outside [0, {}] (x bytes from address {}, y bytes from {}, stride {}, "
            "{}-byte EEPROM)",
            sample_count, max, layout.x_address, layout.y_address, layout.stride, image.size()));
    }
    const auto n = static_cast<std::size_t>(sample_count);
    if (!sample_times_s.empty() && sample_times_s.size() != n) {
        throw std::invalid_argument(fmt::format("EEPROM log: {} sample times for {} samples",
                                                sample_times_s.size(), sample_count));
    }
    std::vector<EepromLogSample> out;
    out.reserve(n);
    for (int k = 0; k < sample_count; ++k) {
        const int x_offset = layout.x_address + k * layout.stride;
        const int y_offset = layout.y_address + k * layout.stride;
        const auto x_addr = static_cast<std::size_t>(x_offset);
        const auto y_addr = static_cast<std::size_t>(y_offset);
        EepromLogSample s;
        s.sample = k;
        s.x_byte = image[x_addr];
        s.y_byte = image[y_addr];
        if (!layout.is_signed) {
            s.x_counts = s.x_byte;
            s.y_counts = s.y_byte;
        } else if (k == 0 || !layout.unwrap) {
            s.x_counts = signed_counts(s.x_byte);
            s.y_counts = signed_counts(s.y_byte);
        } else {
            s.x_counts = unwrap_counts(s.x_byte, out.back().x_counts);
            s.y_counts = unwrap_counts(s.y_byte, out.back().y_counts);
        }
        s.x_m = s.x_counts / layout.counts_per_metre;
        s.y_m = s.y_counts / layout.counts_per_metre;
        s.t_s = sample_times_s.empty() ? (k + 1) * layout.sample_period_s
                                       : sample_times_s[static_cast<std::size_t>(k)];
        out.push_back(s);
    }
    return out;
}

EepromLogTiming eeprom_log_timing(const std::vector<EepromWrite>& writes, Cycles origin_cycle,
                                  uint32_t clock_hz, int eeprom_bytes, const EepromLogLayout& layout) {
    const int max = layout.max_samples(eeprom_bytes);
    constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();
    EepromLogTiming timing;
    for (const auto& w : writes) {
        const int offset = static_cast<int>(w.address) - layout.x_address;
        if (w.cycle < origin_cycle || offset < 0 || offset % layout.stride != 0 || offset / layout.stride >= max) {
            continue;
        }
        const auto k = static_cast<std::size_t>(offset / layout.stride);
        if (timing.times_s.size() <= k) timing.times_s.resize(k + 1, kUnset);
        timing.times_s[k] = cycles_to_s(w.cycle - origin_cycle, clock_hz);
    }
    for (std::size_t k = 0; k < timing.times_s.size(); ++k) {
        if (std::isnan(timing.times_s[k])) {
            throw std::invalid_argument(fmt::format(
                "EEPROM log: sample {} (address {}) was never written, but sample {} was", k,
                layout.x_address + static_cast<int>(k) * layout.stride, timing.times_s.size() - 1));
        }
    }
    timing.sample_count = static_cast<int>(timing.times_s.size());
    return timing;
}

std::string eeprom_log_csv(const std::vector<EepromLogSample>& samples) {
    fmt::memory_buffer csv;
    fmt::format_to(std::back_inserter(csv), "sample,t_s,x_m,y_m\n");
    for (const auto& s : samples) {
        fmt::format_to(std::back_inserter(csv), "{},{:.6f},{:.6f},{:.6f}\n", s.sample, s.t_s, s.x_m,
                       s.y_m);
    }
    return fmt::to_string(csv);
}

}  // namespace ddmr::hil
