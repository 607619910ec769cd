#include "hadal/render/sediment_pattern.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hadal::render {
namespace {

// splitmix64 finaliser (as sensors/noise.h's splitmix64) of a lattice point and the seed, to [0, 1).
double lattice_value(std::int64_t i, std::int64_t j, std::uint64_t seed) {
  std::uint64_t z = seed ^ (static_cast<std::uint64_t>(i) * 0x9e3779b97f4a7c15ULL) ^
                    (static_cast<std::uint64_t>(j) * 0xc2b2ae3d27d4eb4fULL);
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

double smoothstep(double t) { return t * t * (3.0 - 2.0 * t); }

// floor(x) for |x| < 2^62 without libm (baseline x86-64 has no SSE4.1 round instruction).
std::int64_t floor_to_int(double x) {
  const auto i = static_cast<std::int64_t>(x);
  return static_cast<double>(i) > x ? i - 1 : i;
}

// Value noise at (x, y) in lattice units, in [0, 1).
double value_noise(double x, double y, std::uint64_t seed) {
  const std::int64_t i = floor_to_int(x), j = floor_to_int(y);
  const double u = smoothstep(x - static_cast<double>(i)), v = smoothstep(y - static_cast<double>(j));
  const double a = lattice_value(i, j, seed), b = lattice_value(i + 1, j, seed);
  const double c = lattice_value(i, j + 1, seed), d = lattice_value(i + 1, j + 1, seed);
  return (1.0 - v) * ((1.0 - u) * a + u * b) + v * ((1.0 - u) * c + u * d);
}

}  // namespace

void validate(const SedimentPattern& pattern) {
  if (!(pattern.amplitude >= 0.0 && pattern.amplitude <= 1.0)) {
    throw std::invalid_argument("amplitude: must be in [0, 1]");
  }
  if (!(pattern.scale_m > 0.0) || !std::isfinite(pattern.scale_m)) throw std::invalid_argument("scale: must be > 0 [m]");
  if (pattern.octaves < 1 || pattern.octaves > 8) throw std::invalid_argument("octaves: must be in 1..8");
}

double sediment_noise(const SedimentPattern& pattern, double x_m, double y_m) {
  double sum = 0.0, weight = 1.0, total = 0.0, frequency = 1.0 / pattern.scale_m;
  for (int k = 0; k < pattern.octaves; ++k) {
    // Each octave its own lattice (seed + k), so that the octaves' lattice points do not line up.
    sum += weight * value_noise(x_m * frequency, y_m * frequency, pattern.seed + static_cast<std::uint64_t>(k));
    total += weight;
    weight *= 0.5;
    frequency *= 2.0;
  }
  return sum / total;
}

Eigen::Array3d sediment_albedo(const SedimentPattern& pattern, const Eigen::Array3d& mean_albedo, double x_m,
                               double y_m) {
  if (!(pattern.amplitude > 0.0)) return mean_albedo;
  const double factor = 1.0 + pattern.amplitude * (2.0 * sediment_noise(pattern, x_m, y_m) - 1.0);
  const double brightest = mean_albedo.maxCoeff();
  return mean_albedo * std::clamp(factor, 0.0, brightest > 0.0 ? 1.0 / brightest : 1.0);
}

}  // namespace hadal::render
