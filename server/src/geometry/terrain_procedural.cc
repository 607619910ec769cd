#include "hadal/geometry/terrain.h"
#include "hadal/core/units.h"

#include <algorithm>
#include <cmath>

namespace hadal::geometry {

namespace {

// splitmix64: a stateless hash of lattice coordinates (no global generator: docs/ARCHITECTURE.md, "Noise and random streams").
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Uniform value in [-1, 1] at lattice point (i, j) of octave `octave`.
double lattice(std::uint64_t seed, std::int64_t i, std::int64_t j, int octave) {
  const std::uint64_t h = mix(seed ^ mix(static_cast<std::uint64_t>(i) ^ mix(static_cast<std::uint64_t>(j) +
                                                                             static_cast<std::uint64_t>(octave))));
  return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

double smooth(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }  // quintic fade

double value_noise(std::uint64_t seed, double x, double y, int octave) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto i = static_cast<std::int64_t>(fx), j = static_cast<std::int64_t>(fy);
  const double u = smooth(x - fx), v = smooth(y - fy);
  const double a = lattice(seed, i, j, octave), b = lattice(seed, i + 1, j, octave);
  const double c = lattice(seed, i, j + 1, octave), d = lattice(seed, i + 1, j + 1, octave);
  return (a + (b - a) * u) + ((c + (d - c) * u) - (a + (b - a) * u)) * v;
}

// 5-octave fractional Brownian motion, normalised to [-1, 1].
double fbm(std::uint64_t seed, double x, double y) {
  double sum = 0.0, amplitude = 1.0, norm = 0.0, frequency = 1.0;
  for (int octave = 0; octave < 5; ++octave) {
    sum += amplitude * value_noise(seed, x * frequency, y * frequency, octave);
    norm += amplitude;
    amplitude *= 0.5;
    frequency *= 2.0;
  }
  return sum / norm;
}

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

  const double heading = kPi * (lattice(spec.seed, 7, 11, 99) + 1.0);  // seeded slope direction
  const double ux = std::cos(heading), uy = std::sin(heading);
  const double tan_slope = std::tan(spec.slope);
  const std::uint64_t ridge_seed = mix(spec.seed + 1);
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
