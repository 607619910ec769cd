// What cameras see, as a scenario describes it (YAML `world.optics`): the water's absorption and
// scattering per colour channel, daylight from the surface, marine snow, and the albedo of the world's
// surfaces (render/optics.h, render/marine_snow.h, render/sediment_pattern.h model them). Its keys are
// declared once in render::optics_keys() (server/src/render/optics_spec.cc); configs/REFERENCE.md shows
// them. Channels are R, G, B bands (600-700, 500-600, 400-500 nm).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>

#include "hadal/config/key_table_fwd.h"

namespace hadal::render {

using Rgb = Eigen::Array3d;

struct WaterOptics {
  Rgb absorption_per_m = Rgb::Zero();  // a
  Rgb scattering_per_m = Rgb::Zero();  // b
  double phase_g = 0.924;              // Henyey–Greenstein asymmetry, -1 < g < 1
  // Light scattered within this angle of forward still reaches the camera, blurred
  // (render/forward_scatter.h); 0: none (the unscattered beam only). At most 30 deg.
  double forward_scatter_max_angle_rad = 0.0;
  Rgb attenuation_per_m() const { return absorption_per_m + scattering_per_m; }  // c
};

// Daylight: downwelling irradiance E0 [W/m^2] per channel just below the sea surface (z_W =
// surface_z_m), decaying with depth by the diffuse attenuation Kd: E_d(z) = E0 exp(-Kd (surface_z - z)),
// E0 above the surface. Its path radiance in the water is scattered from light travelling straight
// down; surfaces receive it as from a uniformly bright upper hemisphere (below). Below a few hundred metres it is negligible (Kd >= 0.02 /m in every Jerlov
// water type: exp(-0.02 * 1000) = 2e-9).
struct Daylight {
  Rgb surface_irradiance_W_per_m2 = Rgb::Zero();  // E0
  Rgb Kd_per_m = Rgb::Zero();
  double surface_z_m = 0.0;  // z_W of the sea surface over the camera [m]
  // The surface's unit normal there (tilted by waves: the camera sets it per frame) and the water's refractive
  // index, for the surface seen from below (Snell's window, render/frame.h).
  Eigen::Vector3d surface_normal_W = Eigen::Vector3d::UnitZ();
  double refractive_index = 1.34;
  Rgb irradiance_at(double z_W) const;
};

// Marine snow (render/marine_snow.h): a seeded field of particles fixed in the water.
struct MarineSnow {
  double density_per_m3 = 0.0;  // particles per cubic metre; 0: none
  double radius = 0.0015;     // mean particle radius (radii uniform in [0.5, 1.5] x this) [m]
  double max_range = 4.0;     // particles drawn up to this distance from the camera [m]
  double albedo = 0.7;
  std::uint64_t seed = 0;
};

// The seabed's sediment pattern (render/sediment_pattern.h).
struct SedimentPattern {
  double amplitude = 0.0;  // 0: uniform seabed; up to 1 (albedo from 0 to twice the mean)
  double scale_m = 1.0;    // size of the largest patches [m]
  int octaves = 4;         // 1..8
  std::uint64_t seed = 0;
};

}  // namespace hadal::render

namespace hadal {

// What cameras see (render/optics.h, docs/ARCHITECTURE.md "Cameras"). optics_keys().defaults() holds
// the defaults a scenario gets (pure water plus a little scattering, Jerlov type I daylight at the water
// surface); a default-constructed OpticsSpec is clear, dark water.
struct OpticsSpec {
  render::WaterOptics water;
  render::Daylight daylight;
  render::MarineSnow marine_snow;  // none by default; its seed is world.seed
  Eigen::Array3d seabed_albedo = Eigen::Array3d(0.30, 0.28, 0.22);   // sediment, per channel (R, G, B)
  render::SedimentPattern seabed_pattern;  // none by default (amplitude 0); its seed is world.seed
  Eigen::Array3d vehicle_albedo = Eigen::Array3d(0.85, 0.70, 0.15);  // hulls (survey-yellow)
};

namespace render {
// The keys of `world.optics`.
const config::KeyTable<OpticsSpec>& optics_keys();
}  // namespace render

}  // namespace hadal
