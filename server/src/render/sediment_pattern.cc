#include "hadal/render/sediment_pattern.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hadal/core/value_noise.h"
#include "hadal/render/fast_math.h"

namespace hadal::render {
namespace {

// Uniform in [-1, 1) from the top 24 bits of a hash.
inline float lattice_value(std::uint32_t h) {
  return static_cast<float>(static_cast<std::int32_t>(h >> 8)) * (2.0f / 16777216.0f) - 1.0f;
}

constexpr std::uint32_t kStepI = 0x9E3779B1U;  // odd constants that spread lattice indices over the key
constexpr std::uint32_t kStepJ = 0x85EBCA77U;
constexpr std::uint32_t kStepOctave = 0xC2B2AE3DU;

// fbm (header) at count points origin_xy + (x[i], y[i]) into out[i], in [-1, 1).
HADAL_VECTOR_KERNEL void fbm(const SedimentPattern& pattern, const Eigen::Vector2d& origin_xy, const float* x, const float* y,
         std::size_t count, float* out) {
  // The origin in lattice units, split into a whole cell (exact, 64-bit) and the fraction: the points'
  // offsets then stay small enough for single precision.
  const double inv_scale = 1.0 / pattern.scale_m;
  const double ox = origin_xy.x() * inv_scale, oy = origin_xy.y() * inv_scale;
  const double cell_x = std::floor(ox), cell_y = std::floor(oy);
  const auto base_i = static_cast<std::uint64_t>(static_cast<std::int64_t>(cell_x));
  const auto base_j = static_cast<std::uint64_t>(static_cast<std::int64_t>(cell_y));
  const auto fx = static_cast<float>(ox - cell_x), fy = static_cast<float>(oy - cell_y);
  const auto inv = static_cast<float>(inv_scale);
  const auto seed = static_cast<std::uint32_t>(pattern.seed ^ (pattern.seed >> 32));
  std::fill(out, out + count, 0.0f);
  float amplitude = 1.0f, norm = 0.0f;
  for (int octave = 0; octave < pattern.octaves; ++octave) {
    const auto frequency = static_cast<float>(1 << octave);
    const auto bi = static_cast<std::uint32_t>(base_i << octave), bj = static_cast<std::uint32_t>(base_j << octave);
    const std::uint32_t key = seed ^ (static_cast<std::uint32_t>(octave + 1) * kStepOctave);
    for (std::size_t i = 0; i < count; ++i) {  // vectorized
      const float u = (fx + x[i] * inv) * frequency, v = (fy + y[i] * inv) * frequency;
      // floor by truncation and a step down for negative non-integers
      std::int32_t iu = static_cast<std::int32_t>(u), iv = static_cast<std::int32_t>(v);
      iu = static_cast<float>(iu) > u ? iu - 1 : iu;
      iv = static_cast<float>(iv) > v ? iv - 1 : iv;
      const float tu = u - static_cast<float>(iu), tv = v - static_cast<float>(iv);
      const std::uint32_t a0 = (bi + static_cast<std::uint32_t>(iu)) * kStepI, a1 = a0 + kStepI;
      const std::uint32_t b0 = (bj + static_cast<std::uint32_t>(iv)) * kStepJ, b1 = b0 + kStepJ;
      const float v00 = lattice_value(hadal::mix32(key ^ a0 ^ b0)), v10 = lattice_value(hadal::mix32(key ^ a1 ^ b0));
      const float v01 = lattice_value(hadal::mix32(key ^ a0 ^ b1)), v11 = lattice_value(hadal::mix32(key ^ a1 ^ b1));
      const float su = tu * tu * tu * (tu * (tu * 6.0f - 15.0f) + 10.0f);  // quintic fade
      const float sv = tv * tv * tv * (tv * (tv * 6.0f - 15.0f) + 10.0f);
      const float bottom = v00 + (v10 - v00) * su, top = v01 + (v11 - v01) * su;
      out[i] += amplitude * (bottom + (top - bottom) * sv);
    }
    norm += amplitude;
    amplitude *= 0.5f;
  }
  const float inv_norm = 1.0f / norm;
  for (std::size_t i = 0; i < count; ++i) out[i] *= inv_norm;
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
  const float zero = 0.0f;
  float value = 0.0f;
  fbm(pattern, Eigen::Vector2d(x_m, y_m), &zero, &zero, 1, &value);
  return 0.5 * (static_cast<double>(value) + 1.0);
}

Eigen::Array3d sediment_albedo(const SedimentPattern& pattern, const Eigen::Array3d& mean_albedo, double x_m,
                               double y_m) {
  if (!(pattern.amplitude > 0.0)) return mean_albedo;
  const double factor = 1.0 + pattern.amplitude * (2.0 * sediment_noise(pattern, x_m, y_m) - 1.0);
  const double brightest = mean_albedo.maxCoeff();
  return mean_albedo * std::clamp(factor, 0.0, brightest > 0.0 ? 1.0 / brightest : 1.0);
}

void sediment_albedo(const SedimentPattern& pattern, const Eigen::Array3d& mean_albedo, const Eigen::Vector2d& origin_xy,
                     const float* x, const float* y, std::size_t count, float* r, float* g, float* b) {
  const float mean_r = static_cast<float>(mean_albedo[0]), mean_g = static_cast<float>(mean_albedo[1]);
  const float mean_b = static_cast<float>(mean_albedo[2]);
  if (!(pattern.amplitude > 0.0)) {
    std::fill(r, r + count, mean_r);
    std::fill(g, g + count, mean_g);
    std::fill(b, b + count, mean_b);
    return;
  }
  fbm(pattern, origin_xy, x, y, count, r);  // the noise in r first
  const auto amplitude = static_cast<float>(pattern.amplitude);
  const double brightest = mean_albedo.maxCoeff();
  const auto top = static_cast<float>(brightest > 0.0 ? 1.0 / brightest : 1.0);
  for (std::size_t i = 0; i < count; ++i) {
    const float factor = std::clamp(1.0f + amplitude * r[i], 0.0f, top);
    r[i] = mean_r * factor;
    g[i] = mean_g * factor;
    b[i] = mean_b * factor;
  }
}

}  // namespace hadal::render
