// Reading a soil region map (YAML world.soil.map; physics/terramechanics.h, SoilRegionMap): an 8-bit
// single-channel image (PNG, TIFF) whose pixel values are region numbers, 0 the world's soil and
// k >= 1 world.soil.regions[k - 1].
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <memory>
#include <string>

#include "hadal/physics/terramechanics.h"

namespace hadal::physics {

struct SoilMapLoad {
  std::shared_ptr<const SoilRegionMap> map;  // null on error
  std::string error;                         // "<file>: <problem>"
};

// The map in `file`, each pixel a square cell meters_per_pixel wide, centred on center_W, image row 0
// its north (+y) edge. Every pixel must name a region in 0 .. num_regions.
SoilMapLoad load_soil_region_map(const std::string& file, double meters_per_pixel, const Eigen::Vector2d& center_W,
                                 std::size_t num_regions);

}  // namespace hadal::physics
