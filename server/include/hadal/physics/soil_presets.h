// Soil presets (YAML world.soil.preset): Bekker-Wong parameters of published soils, in SI, from the
// table docs/reference/terramechanics/bekker_parameters.csv (its units: k_c kN/m^(n+1), k_phi kN/m^(n+2),
// c kPa, phi deg, K m; its sources per row) and the deep-sea sediment preset documented in
// docs/reference/terramechanics/deep_sea_ooze.md. soil_presets_test.cc recomputes every preset from
// those files. Where the table leaves K blank the preset says what it assumes.
#pragma once

#include "hadal/config/preset.h"
#include "hadal/physics/terramechanics.h"

namespace hadal::physics {

// Each preset's figures are its parameters in SI; its product is the `soil` column of its row in the
// reference table, its source the table and what the preset assumes beyond the row.
const config::Presets<SoilParameters>& soil_presets();

}  // namespace hadal::physics
