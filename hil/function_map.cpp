// FunctionMap: entry points from the ELF's symbols, one function per flash word.
#include "hil/function_map.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <stdexcept>


namespace ddmr::hil {
namespace {

/// Symbols the avr-binutils linker scripts define to mark section boundaries:
/// global NOTYPE in .text, but nothing ever calls them.
constexpr std::array<std::string_view, 10> kLinkerMarkers = {
    "__trampolines_start", "__trampolines_end", "__ctors_start", "__ctors_end",
    "__dtors_start",       "__dtors_end",       "_etext",        "__data_load_start",
    "__data_load_end",     "__vectors_end",
};

bool is_entry_symbol(const ElfSymbol& s, uint32_t text_end) {
    if (!s.in_text || s.is_object || s.address >= text_end) return false;
    if (s.is_function) return true;
    if (s.binding == ElfBinding::kLocal) return false;  // a label inside a function
    return std::find(kLinkerMarkers.begin(), kLinkerMarkers.end(), s.name) == kLinkerMarkers.end();
}

int binding_rank(ElfBinding b) {
    switch (b) {
        case ElfBinding::kGlobal: return 0;
        case ElfBinding::kWeak: return 1;
        case ElfBinding::kLocal: return 2;
    }
    return 3;
}

/// True if `a` is a better canonical name than `b` (see the header).
bool better_name(const ElfSymbol& a, const ElfSymbol& b) {
    if ((a.size > 0) != (b.size > 0)) return a.size > 0;
    if (a.is_function != b.is_function) return a.is_function;
    if (binding_rank(a.binding) != binding_rank(b.binding)) {
        return binding_rank(a.binding) < binding_rank(b.binding);
    }
    if (a.name.size() != b.name.size()) return a.name.size() < b.name.size();
    return a.name < b.name;
}

}  // namespace

FunctionMap::FunctionMap(const ElfImage& elf, const McuDescription& mcu) {
    const uint32_t text_end = elf.text_end();
    // Entry points by address, each with its symbols.
    std::map<uint32_t, std::vector<const ElfSymbol*>> entries;
    for (const ElfSymbol& s : elf.symbols()) {
        if (is_entry_symbol(s, text_end)) entries[s.address].push_back(&s);
    }
    if (entries.empty()) {
        throw std::runtime_error("firmware " + elf.path().string() + ": no function symbols in .text");
    }
    // FunctionId is 16 bits: more entry points than that is not a firmware.
    if (entries.size() + 1 > std::numeric_limits<FunctionId>::max()) {
        throw std::runtime_error("firmware " + elf.path().string() + ": too many entry points");
    }
    for (auto it = entries.begin(); it != entries.end(); ++it) {
        auto& syms = it->second;
        std::sort(syms.begin(), syms.end(), [](const ElfSymbol* a, const ElfSymbol* b) { return better_name(*a, *b); });
        FunctionInfo f;
        f.name = syms.front()->name;
        for (std::size_t i = 1; i < syms.size(); ++i) f.aliases.push_back(syms[i]->name);
        std::sort(f.aliases.begin(), f.aliases.end());
        f.aliases.erase(std::unique(f.aliases.begin(), f.aliases.end()), f.aliases.end());
        f.address = it->first;
        const auto next = std::next(it);
        f.end = next == entries.end() ? text_end : next->first;
        functions_.push_back(std::move(f));
    }
    outside_ = static_cast<FunctionId>(functions_.size());
    functions_.push_back(FunctionInfo{kOutsideName, {}, text_end, mcu.flash_bytes});

    by_word_.assign(mcu.flash_bytes / 2, outside_);
    for (std::size_t id = 0; id < outside_; ++id) {
        const FunctionInfo& f = functions_[id];
        const uint32_t last = std::min(f.end, mcu.flash_bytes);
        for (uint32_t a = f.address; a < last; a += 2) by_word_[a >> 1] = static_cast<FunctionId>(id);
    }
}

std::optional<FunctionId> FunctionMap::find(std::string_view name) const {
    for (std::size_t id = 0; id < functions_.size(); ++id) {
        const FunctionInfo& f = functions_[id];
        if (f.name == name || std::find(f.aliases.begin(), f.aliases.end(), name) != f.aliases.end()) {
            return static_cast<FunctionId>(id);
        }
    }
    return std::nullopt;
}

}  // namespace ddmr::hil
