#pragma once
// Parameter descriptors: one table per part lists every field of its Params
// struct with its key, unit and valid range. The same table drives
// validation (this header), the YAML loader and emitter (params_yaml.hpp) and
// the defaults-equal-file test, so a range is written down exactly once.

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

namespace ddmr::plant {

/// A closed or open interval [lo, hi], (lo, hi), ... on the real line.
struct Range {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_inclusive = true;
    bool hi_inclusive = true;

    [[nodiscard]] bool contains(double v) const {
        if (!std::isfinite(v)) return false;
        const bool above = lo_inclusive ? v >= lo : v > lo;
        const bool below = hi_inclusive ? v <= hi : v < hi;
        return above && below;
    }
    /// "(0, 1000]" style text for messages.
    [[nodiscard]] std::string text() const {
        std::ostringstream os;
        os << (lo_inclusive ? '[' : '(') << lo << ", " << hi << (hi_inclusive ? ']' : ')');
        return os.str();
    }
};

/// (0, hi]: strictly positive.
inline Range positive(double hi) { return Range{0.0, hi, false, true}; }
/// [0, hi]: non-negative.
inline Range non_negative(double hi) { return Range{0.0, hi, true, true}; }

/// One field of a Params struct `P`: its YAML key, unit, range and member.
template <class P>
struct Field {
    using Member = std::variant<double P::*, int P::*, std::uint64_t P::*>;
    const char* key;
    const char* unit;
    Range range;  ///< ignored for std::uint64_t fields (any value is valid)
    Member member;
};

/// Value of a field as double (for range checks and messages).
template <class P>
double field_value(const P& p, const Field<P>& f) {
    return std::visit([&p](auto m) { return static_cast<double>(p.*m); }, f.member);
}

/// Message for an out-of-range value, naming the parameter, value and range.
inline std::string range_message(std::string_view name, double value, const Range& range,
                                 std::string_view unit) {
    std::ostringstream os;
    os.precision(17);
    os << "invalid plant parameter " << name << " = " << value << ": must be finite and in "
       << range.text() << ' ' << unit;
    return os.str();
}

/// Throws std::invalid_argument naming `prefix.key`, the value and its range
/// for the first field of `p` outside its range (NaN and inf included).
template <class P, class Table>
void validate_fields(const P& p, const Table& table, std::string_view prefix) {
    for (const Field<P>& f : table) {
        if (std::holds_alternative<std::uint64_t P::*>(f.member)) continue;
        const double v = field_value(p, f);
        if (!f.range.contains(v)) {
            throw std::invalid_argument(
                range_message(std::string(prefix) + "." + f.key, v, f.range, f.unit));
        }
    }
}

}  // namespace ddmr::plant
