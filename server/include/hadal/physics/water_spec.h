// The water column a scenario describes (YAML `world.water`): surface, density model, temperature and
// salinity, pressure, compressibility, pH and the current. physics/ocean.h models it; its keys, units,
// defaults and ranges are declared once in water_keys() (server/src/physics/water_spec.cc), and
// configs/REFERENCE.md shows them.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "hadal/config/key_table_fwd.h"

namespace hadal {

enum class DensityModel { kConstant, kRamp, kCtd };

// One row of a CTD cast: temperature (ITS-90) and practical salinity at a depth below the surface.
struct CtdSample {
  double depth = 0.0;        // [m] below the surface
  double temperature = 4.0;  // [degC] (YAML: temperature_degc)
  double salinity = 35.0;    // practical salinity [PSS-78, dimensionless]
};

// Water current: uniform + exponentially decaying shear + a first-order Gauss-Markov term, all in W.
struct CurrentSpec {
  Eigen::Vector3d uniform_W = Eigen::Vector3d::Zero();        // [m/s]
  Eigen::Vector3d shear_surface_W = Eigen::Vector3d::Zero();  // shear at the surface [m/s]
  double shear_decay_depth = 50.0;                            // e-folding depth of the shear [m]
  Eigen::Vector3d gauss_markov_sigma_W = Eigen::Vector3d::Zero();  // stationary std per axis [m/s]
  double gauss_markov_time_constant = 600.0;                       // [s]
};

// No ocean is deeper (the Challenger Deep, the deepest sounding, is about 10,935 m): the bound of every depth
// a scenario gives (a cast's rows, the pycnocline, a plane seabed below the surface) [m].
inline constexpr double kDeepestOcean_m = 11000.0;

struct WaterSpec {
  double surface_z = 0.0;  // water surface height in W [m]
  // Constant-model density [kg/m^3]. The lumped fluid model uses this one value whatever density_model
  // is; the reader sets it to rho0 (ramp) or the EOS-80 surface density of the first CTD row (ctd).
  double density = 1025.0;
  DensityModel density_model = DensityModel::kConstant;
  // Ramp model rho(d) = rho0 + pycnocline_density_increase * min(d, pycnocline_depth) / pycnocline_depth.
  double rho0 = 1025.0;                          // [kg/m^3]
  double pycnocline_depth = 1000.0;              // [m]
  double pycnocline_density_increase = 3.075;    // [kg/m^3] (+0.3 % of 1025)
  std::vector<CtdSample> ctd;                    // CTD model: >= 2 rows, depths strictly increasing
  double temperature = 4.0;                      // non-CTD water [degC]
  double salinity = 35.0;                        // non-CTD water (practical salinity)
  double atmospheric_pressure = 101325.0;        // at the surface [Pa]
  double bulk_modulus = 2.2e9;                   // K in kappa(d) = 1 - p(d)/K [Pa]
  double ph = 8.0;                               // sound absorption's boric acid term (physics/seawater.h)
  CurrentSpec current;
};

namespace physics {
// The keys of `world.water` (and its `current`).
const config::KeyTable<WaterSpec>& water_keys();
}  // namespace physics

}  // namespace hadal
