// What a scenario says of a heightmap or procedural seabed (geometry/terrain.h builds them; the model
// in terrain.h's header comment). A spec holding them includes this, not the terrain builder.
#pragma once

#include <cstdint>
#include <string>

namespace hadal::geometry {

struct HeightmapSpec {
  std::string file;               // 16-bit (or 8-bit) single-channel PNG or TIFF
  double meters_per_pixel = 1.0;  // > 0
  double height_min = -100.0;     // z of pixel value 0 [m]
  double height_max = -90.0;      // z of the largest pixel value (65535 or 255) [m]
};

struct ProceduralSeabedSpec {
  double size_x = 400.0, size_y = 400.0;  // extent, centred on the origin [m]
  double resolution = 2.0;                // sample spacing [m]
  double z_datum = -100.0;                // height of the sediment plain [m]
  double relief = 6.0;                    // fbm amplitude [m]
  double ridge_height = 4.0;              // [m]
  double slope = 0.0;                     // regional slope [rad]
  double plain_radius = 60.0;             // [m]
  std::uint64_t seed = 0;
};

}  // namespace hadal::geometry
