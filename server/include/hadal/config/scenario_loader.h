// Strict YAML scenario loading (docs/ARCHITECTURE.md, "Strict configuration").
//
// A scenario file (configs/scenarios/*.yaml) is loaded into a hadal::Model. Vehicle definitions can be
// inline or pulled from configs/vehicles/*.yaml with `include:` (a path relative to the including file).
// Unknown keys, wrong types, missing required keys, out-of-range values and bad references are all
// collected; each reads `file:line:col: error: yaml.path: message` with 1-based line and column of
// the offending node, in the file that holds it. The full key reference is configs/REFERENCE.md.
#pragma once

#include "hadal/config/diagnostic.h"
#include "hadal/core/model.h"

#include <optional>
#include <string>
#include <vector>

namespace hadal::config {

struct LoadResult {
  std::optional<Model> model;  // set only when errors is empty
  std::vector<Diagnostic> errors;
  std::vector<Diagnostic> warnings;  // e.g. an open mesh used for buoyancy; printed, never fatal

  bool ok() const { return model.has_value() && errors.empty(); }
};

// Loads and validates a scenario file. Never throws for bad input: every problem is a Diagnostic.
LoadResult load_scenario_file(const std::string& path);

}  // namespace hadal::config
