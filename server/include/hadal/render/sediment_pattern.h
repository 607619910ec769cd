// A procedural sediment pattern on the seabed (docs/ARCHITECTURE.md, "Cameras"): the seabed's albedo
// varies across the sea floor as patches of lighter and darker sediment with grain inside them, so a
// camera sees texture to track and to judge motion by (a uniform albedo shows a smooth gradient only).
//
//   albedo(x, y) = seabed_albedo * clamp(1 + amplitude * (2 n(x, y) - 1), 0, 1/max(seabed_albedo))
//   n(x, y) = (fbm(x / scale, y / scale) + 1) / 2                                       (in [0, 1))
//
// fbm is seeded fractal value noise (octave k at frequency 2^k, weight 0.5^k, normalised by the sum of
// the weights; each octave the values of its integer lattice, uniform in [-1, 1), interpolated across
// each cell with the quintic fade 6t^5 - 15t^4 + 10t^3), like the procedural seabed's
// (hadal/core/value_noise.h) but with a lattice a camera can afford at every pixel: the value at point
// (i, j) of octave k is the top 24 bits of a murmur3-style finaliser of
// seed32 ^ (k + 1) C_k ^ i C_i ^ j C_j in 32-bit arithmetic (i, j taken modulo 2^32: the pattern repeats
// every 2^32 cells), evaluated in single precision for many points at once (vectorized). A batch takes
// its points as offsets from an origin whose whole lattice cell is split off in double precision, so the
// pattern stays sharp kilometres from the world origin.
// 'scale' is the size of the largest patches [m]; each further octave adds detail half that size with
// half the weight (4 octaves at 1 m show patches down to 12 cm grain). Seeded from world.seed: the same
// scenario gives the same sea floor. A function of the world position (x_W, y_W) only (to single
// precision), so the pattern stays on the ground as the camera moves.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>

#include "hadal/render/optics_spec.h"

namespace hadal::render {

// Throws std::invalid_argument naming the field: amplitude in [0, 1], scale > 0 and finite, octaves 1..8.
void validate(const SedimentPattern& pattern);

// n(x, y) above, in [0, 1].
double sediment_noise(const SedimentPattern& pattern, double x_m, double y_m);

// The seabed's albedo at (x, y) (formula above); the mean albedo itself when amplitude is 0.
Eigen::Array3d sediment_albedo(const SedimentPattern& pattern, const Eigen::Array3d& mean_albedo, double x_m,
                               double y_m);
// The same at `count` points (x_W, y_W) = origin_xy + (x[i], y[i]) [m] at once, in single precision,
// into r[i], g[i], b[i] (a camera band's seabed: vectorized).
void sediment_albedo(const SedimentPattern& pattern, const Eigen::Array3d& mean_albedo, const Eigen::Vector2d& origin_xy,
                     const float* x, const float* y, std::size_t count, float* r, float* g, float* b);

}  // namespace hadal::render
