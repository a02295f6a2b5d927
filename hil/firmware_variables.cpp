#include "hil/firmware_variables.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace ddmr::hil {
namespace {

struct TypeName {
    const char* name;
    VarType type;
};
constexpr TypeName kTypeNames[] = {
    {"int8", VarType::kInt8},   {"uint8", VarType::kUint8},   {"int16", VarType::kInt16},
    {"uint16", VarType::kUint16}, {"int32", VarType::kInt32}, {"uint32", VarType::kUint32},
    {"float", VarType::kFloat},
};

}  // namespace

VarType parse_var_type(std::string_view text) {
    for (const auto& t : kTypeNames) {
        if (text == t.name) return t.type;
    }
    if (text == "double") return VarType::kFloat;  // avr-gcc's double is binary32
    throw std::invalid_argument("variable type '" + std::string(text) +
                                "': expected int8, uint8, int16, uint16, int32, uint32 or float");
}

const char* to_string(VarType type) {
    for (const auto& t : kTypeNames) {
        if (t.type == type) return t.name;
    }
    return "unknown";
}

std::size_t var_type_size(VarType type) {
    switch (type) {
        case VarType::kInt8:
        case VarType::kUint8: return 1;
        case VarType::kInt16:
        case VarType::kUint16: return 2;
        case VarType::kInt32:
        case VarType::kUint32:
        case VarType::kFloat: return 4;
    }
    return 0;
}

std::optional<VarType> default_var_type(std::size_t size_bytes, FourByteDefault four_bytes) {
    switch (size_bytes) {
        case 1: return VarType::kUint8;
        case 2: return VarType::kInt16;
        case 4:
            if (four_bytes == FourByteDefault::kFloat) return VarType::kFloat;
            return std::nullopt;
        default: return std::nullopt;
    }
}

namespace {

template <typename T>
std::array<uint8_t, 4> encode_le(T value) {
    using U = std::conditional_t<sizeof(T) == 1, uint8_t, std::conditional_t<sizeof(T) == 2, uint16_t, uint32_t>>;
    U u = 0;
    std::memcpy(&u, &value, sizeof value);
    std::array<uint8_t, 4> bytes{};
    for (std::size_t i = 0; i < sizeof(T); ++i) bytes[i] = static_cast<uint8_t>((u >> (8 * i)) & 0xFFU);
    return bytes;
}

template <typename T>
std::array<uint8_t, 4> encode_integer(VarType type, double value) {
    const auto lo = static_cast<double>(std::numeric_limits<T>::min());
    const auto hi = static_cast<double>(std::numeric_limits<T>::max());
    if (!(value >= lo && value <= hi) || std::trunc(value) != value) {
        throw std::invalid_argument(fmt::format("{} is not a {} (an integer in [{}, {}])", value, to_string(type),
                                                std::numeric_limits<T>::min(), std::numeric_limits<T>::max()));
    }
    return encode_le(static_cast<T>(value));
}

}  // namespace

std::array<uint8_t, 4> encode_var(VarType type, double value) {
    switch (type) {
        case VarType::kInt8: return encode_integer<int8_t>(type, value);
        case VarType::kUint8: return encode_integer<uint8_t>(type, value);
        case VarType::kInt16: return encode_integer<int16_t>(type, value);
        case VarType::kUint16: return encode_integer<uint16_t>(type, value);
        case VarType::kInt32: return encode_integer<int32_t>(type, value);
        case VarType::kUint32: return encode_integer<uint32_t>(type, value);
        case VarType::kFloat: break;
    }
    if (!std::isfinite(value) || std::fabs(value) > static_cast<double>(std::numeric_limits<float>::max())) {
        throw std::invalid_argument(fmt::format("{} is not a finite float (binary32)", value));
    }
    return encode_le(static_cast<float>(value));
}

double decode_var(VarType type, const std::array<uint8_t, 4>& bytes) {
    switch (type) {
        case VarType::kInt8: return decode_le<int8_t>(bytes);
        case VarType::kUint8: return decode_le<uint8_t>(bytes);
        case VarType::kInt16: return decode_le<int16_t>(bytes);
        case VarType::kUint16: return decode_le<uint16_t>(bytes);
        case VarType::kInt32: return decode_le<int32_t>(bytes);
        case VarType::kUint32: return decode_le<uint32_t>(bytes);
        case VarType::kFloat: return static_cast<double>(decode_le<float>(bytes));
    }
    return std::numeric_limits<double>::quiet_NaN();
}

Variable FirmwareVariables::lookup(const std::string& name, VarType type) const {
    const std::string where = "firmware " + elf_.path().string() + ": ";
    const auto sym = elf_.find(name);
    if (!sym) {
        throw std::runtime_error(where + "no symbol '" + name +
                                 "' (not a global, or folded away by LTO)");
    }
    if (!sym->is_object) {
        throw std::runtime_error(where + "symbol '" + name + "' is " +
                                 (sym->is_function ? "a function" : "not a data object") +
                                 ", not a variable");
    }
    const std::size_t want = var_type_size(type);
    if (sym->size != want) {
        throw std::runtime_error(where + "variable '" + name + "' is " + std::to_string(sym->size) +
                                 " bytes; " + to_string(type) + " is " + std::to_string(want));
    }
    // Globals live in SRAM (datasheet 8.3, "SRAM Data Memory"): from the end of
    // the extended I/O space to RAMEND. Reading there never throws later.
    const McuDescription& mcu = core_.mcu();
    if (sym->address < mcu.sram_start || sym->address + want - 1 > mcu.ram_end) {
        throw std::runtime_error(where + "variable '" + name + "' at data address " +
                                 std::to_string(sym->address) + " is not in SRAM");
    }
    return Variable{name, static_cast<uint16_t>(sym->address), static_cast<uint8_t>(want), type};
}

namespace {

/// What lookup() guarantees; checked again so that a hand-made Variable can
/// neither read outside SRAM nor make AvrCore::data throw.
bool valid(const Variable& var, const McuDescription& mcu) {
    return var.size == var_type_size(var.type) && var.address >= mcu.sram_start &&
           var.address + var.size - 1U <= mcu.ram_end;
}

}  // namespace

std::array<uint8_t, 4> FirmwareVariables::raw_bytes(const Variable& var) const noexcept {
    std::array<uint8_t, 4> b{};
    if (!valid(var, core_.mcu())) return b;
    for (uint8_t i = 0; i < var.size; ++i) b[i] = core_.data(static_cast<uint16_t>(var.address + i));
    return b;
}

double FirmwareVariables::read(const Variable& var) const noexcept {
    if (!valid(var, core_.mcu())) return std::numeric_limits<double>::quiet_NaN();
    return decode_var(var.type, raw_bytes(var));
}

}  // namespace ddmr::hil
