#pragma once
// An AVR firmware ELF file as the HIL needs it, read with libelf: its machine
// and architecture (to refuse firmware built for another chip), its section
// sizes (flash and RAM use), and its symbol table (addresses and sizes of
// functions and globals, to watch the firmware without changing it; binding
// and section too, so FunctionMap can tell code entry points from labels).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hil/mcu.hpp"

namespace ddmr::hil {

/// How far a symbol is visible (the ELF STB_ binding).
enum class ElfBinding : uint8_t { kLocal, kGlobal, kWeak };

/// The C++ name behind an Itanium-mangled symbol (avr-g++ uses that ABI), or
/// the symbol itself (C names, libgcc's assembly).
std::string demangle(const std::string& name);
/// A demangled function name without its parameter list, cv and ref
/// qualifiers and GCC's " [clone .constprop.0]" suffixes:
/// "ns::C::step(int) const" -> "ns::C::step"; a name without them as is.
std::string without_parameters(const std::string& demangled);

/// One entry of the ELF symbol table.

struct ElfSymbol {
    std::string name;       ///< raw (mangled) name
    uint32_t address = 0;   ///< flash byte address for functions; data-space address for
                            ///< objects (the 0x800000 offset of avr-gcc is removed)
    uint32_t size = 0;      ///< bytes
    bool is_function = false;  ///< STT_FUNC
    bool is_object = false;    ///< STT_OBJECT
    ElfBinding binding = ElfBinding::kLocal;
    bool in_text = false;      ///< defined in the .text section (code and PROGMEM)
    bool defined = true;       ///< false for an undefined symbol (SHN_UNDEF: a weak one the link left unresolved)
};

/// Flash and RAM use, as avr-size reports them.
struct ElfMemoryUse {
    uint32_t text_bytes = 0;  ///< .text (code, vectors, progmem)
    uint32_t data_bytes = 0;  ///< .data (initialised globals, stored in flash too)
    uint32_t bss_bytes = 0;   ///< .bss (zeroed globals)
    uint32_t flash_bytes() const { return text_bytes + data_bytes; }
    uint32_t ram_bytes() const { return data_bytes + bss_bytes; }
};

class ElfImage {
public:
    /// Reads `path`. Throws std::runtime_error naming the file and the problem when
    /// it is missing, unreadable, empty or not a well-formed 32-bit ELF.
    static ElfImage read(const std::filesystem::path& path);

    /// Throws std::runtime_error naming the file and the mismatch unless this ELF
    /// was built for `mcu`: EM_AVR machine, the MCU's architecture (avr5 for
    /// the ATmega328P), an optional simavr .mmcu section naming it, the MCU's
    /// JMP vector table (26 entries on the ATmega328P, no more), and a program
    /// and globals that fit its flash and SRAM. `board` (a board-file key, or
    /// empty) names the board in the message: "board 'uno' (ATmega328P)".
    void require_mcu(const McuDescription& mcu, const std::string& board = {}) const;

    const std::filesystem::path& path() const { return path_; }
    uint16_t machine() const { return machine_; }
    uint32_t flags() const { return flags_; }
    const ElfMemoryUse& memory_use() const { return memory_; }
    const std::vector<ElfSymbol>& symbols() const { return symbols_; }
    /// Flash byte addresses of the .text section: [text_begin, text_end).
    uint32_t text_begin() const { return text_address_; }
    uint32_t text_end() const { return text_address_ + memory_.text_bytes; }
    /// text_word(), or 0xFFFF (erased flash) outside .text.
    uint16_t text_word_or_erased(uint32_t byte_address) const { return text_word(byte_address).value_or(0xFFFF); }
    /// MCU name from simavr's .mmcu section, when the firmware has one.
    const std::optional<std::string>& mmcu() const { return mmcu_; }

    /// The symbol with this exact (mangled) name, if any.
    std::optional<ElfSymbol> find(const std::string& name) const;
    /// The functions with code (STT_FUNC, size > 0) that `name` names: the
    /// symbol of that exact name, else by C++ name, whole
    /// ("MyClass::step(int)") or without its parameter list, qualifiers and
    /// clone suffix ("MyClass::step", "serialEventRun"). One per address (a
    /// constructor's aliases are one function); more than one: overloads.
    std::vector<ElfSymbol> find_functions(const std::string& name) const;
    /// The shortest name find_functions() finds `function` alone by: its C++
    /// name without parameters, else whole, else the symbol.
    std::string function_name(const ElfSymbol& function) const;
    /// The 16-bit word of .text at a flash byte address (little-endian, as
    /// fetched), or nullopt outside [text_begin, text_end - 1).
    std::optional<uint16_t> text_word(uint32_t flash_address) const;
    /// Like find(), but throws std::runtime_error naming the symbol and the file.
    ElfSymbol require(const std::string& name) const;
    /// The function whose [address, address + size) contains the flash byte address.
    std::optional<ElfSymbol> function_at(uint32_t flash_address) const;

private:
    std::filesystem::path path_;
    uint16_t machine_ = 0;
    uint32_t flags_ = 0;
    ElfMemoryUse memory_;
    uint32_t text_address_ = 0;
    std::vector<ElfSymbol> symbols_;
    std::optional<std::string> mmcu_;
    /// .text's bytes, shared by copies (an ElfImage is copied into each part that keeps one).
    std::shared_ptr<const std::vector<uint8_t>> text_;
};

}  // namespace ddmr::hil
