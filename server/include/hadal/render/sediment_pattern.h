// A procedural sediment pattern on the seabed (docs/ARCHITECTURE.md, "Cameras"): the seabed's albedo
// varies across the sea floor as patches of lighter and darker sediment with grain inside them, so a
// camera sees texture to track and to judge motion by (a uniform albedo shows a smooth gradient only).
//
//   albedo(x, y) = seabed_albedo * clamp(1 + amplitude * (2 n(x, y) - 1), 0, 1/max(seabed_albedo))
//   n(x, y) = (fbm(seed, x / scale, y / scale, octaves) + 1) / 2                       (in [0, 1))
//
// fbm is the seeded fractal value noise of hadal/core/value_noise.h, the procedural seabed's own (with
// its cheaper MixedLattice hash):
// 'scale' is the size of the largest patches [m]; each further octave adds detail half that size with
// half the weight (4 octaves at 1 m show patches down to 12 cm grain). Seeded from world.seed: the same
// scenario gives the same sea floor. A function of the world position (x_W, y_W) only, so the pattern
// stays on the ground as the camera moves.
#pragma once

#include <Eigen/Core>

#include <cstdint>

namespace hadal::render {

struct SedimentPattern {
  double amplitude = 0.0;  // 0: uniform seabed; up to 1 (albedo from 0 to twice the mean)
  double scale_m = 1.0;    // size of the largest patches [m]
  int octaves = 4;         // 1..8
  std::uint64_t seed = 0;
};

// Throws std::invalid_argument naming the field: amplitude in [0, 1], scale > 0 and finite, octaves 1..8.
void validate(const SedimentPattern& pattern);

// n(x, y) above, in [0, 1].
double sediment_noise(const SedimentPattern& pattern, double x_m, double y_m);

// The seabed's albedo at (x, y) (formula above); the mean albedo itself when amplitude is 0.
Eigen::Array3d sediment_albedo(const SedimentPattern& pattern, const Eigen::Array3d& mean_albedo, double x_m,
                               double y_m);

}  // namespace hadal::render
