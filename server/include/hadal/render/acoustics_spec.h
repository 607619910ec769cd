// The world's acoustics (YAML `world.acoustics`). What sonars hear of the world's surfaces (render/sonar.h,
// docs/ARCHITECTURE.md "Sonars"): Lambert's backscatter parameter mu [dB], sigma = mu cos^2(incidence) per
// unit area and steradian. The seabed's default is Mackenzie's (1961) deep-sea value, -27 dB; hulls (metal,
// GRP) are strong scatterers, -10 dB; a link's appearance.backscatter_db overrides the hulls' value; the sea
// surface seen from below, -30 dB (a moderate wind, Chapman and Harris 1962). What
// acoustic positioning and modems hear (sensors/acoustic_channel.h): the spreading law of their
// transmission loss and the ambient noise (Wenz). Its keys are declared once in render::acoustics_keys()
// (server/src/render/acoustics_spec.cc).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "hadal/config/key_table_fwd.h"

namespace hadal {

// Wenz's ambient noise sources (sensors/acoustic_channel.h).
struct AmbientNoiseSpec {
  double shipping = 0.5;    // shipping activity, 0 (none) to 1 (heavy)
  double wind_speed = 5.0;  // at the surface [m/s] (sea state ~3)
};

// A long-baseline beacon (YAML `world.acoustics.beacons[]`): a transponder fixed in W, which LBL sensors
// interrogate (sensors/lbl_sensor.h).
struct BeaconSpec {
  std::string name;
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // [m]
  double source_level_db = 185.0;                 // the reply, dB re 1 uPa at 1 m
  double detection_threshold_db = 10.0;           // SNR an interrogation needs to be heard [dB]
  double turnaround_s = 0.05;                     // [s]
};

struct AcousticsSpec {
  double seabed_backscatter_db = -27.0;
  double vehicle_backscatter_db = -10.0;
  double surface_backscatter_db = -30.0;  // the sea surface from below
  double spreading_exponent = 2.0;  // k in TL = k 10 log10 r + alpha r (positioning and modems)
  AmbientNoiseSpec ambient_noise;
  std::vector<BeaconSpec> beacons;
};

namespace render {
const config::KeyTable<AcousticsSpec>& acoustics_keys();

// The keys of what replies to an acoustic interrogation (a beacon, a vehicle's transponder), declared once for
// a Spec with source_level_db, detection_threshold_db and turnaround_s; `interrogator` names what subtracts
// the turnaround. Defined in render/responder_keys.h (include it with config/key_table.h).
template <class Spec, class Ctx>
void declare_responder_keys(config::KeyTable<Spec, Ctx>& t, const char* interrogator);
}  // namespace render

}  // namespace hadal
