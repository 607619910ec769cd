// Seeded, stateless noise on the plane shared by the procedural seabed (geometry/terrain.h) and the
// seabed's sediment pattern (render/sediment_pattern.h): no global generator, every value a hash of
// its lattice point (docs/ARCHITECTURE.md, "Noise and random streams").
//
//   splitmix64(x)                Steele, Lea & Flood (2014): the finaliser of x + 0x9e3779b97f4a7c15
//   lattice(seed, i, j, octave)  uniform in [-1, 1) at lattice point (i, j) of an octave (ChainedLattice;
//                                value_noise and fbm take MixedLattice, a cheaper hash, instead)
//   value_noise(seed, x, y, o)   the lattice values interpolated across each unit cell with the
//                                quintic fade 6t^5 - 15t^4 + 10t^3, in [-1, 1)
//   fbm(seed, x, y, octaves)     fractal Brownian motion: octave k at frequency 2^k with weight 0.5^k,
//                                normalised by the sum of the weights, in [-1, 1)
#pragma once

#include <cstdint>

namespace hadal {

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

namespace noise {

// Uniform in [-1, 1) from the top 53 bits of a hash.
inline double signed_unit(std::uint64_t h) { return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0; }

// The procedural seabed's lattice: three chained splitmix64 rounds of the coordinates and the octave.
struct ChainedLattice {
  double operator()(std::uint64_t seed, std::int64_t i, std::int64_t j, int octave) const {
    return signed_unit(splitmix64(
        seed ^ splitmix64(static_cast<std::uint64_t>(i) ^
                          splitmix64(static_cast<std::uint64_t>(j) + static_cast<std::uint64_t>(octave)))));
  }
};

// One splitmix64 round of the seed and the coordinates and octave times odd constants: a third of
// ChainedLattice's cost, for the sediment pattern, which evaluates ~20 lattice points per camera pixel.
struct MixedLattice {
  double operator()(std::uint64_t seed, std::int64_t i, std::int64_t j, int octave) const {
    return signed_unit(splitmix64(seed ^ (static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull) ^
                                  (static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4Full) ^
                                  (static_cast<std::uint64_t>(octave) * 0x165667B19E3779F9ull)));
  }
};

inline double lattice(std::uint64_t seed, std::int64_t i, std::int64_t j, int octave) {
  return ChainedLattice{}(seed, i, j, octave);
}

inline double quintic_fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// floor(x) for |x| < 2^62, exact, without a libm call (baseline x86-64 has no SSE4.1 rounding).
inline std::int64_t floor_to_int(double x) {
  const auto i = static_cast<std::int64_t>(x);
  return static_cast<double>(i) > x ? i - 1 : i;
}

template <class Lattice = ChainedLattice>
double value_noise(std::uint64_t seed, double x, double y, int octave) {
  const Lattice lattice;
  const std::int64_t i = floor_to_int(x), j = floor_to_int(y);
  const double u = quintic_fade(x - static_cast<double>(i)), v = quintic_fade(y - static_cast<double>(j));
  const double a = lattice(seed, i, j, octave), b = lattice(seed, i + 1, j, octave);
  const double c = lattice(seed, i, j + 1, octave), d = lattice(seed, i + 1, j + 1, octave);
  return (a + (b - a) * u) + ((c + (d - c) * u) - (a + (b - a) * u)) * v;
}

template <class Lattice = ChainedLattice>
double fbm(std::uint64_t seed, double x, double y, int octaves) {
  double sum = 0.0, amplitude = 1.0, norm = 0.0, frequency = 1.0;
  for (int octave = 0; octave < octaves; ++octave) {
    sum += amplitude * value_noise<Lattice>(seed, x * frequency, y * frequency, octave);
    norm += amplitude;
    amplitude *= 0.5;
    frequency *= 2.0;
  }
  return sum / norm;
}

}  // namespace noise
}  // namespace hadal
