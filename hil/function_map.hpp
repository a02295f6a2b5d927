#pragma once
// FunctionMap: which function every flash word belongs to, from the ELF's
// symbol table alone (the profiler's address -> function lookup, O(1)).
//
// Entry points are the addresses the chip can call or jump to by name:
//   - .text symbols of type STT_FUNC (compiled functions, local ones too);
//   - global or weak STT_NOTYPE labels in .text: the hand-written assembly
//     of libgcc and avr-libc's libm (`__addsf3`, `__fp_splitA`,
//     `__tablejump2__`, the start-up code `__init`, `__do_copy_data`, ...).
// Not entry points:
//   - objects (PROGMEM tables such as `port_to_mode_PGM`);
//   - local NOTYPE labels (loop labels: `.do_clear_bss_loop`,
//     `__udivmodsi4_loop`; `__stop_program` inside `_exit`);
//   - the linker script's markers (`__trampolines_start`, `__ctors_end`,
//     `_etext`, ...: see kLinkerMarkers in the .cpp) and anything outside
//     .text (absolute symbols such as `__heap_end`, `__stack`).
// Every address belongs to the nearest entry point at or below it, so a
// function is the code from its entry to the next entry: `__subsf3` at
// 0x1ff8 is one instruction that falls into `__addsf3` at 0x1ffa, and a
// symbol's ELF size does not extend it past a later entry. Flash outside
// .text (the .data image, erased flash) belongs to one pseudo-function,
// kOutsideName.
//
// Several symbols at one address are one function with one canonical name:
// a symbol with a size first, then STT_FUNC, then global over weak over
// local, then the shorter name, then alphabetical; the others are its
// aliases (`__cmpsf2` with aliases `__eqsf2`, `__lesf2`, ...).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hil/elf_image.hpp"

namespace ddmr::hil {

/// Index of a function in a FunctionMap (dense: 0 .. size() - 1).
using FunctionId = uint16_t;

struct FunctionInfo {
    std::string name;                  ///< canonical symbol name (raw, mangled)
    std::vector<std::string> aliases;  ///< other symbols at the same address, sorted
    uint32_t address = 0;              ///< flash byte address of the entry point
    uint32_t end = 0;                  ///< one past the last byte (the next entry point)
};

class FunctionMap {
public:
    static constexpr const char* kOutsideName = "(outside .text)";

    /// Builds the map of `elf`'s .text. Throws std::runtime_error naming the
    /// file if .text has no entry point at all.
    /// The functions of `elf` over `mcu`'s flash.
    FunctionMap(const ElfImage& elf, const McuDescription& mcu);

    /// Number of functions, the kOutsideName pseudo-function included.
    std::size_t size() const { return functions_.size(); }
    const FunctionInfo& function(FunctionId id) const { return functions_[id]; }
    const std::vector<FunctionInfo>& functions() const { return functions_; }

    /// The function a flash byte address belongs to (outside() past .text or
    /// past the flash).
    FunctionId at(uint32_t flash_address) const {
        const uint32_t word = flash_address >> 1;
        return word < by_word_.size() ? by_word_[word] : outside_;
    }
    /// True if `flash_address` is the entry point of its function.
    bool is_entry(uint32_t flash_address) const {
        const FunctionId id = at(flash_address);
        return id != outside_ && functions_[id].address == flash_address;
    }
    /// The function whose canonical name or an alias is `name`; with several
    /// (local functions of one name), the lowest address.
    std::optional<FunctionId> find(std::string_view name) const;
    FunctionId outside() const { return outside_; }

private:
    std::vector<FunctionInfo> functions_;  ///< sorted by address; outside() last
    std::vector<FunctionId> by_word_;      ///< function of each flash word
    FunctionId outside_ = 0;
};

}  // namespace ddmr::hil
