#include "hil/elf_image.hpp"

#include <cxxabi.h>
#include <fcntl.h>
#include <gelf.h>
#include <libelf.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "hil/board_description.hpp"

namespace ddmr::hil {

std::string demangle(const std::string& name) {
    if (name.rfind("_Z", 0) != 0) return name;
    int status = 0;
    const std::unique_ptr<char, decltype(&std::free)> out(
        abi::__cxa_demangle(name.c_str(), nullptr, nullptr, &status), &std::free);
    return status == 0 && out ? std::string(out.get()) : name;
}

std::string without_parameters(const std::string& demangled) {
    std::string_view d = demangled;
    const auto strip = [&d](std::string_view suffix) {
        const bool has = d.size() > suffix.size() && d.substr(d.size() - suffix.size()) == suffix;
        if (has) d.remove_suffix(suffix.size());
        return has;
    };
    // "f(int) [clone .constprop.0] [clone .isra.0]"
    while (!d.empty() && d.back() == ']') {
        const auto clone = d.rfind(" [clone ");
        if (clone == std::string_view::npos) break;
        d = d.substr(0, clone);
    }
    while (strip(" const") || strip(" volatile") || strip(" &&") || strip(" &")) {
    }
    if (d.empty() || d.back() != ')') return std::string(d);
    // The parameter list is the last balanced (...): "(anonymous namespace)::f(int)",
    // "C::operator()(int)" and "f(void (*)(int))" keep what precedes it.
    int depth = 0;
    for (std::size_t i = d.size(); i-- > 0;) {
        if (d[i] == ')') ++depth;
        if (d[i] == '(' && --depth == 0) return std::string(d.substr(0, i));
    }
    return std::string(d);
}

namespace {

/// avr-gcc places data-space objects at 0x800000 in the ELF address space.
constexpr uint32_t kAvrDataOffset = 0x800000;
/// EF_AVR_MACH: the architecture field of an AVR ELF's e_flags.
constexpr uint32_t kEfAvrMachMask = 0x7F;

/// " (e.g. the ATmega2560)": a well-known part of an avr-gcc architecture, for messages.
std::string arch_example(uint32_t arch) {
    switch (arch) {
        case 4: return " (e.g. the ATmega8, ATmega88)";
        case 5: return " (e.g. the ATmega328P, ATmega32U4)";
        case 6: return " (e.g. the ATmega2560)";
        default: return "";
    }
}
/// simavr's .mmcu tag holding the MCU name (AVR_MMCU_TAG_NAME in avr_mcu_section.h).
constexpr uint8_t kMmcuTagName = 1;

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
    throw std::runtime_error("firmware " + path.string() + ": " + what);
}

struct FdCloser {
    int fd;
    ~FdCloser() {
        if (fd >= 0) ::close(fd);
    }
};

struct ElfDeleter {
    void operator()(Elf* e) const { elf_end(e); }
};

/// True when the 4 bytes at `p` are a JMP instruction (1001 010k kkkk 110k).
uint16_t word_at(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }

/// A vector slot's jump: JMP k, or RJMP k where the linker's relaxation
/// (-mrelax, as the Arduino core builds the Mega) shortened it.
bool is_jmp(const uint8_t* p) {
    const uint16_t word = word_at(p);
    return (word & 0xFE0E) == 0x940C || (word & 0xF000) == 0xC000;
}

/// A whole 4-byte vector slot: JMP k, or a relaxed RJMP k followed by NOP
/// (what follows the table is code or data: one RJMP-like word is no vector).
bool is_vector_slot(const uint8_t* p) {
    const uint16_t word = word_at(p);
    return (word & 0xFE0E) == 0x940C || ((word & 0xF000) == 0xC000 && word_at(p + 2) == 0x0000);
}

std::optional<std::string> parse_mmcu_name(const uint8_t* data, std::size_t size) {
    std::size_t i = 0;
    while (i + 2 <= size) {
        const uint8_t tag = data[i];
        const uint8_t len = data[i + 1];
        if (len < 2 || i + len > size) break;
        if (tag == kMmcuTagName) {
            const char* s = reinterpret_cast<const char*>(data + i + 2);
            return std::string(s, strnlen(s, static_cast<std::size_t>(len - 2)));
        }
        i += len;
    }
    return std::nullopt;
}

}  // namespace

