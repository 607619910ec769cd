// Seeded, stateless noise on the plane of the procedural seabed (geometry/terrain.h; the sediment
// pattern, render/sediment_pattern.h, has its own 32-bit lattice): no global generator, every value a
// hash of its lattice point (docs/ARCHITECTURE.md, "Noise and random streams").
//
//   splitmix64(x)                Steele, Lea & Flood (2014): the finaliser of x + 0x9e3779b97f4a7c15
//   fnv1a(text)                  FNV-1a 64 of a name, to key a stream by it (the ocean's current, the waves)
//   mix32(h)                     a 32-bit finaliser for per-pixel hashes (below)
//   lattice(seed, i, j, octave)  uniform in [-1, 1) at lattice point (i, j) of an octave (ChainedLattice)
//   value_noise(seed, x, y, o)   the lattice values interpolated across each unit cell with the
//                                quintic fade 6t^5 - 15t^4 + 10t^3, in [-1, 1)
//   fbm(seed, x, y, octaves)     fractal Brownian motion: octave k at frequency 2^k with weight 0.5^k,
//                                normalised by the sum of the weights, in [-1, 1)
#pragma once

#include <cstdint>
#include <string_view>

namespace hadal {

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline std::uint64_t fnv1a(std::string_view text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

// murmur3's 32-bit finaliser (Appleby), with Wellons' constants (lowbias32): a bijection of 32-bit keys
// whose output bits each depend on every input bit; cheap enough for a camera's every pixel, and in
// 32-bit integer arithmetic, which vectorizes (render/sediment_pattern.h, sensors/image_sensor.h).
inline std::uint32_t mix32(std::uint32_t h) {
  h ^= h >> 16;
  h *= 0x7feb352dU;
  h ^= h >> 15;
  h *= 0x846ca68bU;
  h ^= h >> 16;
  return h;
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

}  // namespace noise
}  // namespace hadal
