#pragma once
// `ddmr-hil parts [TYPE]`: the part types a board file's `parts:` list can
// name (hil/parts/part_registry.hpp), each with its keys and output ports,
// as `scenario --list-steps` lists the steps. `--markdown` prints the table
// of docs/boards.md ("Parts", between its parts-table markers) and
// `--schema` the JSON Schema of one `parts:` item
// (docs/schema/board.schema.json, properties.parts.items): both come from
// the registry, and `make docs-parts` (tools/update_parts_docs.py) writes
// them into the docs.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hil/parts/part.hpp"
#include "subcommand.hpp"

namespace ddmr::tools {

/// The listing: per type its summary, datasheet, keys and output ports.
std::string parts_text(const std::vector<const hil::PartType*>& types);
/// docs/boards.md's parts table (a Markdown block, ends with a newline).
std::string parts_markdown(const std::vector<const hil::PartType*>& types);
/// The JSON Schema (draft 2020-12) of one `parts:` item; it refers to the
/// board schema's $defs `pin` and `partInput`.
nlohmann::ordered_json parts_schema(const std::vector<const hil::PartType*>& types);

Subcommand register_parts_command(CLI::App& app);

}  // namespace ddmr::tools