ElfImage ElfImage::read(const std::filesystem::path& path) {
    ElfImage img;
    img.path_ = path;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
    if (std::filesystem::is_directory(path, ec)) fail(path, "is a folder, not an ELF file");
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) fail(path, std::string("cannot open: ") + std::strerror(errno));
    const FdCloser closer{fd};
    if (std::filesystem::file_size(path, ec) == 0) fail(path, "empty file, not an ELF");

    if (elf_version(EV_CURRENT) == EV_NONE) fail(path, "libelf initialisation failed");
    std::unique_ptr<Elf, ElfDeleter> elf(elf_begin(fd, ELF_C_READ, nullptr));
    if (!elf || elf_kind(elf.get()) != ELF_K_ELF) {
        char first = 0;
        if (::pread(fd, &first, 1, 0) == 1 && first == ':') {
            fail(path, "is an Intel HEX file, not an ELF: the HIL needs the ELF's symbols; give the .elf the build "
                       "wrote next to it");
        }
        fail(path, "not an ELF file (wrong magic bytes); give the .elf the build wrote");
    }
    GElf_Ehdr ehdr;
    if (gelf_getehdr(elf.get(), &ehdr) == nullptr) {
        fail(path, std::string("corrupt ELF header: ") + elf_errmsg(-1));
    }
    img.machine_ = ehdr.e_machine;
    img.flags_ = static_cast<uint32_t>(ehdr.e_flags);

    std::size_t shstrndx = 0;
    if (elf_getshdrstrndx(elf.get(), &shstrndx) != 0) {
        fail(path, std::string("corrupt section table: ") + elf_errmsg(-1));
    }
    // The symbol table may come before .text: find .text's index first.
    std::size_t text_index = 0;
    Elf_Scn* scn = nullptr;
    while ((scn = elf_nextscn(elf.get(), scn)) != nullptr) {
        GElf_Shdr shdr;
        if (gelf_getshdr(scn, &shdr) == nullptr) continue;
        const char* name = elf_strptr(elf.get(), shstrndx, shdr.sh_name);
        if (name != nullptr && std::strcmp(name, ".text") == 0) text_index = elf_ndxscn(scn);
    }
    scn = nullptr;
    while ((scn = elf_nextscn(elf.get(), scn)) != nullptr) {
        GElf_Shdr shdr;
        if (gelf_getshdr(scn, &shdr) == nullptr) {
            fail(path, std::string("corrupt section header: ") + elf_errmsg(-1));
        }
        const char* name = elf_strptr(elf.get(), shstrndx, shdr.sh_name);
        if (name == nullptr) fail(path, "corrupt section name table");
        const std::string sname(name);
        // simavr's loader picks sections by name: a name it knows on a section
        // that holds no program bytes (e.g. a symbol table called .data) makes
        // it read that section as code or data (found by tests/fuzz).
        const bool loaded = sname == ".text" || sname == ".data" || sname == ".bss" ||
                            sname == ".eeprom" || sname == ".fuse" || sname == ".lock" ||
                            sname == ".mmcu";
        if (loaded && shdr.sh_type != SHT_PROGBITS && shdr.sh_type != SHT_NOBITS) {
            fail(path, "corrupt section table: section " + std::to_string(elf_ndxscn(scn)) + " is called '" +
                           sname + "' but has type " + std::to_string(shdr.sh_type) +
                           ", not program data");
        }
        if (sname == ".text") {
            img.memory_.text_bytes = static_cast<uint32_t>(shdr.sh_size);
            img.text_address_ = static_cast<uint32_t>(shdr.sh_addr);
            Elf_Data* d = elf_getdata(scn, nullptr);
            if (d == nullptr || d->d_buf == nullptr) fail(path, "corrupt .text section");
            const auto* bytes = static_cast<const uint8_t*>(d->d_buf);
            img.text_ = std::make_shared<const std::vector<uint8_t>>(bytes, bytes + d->d_size);
        } else if (sname == ".data") {
            img.memory_.data_bytes = static_cast<uint32_t>(shdr.sh_size);
        } else if (sname == ".bss") {
            img.memory_.bss_bytes = static_cast<uint32_t>(shdr.sh_size);
        } else if (sname == ".mmcu") {
            Elf_Data* d = elf_getdata(scn, nullptr);
            if (d != nullptr && d->d_buf != nullptr) {
                img.mmcu_ = parse_mmcu_name(static_cast<const uint8_t*>(d->d_buf), d->d_size);
            }
        } else if (shdr.sh_type == SHT_SYMTAB) {
            Elf_Data* d = elf_getdata(scn, nullptr);
            if (d == nullptr || shdr.sh_entsize == 0) fail(path, "corrupt symbol table");
            const std::size_t count = shdr.sh_size / shdr.sh_entsize;
            for (std::size_t i = 0; i < count; ++i) {
                GElf_Sym sym;
                if (gelf_getsym(d, static_cast<int>(i), &sym) == nullptr) {
                    fail(path, "corrupt symbol table entry");
                }
                const char* sn = elf_strptr(elf.get(), shdr.sh_link, sym.st_name);
                // simavr's own loader reads every symbol's name without a
                // check (a NULL name crashes it: found by tests/fuzz): refuse.
                if (sn == nullptr) {
                    fail(path, "corrupt symbol table: symbol " + std::to_string(i) + " has no name in its string table");
                }
                if (*sn == '\0') continue;
                const int type = GELF_ST_TYPE(sym.st_info);
                ElfSymbol s;
                s.name = sn;
                s.size = static_cast<uint32_t>(sym.st_size);
                s.is_function = type == STT_FUNC;
                s.is_object = type == STT_OBJECT;
                const int bind = GELF_ST_BIND(sym.st_info);
                s.binding = bind == STB_GLOBAL ? ElfBinding::kGlobal
                            : bind == STB_WEAK ? ElfBinding::kWeak
                                               : ElfBinding::kLocal;
                // The linker script puts some data-space markers (_end) in .text's
                // index with a 0x800000 address: not code.
                s.in_text = text_index != 0 && sym.st_shndx == text_index && sym.st_value < kAvrDataOffset;
                s.defined = sym.st_shndx != SHN_UNDEF;
                auto addr = static_cast<uint32_t>(sym.st_value);
                if (addr >= kAvrDataOffset && addr < kAvrDataOffset + 0x10000) addr -= kAvrDataOffset;
                s.address = addr;
                img.symbols_.push_back(std::move(s));
            }
        }
    }
    std::sort(img.symbols_.begin(), img.symbols_.end(),
              [](const ElfSymbol& a, const ElfSymbol& b) {
                  return a.address != b.address ? a.address < b.address : a.name < b.name;
              });
    return img;
}

