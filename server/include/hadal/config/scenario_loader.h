// Strict YAML scenario loading (docs/ARCHITECTURE.md, "Strict configuration").
//
// A scenario file (configs/scenarios/*.yaml) is loaded into a hadal::Model. Vehicle definitions can be
// inline or pulled from configs/vehicles/*.yaml with `include:` (a path relative to the including file).
// Unknown keys, wrong types, missing required keys, out-of-range values and bad references are all
// collected; each reads `file:line:col: error: yaml.path: message` with 1-based line and column of
// the offending node, in the file that holds it. The full key reference is configs/REFERENCE.md.
#pragma once

#include "hadal/config/diagnostic.h"
#include "hadal/config/key_table_fwd.h"
#include "hadal/core/model.h"

#include <optional>
#include <string>
#include <vector>

namespace hadal::config {

struct LoadContext;

struct LoadResult {
  std::optional<Model> model;  // set only when errors is empty
  std::vector<Diagnostic> errors;
  std::vector<Diagnostic> warnings;  // e.g. an open mesh used for buoyancy; printed, never fatal

  bool ok() const { return model.has_value() && errors.empty(); }
};

struct LoadOptions {
  // Directories, besides the scenario's tree and hadal's configs, the files a scenario names may lie in
  // (hadald --asset-root).
  std::vector<std::string> asset_roots;
  // Overrides (hadald --set; docs/configuration.md, "Overrides"), each "KEY.PATH=VALUE": a key path as the
  // file is written (a list's entry by its `name`, or its index), into a vehicle's or object's included file
  // through its entry; VALUE in YAML (flow style for lists and maps). Checked by the same keys, ranges and
  // messages as the file; an error in one is reported at "--set KEY.PATH=VALUE:1:column". Later ones win.
  std::vector<std::string> overrides;
};

// Files a scenario may reach (docs/ARCHITECTURE.md, "Files a scenario may reach"): every file it or a file
// it includes names (includes, meshes, heightmaps, soil maps) must lie, symlinks resolved, in one of these
// directories: the scenario's tree (its directory; the parent of that directory when it is called
// `scenarios`, the layout of configs/), hadal's own configs (installed beside the executable, else the
// source tree's; $HADAL_DATA_DIR/configs when that is set), options.asset_roots, and those listed in
// $HADAL_ASSET_ROOTS (colon-separated).
struct AssetRoot {
  std::string path;    // absolute, symlinks resolved (as given when error is set)
  std::string origin;  // where it comes from, for messages
  std::string error;   // non-empty: unusable ("is not a directory")
};
std::vector<AssetRoot> asset_roots(const std::string& scenario_path, const LoadOptions& options = {});

// The keys of a scenario file's root (world, vehicles, security), and through them every key of the
// format (docs/ARCHITECTURE.md, "Keys: one declaration each"). A vehicle file's root is
// definition_keys() (config/vehicle_keys.h).
const KeyTable<Model, LoadContext>& scenario_keys();

// Loads and validates a scenario file. Never throws for bad input: every problem is a Diagnostic.
LoadResult load_scenario_file(const std::string& path, const LoadOptions& options = {});

}  // namespace hadal::config
