#pragma once
// FirmwareVariables: reads the firmware's globals by their ELF symbol names,
// decoded as the type the caller asks for, without changing the firmware.
//
// Decoding follows avr-gcc's data layout: little-endian, no padding; int is
// 16 bits, long 32 bits; float is IEEE-754 binary32, and so is avr-gcc's
// double (it is 32-bit by default), so "double" parses as kFloat.
//
// A name is resolved once with lookup(), which checks that the symbol is a data
// object in SRAM whose size is the type's size; the Variable it returns reads
// with no string lookup and cannot throw, so it can be used from simavr
// callbacks and per-sample trace loops. Reads copy bytes from AvrCore::data()
// (avr->data), which has no side effects: it does not run read handlers.
//
// Limits: the ELF must keep the symbol. With LTO a `const` or never-written
// global is folded into code and has no symbol (the reference sketch's
// `endtime`, `Ka`, `GR`...); a file-local one may be renamed
// (`_ZL2Gd.lto_priv.31`): pass the name exactly as `avr-nm` lists it. A
// PROGMEM object cannot be told from an SRAM object by its symbol alone (the
// ELF reader drops the section); reading one returns SRAM bytes, not flash.

#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#include "hil/avr_core.hpp"
#include "hil/elf_image.hpp"

namespace ddmr::hil {

enum class VarType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat };

/// "int8", "uint8", "int16", "uint16", "int32", "uint32", "float" ("double" is
/// an alias of float, as in avr-gcc). Throws std::invalid_argument naming the
/// text and the accepted names.
VarType parse_var_type(std::string_view text);
/// The name parse_var_type accepts ("float" for kFloat).
const char* to_string(VarType type);
/// Bytes the type occupies on the AVR: 1, 2 or 4.
std::size_t var_type_size(VarType type);

/// What a 4-byte global is taken for when no type is given: the symbol table
/// cannot tell a long from a float. kFloat suits the reference sketch, whose
/// 4-byte globals are floats (`run --trace`); kNone makes the caller ask for
/// the type (a scenario's `expect-var`, where a wrong guess passes or fails a
/// check silently).
enum class FourByteDefault { kFloat, kNone };

/// The type of a `size_bytes`-byte global when none is given: 1 byte uint8,
/// 2 bytes int16 (avr-gcc's int), 4 bytes float or none per `four_bytes`;
/// std::nullopt when the size does not decide it.
std::optional<VarType> default_var_type(std::size_t size_bytes, FourByteDefault four_bytes);

// The firmware's float is binary32 and is decoded by copying its bits into a
// host float: that needs the host's float to be binary32 too.
static_assert(std::numeric_limits<float>::is_iec559 && sizeof(float) == 4,
              "decoding AVR floats needs an IEEE-754 binary32 host float");

/// The first sizeof(T) bytes, little-endian, as T (int8_t ... uint32_t, float):
/// assembled into the unsigned integer of T's width, then reinterpreted bit
/// for bit (two's complement; binary32).
template <typename T>
T decode_le(const std::array<uint8_t, 4>& bytes) {
    static_assert(sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4, "AVR scalar sizes");
    using U = std::conditional_t<sizeof(T) == 1, uint8_t,
                                 std::conditional_t<sizeof(T) == 2, uint16_t, uint32_t>>;
    uint32_t u = 0;
    for (std::size_t i = sizeof(T); i-- > 0;) u = (u << 8) | bytes[i];
    const auto narrow = static_cast<U>(u);
    T value;
    std::memcpy(&value, &narrow, sizeof value);
    return value;
}

/// Decodes `var_type_size(type)` little-endian bytes (the rest are ignored) as
/// `type`. Every value of every type is exact in a double.
double decode_var(VarType type, const std::array<uint8_t, 4>& bytes);

/// `value` as `type`'s var_type_size(type) little-endian bytes (the rest 0).
/// Throws std::invalid_argument naming the value and the type when an
/// integer type cannot hold it exactly (a fraction, out of range) or a float
/// is not finite or past binary32's range.
std::array<uint8_t, 4> encode_var(VarType type, double value);

/// The VarType of a C++ type (int8_t ... uint32_t, float).
template <typename T>
constexpr VarType var_type_of();
template <> constexpr VarType var_type_of<int8_t>() { return VarType::kInt8; }
template <> constexpr VarType var_type_of<uint8_t>() { return VarType::kUint8; }
template <> constexpr VarType var_type_of<int16_t>() { return VarType::kInt16; }
template <> constexpr VarType var_type_of<uint16_t>() { return VarType::kUint16; }
template <> constexpr VarType var_type_of<int32_t>() { return VarType::kInt32; }
template <> constexpr VarType var_type_of<uint32_t>() { return VarType::kUint32; }
template <> constexpr VarType var_type_of<float>() { return VarType::kFloat; }

/// A resolved firmware global: where it lives and how to decode it.
struct Variable {
    std::string name;       ///< ELF symbol name, for messages only
    uint16_t address = 0;   ///< data-space address of its first (lowest) byte
    uint8_t size = 0;       ///< bytes, == var_type_size(type)
    VarType type = VarType::kUint8;
};

class FirmwareVariables {
public:
    /// Keeps references: `elf` and `core` must outlive this object.
    FirmwareVariables(const ElfImage& elf, const AvrCore& core) : elf_(elf), core_(core) {}

    /// Resolves `name` as a `type`. Throws std::runtime_error naming the symbol
    /// (and the firmware file) if there is no such symbol, if it is not a data
    /// object in SRAM, or if its size is not the type's size (the message gives
    /// both sizes and the type).
    Variable lookup(const std::string& name, VarType type) const;

    /// The variable's current value. No lookup, no allocation, no throw; NaN if
    /// `var` did not come from lookup() (its size or address is invalid).
    double read(const Variable& var) const noexcept;
    /// lookup() + read(): convenient, not for hot paths.
    double read(const std::string& name, VarType type) const { return read(lookup(name, type)); }

    /// The value as the C++ type T (int8_t ... uint32_t, float); exact.
    /// Throws std::invalid_argument if `var` was looked up as another type.
    template <typename T>
    T read_as(const Variable& var) const {
        if (var.type != var_type_of<T>()) {
            throw std::invalid_argument("firmware variable '" + var.name + "' was looked up as " +
                                        to_string(var.type) + ", read as " +
                                        to_string(var_type_of<T>()));
        }
        return decode_le<T>(raw_bytes(var));
    }
    template <typename T>
    T read_as(const std::string& name) const {
        return read_as<T>(lookup(name, var_type_of<T>()));
    }

    int8_t read_i8(const std::string& name) const { return read_as<int8_t>(name); }
    uint8_t read_u8(const std::string& name) const { return read_as<uint8_t>(name); }
    int16_t read_i16(const std::string& name) const { return read_as<int16_t>(name); }
    uint16_t read_u16(const std::string& name) const { return read_as<uint16_t>(name); }
    int32_t read_i32(const std::string& name) const { return read_as<int32_t>(name); }
    uint32_t read_u32(const std::string& name) const { return read_as<uint32_t>(name); }
    float read_float(const std::string& name) const { return read_as<float>(name); }

private:
    std::array<uint8_t, 4> raw_bytes(const Variable& var) const noexcept;

    const ElfImage& elf_;
    const AvrCore& core_;
};

}  // namespace ddmr::hil
