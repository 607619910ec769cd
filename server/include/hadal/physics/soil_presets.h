// Soil presets (YAML world.soil.preset): Bekker-Wong parameters of published soils, in SI, from the
// table docs/reference/terramechanics/bekker_parameters.csv (its units: k_c kN/m^(n+1), k_phi kN/m^(n+2),
// c kPa, phi deg, K m; its sources per row) and the deep-sea sediment preset documented in
// docs/reference/terramechanics/deep_sea_ooze.md. soil_presets_test.cc recomputes every preset from
// those files. Where the table leaves K blank the preset says what it assumes.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "hadal/physics/terramechanics.h"

namespace hadal::physics {

struct SoilPreset {
  std::string name;        // YAML name, e.g. "dry_sand"
  std::string table_row;   // the `soil` column of its row in the reference table
  SoilParameters soil;     // SI; damping and shear_damping_time at their defaults
  std::string note;        // what the preset assumes beyond its row ("" if nothing)
};

const std::vector<SoilPreset>& soil_presets();
// The preset of that name, or null.
const SoilPreset* find_soil_preset(std::string_view name);
// The presets' names, comma-separated (for error messages).
std::string soil_preset_names();

}  // namespace hadal::physics
