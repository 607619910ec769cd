#include "hadal/geometry/terrain.h"
#include "hadal/core/units.h"
#include "hadal/core/value_noise.h"

#include <algorithm>
#include <cmath>

namespace hadal::geometry {

namespace {

// The seabed's noise: hadal/core/value_noise.h, five octaves.
double fbm(std::uint64_t seed, double x, double y) { return noise::fbm(seed, x, y, 5); }

double smoothstep(double edge0, double edge1, double x) {
  if (edge1 <= edge0) return x < edge0 ? 0.0 : 1.0;
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace

HeightField procedural_seabed(const ProceduralSeabedSpec& spec) {
  HeightField field;
  field.nx = std::max(2, static_cast<int>(std::lround(spec.size_x / spec.resolution)) + 1);
  field.ny = std::max(2, static_cast<int>(std::lround(spec.size_y / spec.resolution)) + 1);
  field.dx = spec.size_x / (field.nx - 1);
  field.dy = spec.size_y / (field.ny - 1);
  field.x0 = -0.5 * spec.size_x;
  field.y0 = -0.5 * spec.size_y;
  field.heights.resize(static_cast<std::size_t>(field.nx) * field.ny);

  const double heading = kPi * (noise::lattice(spec.seed, 7, 11, 99) + 1.0);  // seeded slope direction
  const double ux = std::cos(heading), uy = std::sin(heading);
  const double tan_slope = std::tan(spec.slope);
  const std::uint64_t ridge_seed = splitmix64(spec.seed + 1);
  for (int j = 0; j < field.ny; ++j) {
    const double y = field.y0 + j * field.dy;
    for (int i = 0; i < field.nx; ++i) {
      const double x = field.x0 + i * field.dx;
      const double roughness = smoothstep(spec.plain_radius, 2.0 * spec.plain_radius, std::hypot(x, y));
      double h = spec.z_datum + tan_slope * (x * ux + y * uy);
      if (roughness > 0.0) {
        const double ridge = 1.0 - std::abs(fbm(ridge_seed, x / 70.0, y / 70.0));
        h += roughness * (spec.relief * fbm(spec.seed, x / 120.0, y / 120.0) + spec.ridge_height * ridge * ridge);
      }
      field.heights[static_cast<std::size_t>(j) * field.nx + i] = static_cast<float>(h);
    }
  }
  return field;
}

}  // namespace hadal::geometry
