// The seabed's soil a scenario describes (YAML `world.soil`): Bekker-Wong parameters in SI, a preset of
// published ones (physics/soil_presets.h) with any of them overridden, and soils by region placed by an
// image. physics/terramechanics.h presses and shears vehicles' faces into it. Its keys are declared once
// in physics::soil_keys() (server/src/physics/soil_spec.cc); configs/REFERENCE.md shows them.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hadal/config/key_table_fwd.h"

namespace hadal::physics {

// Bekker-Wong soil, SI units (YAML world.soil; presets in physics/soil_presets.h).
struct SoilParameters {
  double sinkage_exponent = 1.0;           // n [-], > 0
  double k_c = 0.0;                        // cohesive modulus of deformation [N/m^(n+1)], >= 0
  double k_phi = 0.0;                      // frictional modulus of deformation [N/m^(n+2)], >= 0
  double cohesion = 0.0;                   // c [Pa], >= 0
  double friction_angle = 0.0;             // phi [rad], in [0, pi/2)
  double shear_deformation_modulus = 0.01; // K [m], > 0
  double damping = 2.0e4;                  // c_d [Pa s/m], >= 0 (normal damping)
  double shear_damping_time = 0.02;        // eta [s], >= 0 (Rayleigh damping of the shear)

  // p(z) [Pa] under a patch of width b [m] at sinkage z [m] (0 for z <= 0).
  double pressure(double sinkage, double width) const;
  // tau_max = c + p tan(phi) [Pa].
  double shear_strength(double pressure) const;
  // Static sinkage of a flat patch of area A and width b under load W: z = (W / (A (k_c/b + k_phi)))^(1/n).
  double static_sinkage(double load, double area, double width) const;
};

// Which soil is where (YAML world.soil.map and regions, configs/REFERENCE.md): an image of region
// indices laid over the horizontal plane of W like a heightmap seabed (centred on center_W, image row 0
// its north (+y) edge), each pixel a square cell meters_per_pixel wide. Region 0 -- and everywhere
// outside the image -- is the world's soil, region k >= 1 the k-th entry of world.soil.regions.
struct SoilRegionMap {
  int columns = 0, rows = 0;
  double meters_per_pixel = 1.0;                       // [m]
  Eigen::Vector2d center_W = Eigen::Vector2d::Zero();  // [m]
  std::vector<std::uint8_t> index;                     // row-major, row 0 the north edge

  // The region of the cell that holds (x, y) in W; 0 outside the image.
  std::size_t region_at(double x_W, double y_W) const;
};

// A world's soils: soils[0] everywhere the map does not name another (no map: everywhere).
struct SoilLayout {
  std::vector<SoilParameters> soils;         // non-empty
  std::shared_ptr<const SoilRegionMap> map;  // null: one soil

  std::size_t region_at(double x_W, double y_W) const { return map ? map->region_at(x_W, y_W) : 0; }
};

}  // namespace hadal::physics

namespace hadal {

// The world's soil: a preset with any parameter overridden, used by vehicles with seabed_contact soil.
// Default-constructed it is no soil at all; soil_keys().defaults() is the deep-sea ooze a scenario gets
// when it says nothing.
struct SoilSpec {
  std::string preset = "deep_sea_ooze";  // the preset the parameters started from ("" if none)
  physics::SoilParameters parameters;    // SI, filled by the reader
  // Soils by region (world.soil.regions and map): the map's region k >= 1 is regions[k - 1]; region 0
  // and everywhere off the map is `parameters`.
  struct Region {
    std::string preset = "deep_sea_ooze";
    physics::SoilParameters parameters;
  };
  std::vector<Region> regions;
  std::shared_ptr<const physics::SoilRegionMap> map;  // null: `parameters` everywhere

  physics::SoilLayout layout() const {
    physics::SoilLayout layout{{parameters}, map};
    for (const Region& region : regions) layout.soils.push_back(region.parameters);
    return layout;
  }
};

namespace physics {
// The keys of `world.soil`.
const config::KeyTable<SoilSpec>& soil_keys();
}  // namespace physics

}  // namespace hadal
