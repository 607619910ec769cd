// The JSON Schema (draft-07) of a map of keys and everything it nests, made from the key tables'
// descriptions (config/key_doc.h): editors (the YAML language server, `# yaml-language-server:
// $schema=...`) complete and check scenarios with it, and `hadald --schema` prints it.
//
// Each table is a definition named by its id (`#/definitions/world.water`); a key's schema carries its
// type, range, choices, and a description with its unit and default. A table's selector (a seabed's
// `type`) becomes if/then clauses: keys another selection does not use are refused (`false`), keys it
// needs are required. A table with variants (a sensor entry) lists every variant's keys and, per value of
// its selector, refuses the keys of the others and checks its own.
#pragma once

#include <optional>
#include <string>

#include "hadal/config/key_doc.h"

namespace hadal::config {

// The schema document whose root is `root`, indented by 2.
std::string json_schema(const TableDoc& root, const std::string& title);

// The schema of a scenario file ("scenario") or of a vehicle file ("vehicle"); nullopt for another name.
std::optional<std::string> scenario_json_schema(const std::string& which);

}  // namespace hadal::config
