// The benchmarks' generated seabed (bench/raycast.cc, bench/render.cc): Q x Q quads over 1 km x 1 km at
// z ~ -100 m with 40 seeded Gaussian hills and hollows of 1-8 m, sigma 20-120 m (std::mt19937 seed 1);
// Q = 708 gives 1 002 528 triangles.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "hadal/geometry/triangle_mesh.h"

namespace hadal::bench {

inline constexpr float kSeabedSize = 1000.0f;  // seabed edge [m]

struct Bump {
  float x, y, sigma, amplitude;
};

inline std::vector<Bump> make_bumps() {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> position(-kSeabedSize / 2, kSeabedSize / 2), sigma(20.0f, 120.0f),
      amplitude(1.0f, 8.0f), sign(-1.0f, 1.0f);
  std::vector<Bump> bumps;
  for (int i = 0; i < 40; ++i) {
    const float a = amplitude(rng);
    bumps.push_back({position(rng), position(rng), sigma(rng), sign(rng) < 0 ? -a : a});
  }
  return bumps;
}

inline float seabed_height(const std::vector<Bump>& bumps, float x, float y) {
  float z = -100.0f;
  for (const Bump& b : bumps) {
    const float r2 = (x - b.x) * (x - b.x) + (y - b.y) * (y - b.y);
    z += b.amplitude * std::exp(-r2 / (2.0f * b.sigma * b.sigma));
  }
  return z;
}

inline hadal::geometry::TriangleMesh make_seabed(const std::vector<Bump>& bumps, int quads) {
  hadal::geometry::TriangleMesh mesh;
  const auto n = static_cast<std::size_t>(quads);
  mesh.positions.reserve(3 * (n + 1) * (n + 1));
  mesh.indices.reserve(6 * n * n);
  for (std::size_t j = 0; j <= n; ++j) {
    for (std::size_t i = 0; i <= n; ++i) {
      const float x = -kSeabedSize / 2 + kSeabedSize * static_cast<float>(i) / static_cast<float>(n);
      const float y = -kSeabedSize / 2 + kSeabedSize * static_cast<float>(j) / static_cast<float>(n);
      mesh.positions.insert(mesh.positions.end(), {x, y, seabed_height(bumps, x, y)});
    }
  }
  for (std::size_t j = 0; j < n; ++j) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto a = static_cast<std::uint32_t>(j * (n + 1) + i), b = a + 1;
      const auto c = a + static_cast<std::uint32_t>(n + 1), d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  }
  return mesh;
}

}  // namespace hadal::bench
