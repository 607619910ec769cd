// The world's acoustics (YAML `world.acoustics`). What sonars hear of the world's surfaces (render/sonar.h,
// docs/ARCHITECTURE.md "Sonars"): Lambert's backscatter parameter mu [dB], sigma = mu cos^2(incidence) per
// unit area and steradian. The seabed's default is Mackenzie's (1961) deep-sea value, -27 dB; hulls (metal,
// GRP) are strong scatterers, -10 dB; a link's appearance.backscatter_db overrides the hulls' value. What
// acoustic positioning and modems hear (sensors/acoustic_channel.h): the spreading law of their
// transmission loss and the ambient noise (Wenz). Its keys are declared once in render::acoustics_keys()
// (server/src/render/acoustics_spec.cc).
#pragma once

#include "hadal/config/key_table_fwd.h"

namespace hadal {

// Wenz's ambient noise sources (sensors/acoustic_channel.h).
struct AmbientNoiseSpec {
  double shipping = 0.5;    // shipping activity, 0 (none) to 1 (heavy)
  double wind_speed = 5.0;  // at the surface [m/s] (sea state ~3)
};

struct AcousticsSpec {
  double seabed_backscatter_db = -27.0;
  double vehicle_backscatter_db = -10.0;
  double spreading_exponent = 2.0;  // k in TL = k 10 log10 r + alpha r (positioning and modems)
  AmbientNoiseSpec ambient_noise;
};

namespace render {
const config::KeyTable<AcousticsSpec>& acoustics_keys();
}  // namespace render

}  // namespace hadal
