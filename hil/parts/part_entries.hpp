#pragma once
// The board file's `parts:` list (docs/boards.md, "Parts"): each entry a
// mapping {name, type, <the type's keys>}, checked against its PartType
// (part_registry.hpp). Refusals are "FILE:LINE: key 'parts.NAME.KEY': what is
// wrong" (std::runtime_error, via YamlReader::fail).

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "hil/parts/part.hpp"
#include "hil/parts/part_registry.hpp"
#include "hil/yaml_reader.hpp"

namespace ddmr::hil {

/// Reads a board pin (the board's own pin reader, with its messages).
using PinReader = std::function<int(const YAML::Node&, const std::string&)>;

/// Reads `list` (a sequence). Refuses an entry that is not a mapping, a
/// missing or repeated name, an unknown type (naming the known ones), an
/// unknown or missing key, an input that is not a pin, NAME.PORT, high or
/// low, an output that is not a pin, an option out of its range or choices,
/// and an entry its type's check() refuses on `board`.
std::vector<PartEntry> read_part_entries(const YamlReader& reader, const YAML::Node& list, const PinReader& pin,
                                         const PartRegistry& registry, const BoardDescription& board);

}  // namespace ddmr::hil
