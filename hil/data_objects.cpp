#include "hil/data_objects.hpp"

#include <algorithm>
#include <tuple>

namespace ddmr::hil {

DataObjects::DataObjects(const ElfImage& elf, const McuDescription& mcu)
    : sram_start_(mcu.sram_start), ram_end_(mcu.ram_end), index_(mcu.ram_end + 1U - mcu.sram_start, kNone) {
    std::vector<const ElfSymbol*> candidates;
    for (const ElfSymbol& s : elf.symbols()) {
        if (!s.is_object || s.in_text || s.size == 0) continue;
        if (s.address < sram_start_ || s.address + s.size - 1 > ram_end_) continue;
        candidates.push_back(&s);
    }
    std::sort(candidates.begin(), candidates.end(), [](const ElfSymbol* a, const ElfSymbol* b) {
        return std::make_tuple(a->address, -static_cast<int64_t>(a->size), a->name) <
               std::make_tuple(b->address, -static_cast<int64_t>(b->size), b->name);
    });
    for (const ElfSymbol* s : candidates) {
        const std::size_t first = s->address - sram_start_;
        const bool free = std::all_of(index_.begin() + static_cast<std::ptrdiff_t>(first),
                                      index_.begin() + static_cast<std::ptrdiff_t>(first + s->size),
                                      [](uint16_t v) { return v == kNone; });
        if (!free) continue;
        const auto id = static_cast<uint16_t>(objects_.size());
        std::fill_n(index_.begin() + static_cast<std::ptrdiff_t>(first), s->size, id);
        objects_.push_back(DataObject{demangle(s->name), static_cast<uint16_t>(s->address),
                                      static_cast<uint16_t>(s->size)});
        raw_names_.push_back(s->name);
    }
}

std::optional<std::size_t> DataObjects::at(uint16_t address) const {
    if (address < sram_start_ || address > ram_end_) return std::nullopt;
    const uint16_t id = index_[address - sram_start_];
    if (id == kNone) return std::nullopt;
    return id;
}

std::optional<std::size_t> DataObjects::find(std::string_view name) const {
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        if (objects_[i].name == name || raw_names_[i] == name) return i;
    }
    return std::nullopt;
}

}  // namespace ddmr::hil