void ElfImage::require_mcu(const McuDescription& mcu, const std::string& board) const {
    const std::string chip = mcu.label;
    const std::string on = board.empty() ? chip : fmt::format("board '{}' ({})", board, chip);
    if (machine_ != EM_AVR) {
        fail(path_, "built for ELF machine " + std::to_string(machine_) +
                        ", not AVR (83): this is not an AVR firmware");
    }
    const uint32_t arch = flags_ & kEfAvrMachMask;
    if (arch != mcu.elf_arch) {
        // A supported board with that architecture is the likelier fix than a rebuild.
        std::string boards;
        for (const BoardModel m : board_models()) {
            const BoardDescription& b = board_description(m);
            if (b.mcu->elf_arch == arch) boards += std::string(boards.empty() ? "" : " or ") + b.key;
        }
        const std::string other_board =
            boards.empty() ? std::string()
                           : fmt::format("if it was built for the {}, give that board (board: KEY in the board file, "
                                         "or run --board-name KEY); else ",
                                         boards);
        fail(path_, fmt::format("built for AVR architecture avr{}{}, but the {} is avr{}: {}build it for the {} "
                                "(avr-gcc -mmcu={}, or the board's FQBN)",
                                arch, arch_example(arch), on, mcu.elf_arch, other_board, chip, mcu.name));
    }
    if (mmcu_ && *mmcu_ != mcu.name) {
        fail(path_, fmt::format("its .mmcu section names MCU '{}', not {} ({})", *mmcu_, mcu.name, on));
    }
    if (memory_.flash_bytes() == 0) fail(path_, "has no .text section: nothing to load");
    if (memory_.flash_bytes() > mcu.flash_bytes) {
        fail(path_, fmt::format("program of {} bytes does not fit the {}'s {}-byte flash", memory_.flash_bytes(),
                                chip, mcu.flash_bytes));
    }
    if (memory_.ram_bytes() > mcu.sram_bytes) {
        fail(path_, fmt::format("globals of {} bytes do not fit the {}'s {}-byte SRAM", memory_.ram_bytes(), chip,
                                mcu.sram_bytes));
    }
    // The chip's vectors are one JMP each. Another part of the same
    // architecture with a larger table (ATmega16x4, ATmega32U4, ... for the
    // ATmega328P) has a JMP in the slot after the last one as well.
    const auto count = static_cast<std::size_t>(mcu.vector_count());
    const auto slot = static_cast<std::size_t>(mcu.vector_bytes);
    const std::size_t table = count * slot;
    static const std::vector<uint8_t> kNoText;
    const std::vector<uint8_t>& text = text_ ? *text_ : kNoText;
    if (text.size() < table) fail(path_, fmt::format("too short for an {} vector table", chip));
    for (std::size_t v = 0; v < count; ++v) {
        if (!is_jmp(&text[v * slot])) {
            fail(path_, fmt::format("interrupt vector {} is not a JMP or RJMP: not an {} vector table", v, chip));
        }
    }
    if (text.size() >= table + slot && is_vector_slot(&text[table])) {
        fail(path_, fmt::format("has more than {} interrupt vectors: built for another avr{} MCU, not the {}", count,
                                mcu.elf_arch, on));
    }
}

