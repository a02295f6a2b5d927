#pragma once
// The reference sketch's EEPROM position log, decoded.
//
// Case 1 logs after every 10 control iterations (0.1 s of the firmware's own
// clock `t`, dt = 0.01 s):
//     EEPROM.write(addr, int(Ex*250.0)); EEPROM.write(addr+500, int(Ey*250.0)); addr += 2;
// so sample k (from 0) has its x byte at address 2k and its y byte at 2k + 500.
// Each byte is the low 8 bits of int(E*250): float product, truncation toward
// zero, then wrapped to 8 bits by EEPROM.write's uint8_t parameter. One count
// is 1/250 m = 4 mm.
//
// Unwrapping: a byte holds -128..127 counts (+-0.512 m), but case 1 tracks a
// point on a 0.6 m circle about the origin, so |x| and |y| exceed that range. The robot starts at the origin, so sample 0 is read as a signed byte;
// each later sample is the value b + 256 m (m integer) closest to the previous
// sample's value: correct while the robot moves less than 128 counts
// (0.512 m) per 0.1 s, i.e. slower than 5.12 m/s. A tie (exactly 128 counts)
// takes the lower value. The sketch's own dump prints EEPROM.read(j)/250.0
// (unsigned, not unwrapped): 0..1.02 m.
//
// Times: with no times given, sample k is stamped with the firmware's clock
// when it was logged, the nominal (k + 1) * 0.1 s after the case started (t is
// summed in float: after 1200 additions of 0.01f it reads 12.0001793 s, a
// drift of 1.8e-4 s). For measured times pass eeprom_log_timing(...) of an
// EepromWriteTiming's writes.

#include <cstdint>
#include <string>
#include <vector>

#include "hil/cycle_time.hpp"
#include "hil/eeprom_port.hpp"
#include "hil/eeprom_write_timing.hpp"

namespace ddmr::hil {

/// Layout and scale of the reference sketch's log (its case 1).
namespace eeprom_log {
inline constexpr int kAddressStride = 2;        ///< addr += 2 per sample
inline constexpr int kYOffset = 500;            ///< y byte at addr + 500
inline constexpr int kMaxSamples = kYOffset / kAddressStride;  ///< x bytes stay below 500
inline constexpr double kCountsPerMetre = 250.0;               ///< int(E * 250.0)
inline constexpr double kSamplePeriod_s = 0.1;  ///< 10 iterations of dt = 0.01 s
}  // namespace eeprom_log

/// Where and how a sketch logs (x, y) samples in the EEPROM: sample k's x
/// byte at x_address + k * stride, its y byte at y_address + k * stride,
/// each the low 8 bits of int(value * counts_per_metre), unwrapped as above
/// (sample 0 signed, then the nearest value to the previous sample) or, with
/// unwrap false, read as a signed byte each. A sketch contract gives it
/// (hil/sketch_contract.hpp); the default is the reference sketch's.
struct EepromLogLayout {
    int x_address = 0;
    int y_address = eeprom_log::kYOffset;
    int stride = eeprom_log::kAddressStride;
    double counts_per_metre = eeprom_log::kCountsPerMetre;
    bool is_signed = true;  ///< false: each byte is 0..255 counts (no unwrapping)
    bool unwrap = true;
    double sample_period_s = eeprom_log::kSamplePeriod_s;  ///< nominal time between samples [s]
    /// Samples that fit in an EEPROM of `eeprom_bytes`: the x bytes stay below
    /// the y bytes (or the EEPROM's end); 0 when a series starts past the end.
    int max_samples(int eeprom_bytes) const;
    /// The highest address the layout starts a series at.
    int last_series_start() const { return x_address > y_address ? x_address : y_address; }
};

struct EepromLogSample {
    int sample = 0;        ///< k, from 0
    double t_s = 0.0;      ///< [s] since the case started (see the header comment)
    double x_m = 0.0;      ///< [m] x_counts / 250
    double y_m = 0.0;      ///< [m] y_counts / 250
    int x_counts = 0;      ///< unwrapped int(Ex * 250)
    int y_counts = 0;      ///< unwrapped int(Ey * 250)
    uint8_t x_byte = 0;    ///< EEPROM byte at 2k
    uint8_t y_byte = 0;    ///< EEPROM byte at 2k + 500
};

/// Decodes samples 0 .. sample_count - 1 of `image`. sample_count is the
/// firmware's printed addr / 2 (or eeprom_log_timing(...).sample_count).
/// `sample_times_s` is empty (nominal times (k + 1) * 0.1 s) or holds one time
/// per sample. Throws std::invalid_argument naming the value if sample_count
/// is outside [0, 250] or the times do not match it.
std::vector<EepromLogSample> decode_eeprom_log(const EepromImage& image, int sample_count,
                                               const std::vector<double>& sample_times_s = {},
                                               const EepromLogLayout& layout = {});

/// The int value b + 256 m closest to `previous_counts` (a tie takes the
/// lower). Exposed for tests.
int unwrap_counts(uint8_t byte, int previous_counts);

/// Sample count and times recovered from recorded writes.
struct EepromLogTiming {
    int sample_count = 0;
    std::vector<double> times_s;  ///< [s] from `origin_cycle` to each sample's x-byte write
};

/// The x-byte writes (even addresses below 500) at or after `origin_cycle`
/// (the cycle the case byte was sent) give the samples: sample k at address
/// 2k, timed by its latest write. Throws std::invalid_argument naming the
/// sample if some sample below the highest one was never written.
EepromLogTiming eeprom_log_timing(const std::vector<EepromWrite>& writes, Cycles origin_cycle,
                                  uint32_t clock_hz, int eeprom_bytes, const EepromLogLayout& layout = {});

/// CSV with header "sample,t_s,x_m,y_m" and one row per sample, fixed
/// precision (6 decimals), locale-independent: the same samples give the same
/// bytes.
std::string eeprom_log_csv(const std::vector<EepromLogSample>& samples);

}  // namespace ddmr::hil
