// What sonars hear of the world's surfaces (YAML `world.acoustics`; render/sonar.h, docs/ARCHITECTURE.md
// "Sonars"): Lambert's backscatter parameter mu [dB], sigma = mu cos^2(incidence) per unit area and
// steradian. The seabed's default is Mackenzie's (1961) deep-sea value, -27 dB; hulls (metal, GRP) are
// strong scatterers, -10 dB; a link's appearance.backscatter_db overrides the hulls' value. Its keys are
// declared once in render::acoustics_keys() (server/src/render/acoustics_spec.cc).
#pragma once

#include "hadal/config/key_table_fwd.h"

namespace hadal {

struct AcousticsSpec {
  double seabed_backscatter_db = -27.0;
  double vehicle_backscatter_db = -10.0;
};

namespace render {
const config::KeyTable<AcousticsSpec>& acoustics_keys();
}  // namespace render

}  // namespace hadal
