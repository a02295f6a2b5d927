#include "hil/eeprom_log.hpp"

#include <fmt/format.h>

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

std::vector<EepromLogSample> decode_eeprom_log(const EepromImage& image, int sample_count,
                                               const std::vector<double>& sample_times_s) {
    if (sample_count < 0 || sample_count > eeprom_log::kMaxSamples) {
        throw std::invalid_argument(fmt::format(
            "EEPROM log: sample count {} outside [0, {}] (x bytes must stay below address {})",
            sample_count, eeprom_log::kMaxSamples, eeprom_log::kYOffset));
    }
    const auto n = static_cast<std::size_t>(sample_count);
    if (!sample_times_s.empty() && sample_times_s.size() != n) {
        throw std::invalid_argument(fmt::format("EEPROM log: {} sample times for {} samples",
                                                sample_times_s.size(), sample_count));
    }
    std::vector<EepromLogSample> out;
    out.reserve(n);
    for (int k = 0; k < sample_count; ++k) {
        const auto x_addr = static_cast<std::size_t>(k) * eeprom_log::kAddressStride;
        const auto y_addr = x_addr + eeprom_log::kYOffset;
        EepromLogSample s;
        s.sample = k;
        s.x_byte = image[x_addr];
        s.y_byte = image[y_addr];
        if (k == 0) {
            s.x_counts = signed_counts(s.x_byte);
            s.y_counts = signed_counts(s.y_byte);
        } else {
            s.x_counts = unwrap_counts(s.x_byte, out.back().x_counts);
            s.y_counts = unwrap_counts(s.y_byte, out.back().y_counts);
        }
        s.x_m = s.x_counts / eeprom_log::kCountsPerMetre;
        s.y_m = s.y_counts / eeprom_log::kCountsPerMetre;
        s.t_s = sample_times_s.empty() ? (k + 1) * eeprom_log::kSamplePeriod_s
                                       : sample_times_s[static_cast<std::size_t>(k)];
        out.push_back(s);
    }
    return out;
}

EepromLogTiming eeprom_log_timing(const std::vector<EepromWrite>& writes, Cycles origin_cycle,
                                  uint32_t clock_hz) {
    constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();
    EepromLogTiming timing;
    for (const auto& w : writes) {
        if (w.cycle < origin_cycle || w.address >= eeprom_log::kYOffset ||
            w.address % eeprom_log::kAddressStride != 0) {
            continue;
        }
        const auto k = static_cast<std::size_t>(w.address / eeprom_log::kAddressStride);
        if (timing.times_s.size() <= k) timing.times_s.resize(k + 1, kUnset);
        timing.times_s[k] = cycles_to_s(w.cycle - origin_cycle, clock_hz);
    }
    for (std::size_t k = 0; k < timing.times_s.size(); ++k) {
        if (std::isnan(timing.times_s[k])) {
            throw std::invalid_argument(fmt::format(
                "EEPROM log: sample {} (address {}) was never written, but sample {} was", k,
                k * eeprom_log::kAddressStride, timing.times_s.size() - 1));
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
