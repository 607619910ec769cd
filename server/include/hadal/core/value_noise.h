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

// The four lattice values around a unit cell: (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1).
struct Cell {
  std::int64_t i = 0, j = 0;
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0;
};

template <class Lattice>
Cell lattice_cell(std::uint64_t seed, std::int64_t i, std::int64_t j, int octave) {
  const Lattice lattice;
  return Cell{i, j, lattice(seed, i, j, octave), lattice(seed, i + 1, j, octave), lattice(seed, i, j + 1, octave),
              lattice(seed, i + 1, j + 1, octave)};
}

// The cell's values interpolated at (x, y) inside it.
inline double interpolate(const Cell& cell, double x, double y) {
  const double u = quintic_fade(x - static_cast<double>(cell.i)), v = quintic_fade(y - static_cast<double>(cell.j));
  return (cell.a + (cell.b - cell.a) * u) + ((cell.c + (cell.d - cell.c) * u) - (cell.a + (cell.b - cell.a) * u)) * v;
}

template <class Lattice = ChainedLattice>
double value_noise(std::uint64_t seed, double x, double y, int octave) {
  return interpolate(lattice_cell<Lattice>(seed, floor_to_int(x), floor_to_int(y), octave), x, y);
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

// fbm remembering the last cell of each octave: the same values, for callers that evaluate points in
// sequence close together (a camera's pixels along a row share each coarse cell with dozens of
// neighbours), which then hash a cell's four lattice values once instead of at every point. One
// instance per thread.
template <class Lattice, int kMaxOctaves = 8>
class FbmMemo {
 public:
  double operator()(std::uint64_t seed, double x, double y, int octaves) {
    if (seed != seed_) {
      seed_ = seed;
      for (bool& v : valid_) v = false;
    }
    double sum = 0.0, amplitude = 1.0, norm = 0.0, frequency = 1.0;
    for (int octave = 0; octave < octaves; ++octave) {
      const double xo = x * frequency, yo = y * frequency;
      const std::int64_t i = floor_to_int(xo), j = floor_to_int(yo);
      if (octave >= kMaxOctaves) {
        sum += amplitude * interpolate(lattice_cell<Lattice>(seed, i, j, octave), xo, yo);
      } else {
        Cell& cell = cells_[octave];
        if (!valid_[octave] || cell.i != i || cell.j != j) {
          cell = lattice_cell<Lattice>(seed, i, j, octave);
          valid_[octave] = true;
        }
        sum += amplitude * interpolate(cell, xo, yo);
      }
      norm += amplitude;
      amplitude *= 0.5;
      frequency *= 2.0;
    }
    return sum / norm;
  }

 private:
  std::uint64_t seed_ = 0;
  Cell cells_[kMaxOctaves];
  bool valid_[kMaxOctaves] = {};
};

}  // namespace noise
}  // namespace hadal