std::optional<ElfSymbol> ElfImage::find(const std::string& name) const {
    for (const auto& s : symbols_) {
        if (s.name == name) return s;
    }
    return std::nullopt;
}

std::vector<ElfSymbol> ElfImage::find_functions(const std::string& name) const {
    std::vector<ElfSymbol> out;
    const auto add = [&out](const ElfSymbol& s) {
        if (std::none_of(out.begin(), out.end(), [&s](const ElfSymbol& o) { return o.address == s.address; })) {
            out.push_back(s);
        }
    };
    const auto has_code = [](const ElfSymbol& s) { return s.is_function && s.size > 0; };
    for (const auto& s : symbols_) {
        if (has_code(s) && s.name == name) add(s);
    }
    if (!out.empty()) return out;
    for (const auto& s : symbols_) {
        if (!has_code(s) || s.name.rfind("_Z", 0) != 0) continue;
        const std::string d = demangle(s.name);
        if (d == name || without_parameters(d) == name) add(s);
    }
    return out;
}

std::string ElfImage::function_name(const ElfSymbol& function) const {
    const std::string d = demangle(function.name);
    for (const std::string& name : {without_parameters(d), d}) {
        const auto found = find_functions(name);
        if (found.size() == 1 && found.front().address == function.address) return name;
    }
    return function.name;
}

std::optional<uint16_t> ElfImage::text_word(uint32_t flash_address) const {
    if (!text_ || flash_address < text_address_ || flash_address - text_address_ + 1 >= text_->size()) {
        return std::nullopt;
    }
    return word_at(&(*text_)[flash_address - text_address_]);
}

ElfSymbol ElfImage::require(const std::string& name) const {
    auto s = find(name);
    if (!s) fail(path_, "has no symbol '" + name + "'");
    return *s;
}

std::optional<ElfSymbol> ElfImage::function_at(uint32_t flash_address) const {
    for (const auto& s : symbols_) {
        if (s.is_function && flash_address >= s.address && flash_address < s.address + s.size) {
            return s;
        }
    }
    return std::nullopt;
}

}  // namespace ddmr::hil
