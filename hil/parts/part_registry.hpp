#pragma once
// PartRegistry: every part type a board file can name, by its `type:` word.
// The built-in types are an explicit list (builtin_parts.cpp), so static
// linking cannot drop one; a program or a test adds its own with add()
// before it reads a board file that names it. The board-file parser,
// `ddmr-hil parts`, the parts table in docs/boards.md and the schema's
// `parts` items all come from here.
//
// Thread-safe: add() and the lookups take a lock; a PartType, once added,
// stays at its address for the life of the process.

#include <deque>
#include <mutex>
#include <string>
#include <vector>

#include "hil/parts/part.hpp"

namespace ddmr::hil {

class PartRegistry {
public:
    /// The process's registry, holding the built-in types.
    static PartRegistry& global();

    /// Adds `type`; throws std::invalid_argument if its word is taken, it has
    /// no factory, or two keys share a name.
    void add(PartType type);
    /// The type of that word, or nullptr.
    [[nodiscard]] const PartType* find(const std::string& type) const;
    /// Every type, in the order added.
    [[nodiscard]] std::vector<const PartType*> types() const;
    /// "74hc595, ..." (for messages).
    [[nodiscard]] std::string type_list() const;

private:
    mutable std::mutex mutex_;
    std::deque<PartType> types_;
};

/// The built-in part types (builtin_parts.cpp: one line per part file).
std::vector<PartType> builtin_part_types();

}  // namespace ddmr::hil
