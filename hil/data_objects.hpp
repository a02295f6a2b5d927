#pragma once
// DataObjects: the firmware's variables in SRAM (.data, .bss and the
// library's statics), from the ELF's object symbols, with a lookup from a
// data-space address to the variable holding it. The race detector groups
// the bytes an instruction sequence loads or stores by variable with it.
//
// Symbols that overlap one already taken (an alias of the same storage) are
// dropped: objects are taken by address, then larger first, then by name, so
// the result does not depend on the symbol table's order.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hil/elf_image.hpp"

namespace ddmr::hil {

struct DataObject {
    std::string name;      ///< as the ELF names it (C++ names demangled where they are mangled)
    uint16_t address = 0;  ///< data-space address of the first byte
    uint16_t size = 0;     ///< bytes
};

class DataObjects {
public:
    /// The variables of `elf` inside `mcu`'s SRAM.
    DataObjects(const ElfImage& elf, const McuDescription& mcu);

    const std::vector<DataObject>& all() const { return objects_; }
    const DataObject& operator[](std::size_t i) const { return objects_[i]; }
    std::size_t size() const { return objects_.size(); }
    /// Index of the object that holds data-space byte `address`, if any.
    std::optional<std::size_t> at(uint16_t address) const;
    /// Index of the object named `name` (raw or demangled), if any.
    std::optional<std::size_t> find(std::string_view name) const;

private:
    static constexpr uint16_t kNone = 0xFFFF;
    uint16_t sram_start_ = 0;
    uint16_t ram_end_ = 0;
    std::vector<DataObject> objects_;
    std::vector<std::string> raw_names_;
    std::vector<uint16_t> index_;  ///< per SRAM byte: object index or kNone
};

}  // namespace ddmr::hil
