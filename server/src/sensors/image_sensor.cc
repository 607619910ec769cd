#include "hadal/sensors/image_sensor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hadal/core/validation_error.h"
#include "hadal/core/value_noise.h"
#include "hadal/render/fast_math.h"
#include "hadal/sensors/noise.h"

namespace hadal::sensors {
namespace {

namespace fast = render::fast;

constexpr float kExactPoissonBelow = 30.0f;  // electrons (header)
constexpr float kMergeSigmas = 6.0f;         // shot and read noise drawn as one normal (header)
constexpr std::uint32_t kSampleStep = 0x9E3779B1U;  // odd: j -> j C is a bijection of 32-bit indices

using validation::invalid;

// A frame's stream keys (header): four 32-bit keys from splitmix64 of the camera's key and the frame.
struct FrameKeys {
  std::uint32_t normal_radius, normal_angle, poisson, poisson_normal;
};

FrameKeys frame_keys(std::uint64_t key, std::uint64_t frame) {
  const std::uint64_t a = splitmix64(key ^ splitmix64(frame)), b = splitmix64(a);
  return FrameKeys{static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(a >> 32), static_cast<std::uint32_t>(b),
                   static_cast<std::uint32_t>(b >> 32)};
}

// Uniform in (0, 1) from the top 24 bits of a hash: never 0, so its log is finite.
inline float unit_open(std::uint32_t h) {
  return (static_cast<float>(static_cast<std::int32_t>(h >> 8)) + 0.5f) * (1.0f / 16777216.0f);
}

// Sample j's uniform of stream `stream_key`.
inline float uniform(std::uint32_t stream_key, std::uint32_t j) { return unit_open(mix32(stream_key ^ (j * kSampleStep))); }

// N(0, 1) by Box and Muller's transform, cosine half: sqrt(-2 ln u1) cos(2 pi u2).
inline float normal(std::uint32_t radius_key, std::uint32_t angle_key, std::uint32_t j) {
  return __builtin_sqrtf(-2.0f * fast::log(uniform(radius_key, j))) * fast::cos_2pi(uniform(angle_key, j));
}

constexpr std::size_t kChunk = 256;  // pixels per vectorized pass (even: pixel pairs stay in a chunk)
constexpr std::uint32_t kMaxPoissonSteps = 200;  // the inversion's search (P(k > 200 | mu < 30) < 1e-80)

// The sensor's constants as the passes use them.
struct Exposure {
  float read_noise, read_variance, full_well, gain;
  bool shot, vignetting;
};

// The read noise of `pairs` pixel pairs of one channel into z[q] and z[q + pairs]: the two halves of
// Box and Muller's transform, r cos(2 pi u2) and r sin(2 pi u2), r = sqrt(-2 ln u1), from the pair's
// two uniforms (stream keys normal_radius and normal_angle, index first_id + 3 q). Vectorized.
HADAL_VECTOR_KERNEL __attribute__((noinline)) void pair_normals(const FrameKeys& keys, std::uint32_t first_id,
                                                                std::uint32_t pairs, float* __restrict z) {
  const std::uint32_t radius_key = keys.normal_radius, angle_key = keys.normal_angle;
  float* __restrict second = z + pairs;
  for (std::uint32_t q = 0; q < pairs; ++q) {
    const std::uint32_t id = first_id + 3 * q;
    const float r = __builtin_sqrtf(-2.0f * fast::log(uniform(radius_key, id)));
    const float angle = uniform(angle_key, id);
    z[q] = r * fast::cos_2pi(angle);
    second[q] = r * fast::sin_2pi(angle);
  }
}

// One channel of m pixels (header): the mean electrons mu, the counts before rounding into dn, and
// exact[i] = 1 where the shot noise must be drawn exactly (the scalar pass), from the read noise z.
// Vectorized: the switches are template arguments (GCC does not vectorize a select on a loop-invariant
// bool), and the function is not inlined into its caller's chunk loop (where GCC no longer sees plain
// arrays).
template <bool kShot, bool kVignetting>
HADAL_VECTOR_KERNEL __attribute__((noinline)) void expose_channel(const Exposure& e, float scale,
                                                                  const float* __restrict radiance,
                                                                  const float* __restrict cos_theta,
                                                                  const float* __restrict z, std::uint32_t m,
                                                                  float* __restrict mean, float* __restrict dn,
                                                                  float* __restrict exact) {
  const float read_noise = e.read_noise, read_variance = e.read_variance, full_well = e.full_well, gain = e.gain;
  for (std::uint32_t i = 0; i < m; ++i) {
    const float c = fast::max(0.0f, cos_theta[i]), L = radiance[i], zi = z[i];
    const float mu = scale * fast::max(0.0f, L) * (kVignetting ? (c * c) * (c * c) : 1.0f);
    mean[i] = mu;
    if constexpr (kShot) {
      // Shot and read noise merged where neither clip can act; elsewhere the scalar pass draws them.
      const bool merged = (mu >= kExactPoissonBelow) & (mu + kMergeSigmas * __builtin_sqrtf(mu) <= full_well);
      dn[i] = fast::max(0.0f, fast::min(gain * (mu + __builtin_sqrtf(mu + read_variance) * zi), 255.0f));
      exact[i] = merged ? 0.0f : 1.0f;
    } else {
      dn[i] = fast::max(0.0f, fast::min(gain * (fast::min(mu, full_well) + read_noise * zi), 255.0f));
      exact[i] = 0.0f;
    }
  }
}

// u[i] = sample (first_j + 3 i)'s uniform of stream `key`, i < m (one channel's samples of a chunk).
HADAL_VECTOR_KERNEL __attribute__((noinline)) void uniforms(std::uint32_t key, std::uint32_t first_j, std::uint32_t m,
                                                            float* __restrict u) {
  for (std::uint32_t i = 0; i < m; ++i) u[i] = uniform(key, first_j + 3 * i);
}

// How a chunk's samples that need exact shot noise (exact[i] = 1) get it: by inversion where their mean
// is below kExactPoissonBelow, else by the normal approximation.
struct ShotDraws {
  std::uint32_t by_inversion = 0, normal = 0;  // how many of each
};

// Classifies m samples (ShotDraws): by_inversion[i] = 1 for the samples drawn by inversion, else 0, and
// small_mu[i] their mean, else 0 (their inversion stops at k = 0 at once). Integer counts: a float sum
// would not vectorize.
HADAL_VECTOR_KERNEL __attribute__((noinline)) ShotDraws classify(const float* __restrict exact,
                                                                 const float* __restrict mu, std::uint32_t m,
                                                                 float* __restrict by_inversion,
                                                                 float* __restrict small_mu) {
  std::uint32_t inverted = 0, approximated = 0;
  for (std::uint32_t i = 0; i < m; ++i) {
    const float mean = mu[i];
    const bool needed = exact[i] != 0.0f, low = mean < kExactPoissonBelow;
    by_inversion[i] = needed & low ? 1.0f : 0.0f;
    small_mu[i] = needed & low ? mean : 0.0f;
    inverted += needed & low ? 1u : 0u;
    approximated += needed & !low ? 1u : 0u;
  }
  return ShotDraws{inverted, approximated};
}

// dn[i] from the Poisson count k[i] and the read noise z[i] where by_inversion[i] is set; the other
// samples keep theirs.
HADAL_VECTOR_KERNEL __attribute__((noinline)) void counts_to_dn(const Exposure& e, const float* __restrict k,
                                                                const float* __restrict z, std::uint32_t m,
                                                                const float* __restrict by_inversion,
                                                                float* __restrict dn) {
  const float gain = e.gain, full_well = e.full_well, read_noise = e.read_noise;
  for (std::uint32_t i = 0; i < m; ++i) {
    const float counted = fast::max(0.0f, fast::min(gain * (fast::min(k[i], full_well) + read_noise * z[i]), 255.0f));
    dn[i] = by_inversion[i] != 0.0f ? counted : dn[i];
  }
}

// A chunk's m pixels of R, G, B (interleaved) into three planes, and back as rounded counts (half up):
// one statement per channel, so that GCC vectorizes the stride-3 accesses (with permutes).
HADAL_VECTOR_KERNEL __attribute__((noinline)) void split_channels(const float* __restrict rgb, std::size_t m,
                                                                  float* __restrict r, float* __restrict g,
                                                                  float* __restrict b) {
  for (std::size_t i = 0; i < m; ++i) {
    r[i] = rgb[3 * i];
    g[i] = rgb[3 * i + 1];
    b[i] = rgb[3 * i + 2];
  }
}

HADAL_VECTOR_KERNEL __attribute__((noinline)) void round_to_bytes(const float* __restrict r, const float* __restrict g,
                                                                  const float* __restrict b, std::size_t m,
                                                                  std::uint8_t* __restrict bytes) {
  for (std::size_t i = 0; i < m; ++i) {
    bytes[3 * i] = static_cast<std::uint8_t>(r[i] + 0.5f);
    bytes[3 * i + 1] = static_cast<std::uint8_t>(g[i] + 0.5f);
    bytes[3 * i + 2] = static_cast<std::uint8_t>(b[i] + 0.5f);
  }
}

// Poisson variates k[n] of means mu[n] < kExactPoissonBelow by inversion of the cumulative
// distribution with the uniforms u[n]: the smallest k with u < P(K <= k). Vectorized across the
// samples: each step of the search updates every sample still searching, until none is.
HADAL_VECTOR_KERNEL __attribute__((noinline)) void poisson_by_inversion(const float* __restrict mu,
                                                                        const float* __restrict u, std::uint32_t n,
                                                                        float* __restrict k) {
  float p[kChunk], cumulative[kChunk];
  for (std::uint32_t i = 0; i < n; ++i) {
    p[i] = fast::exp(-mu[i]);
    cumulative[i] = p[i];
    k[i] = 0.0f;
  }
  for (std::uint32_t step = 1; step <= kMaxPoissonSteps; ++step) {
    const auto s = static_cast<float>(step);
    int searching = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      const float pi = p[i], ci = cumulative[i], ki = k[i], next = pi * (mu[i] / s);
      const bool on = u[i] >= ci;
      p[i] = on ? next : pi;
      cumulative[i] = on ? ci + next : ci;
      k[i] = on ? s : ki;
      searching |= on ? 1 : 0;
    }
    if (searching == 0) break;
  }
}

// The counts of pixels [begin, end) (header), in chunks: the radiance split into channel planes, each
// channel's read noise, mean and merged case in vectorized passes, then the exact shot noise of the
// samples that need it (inversion across the whole chunk, vectorized; the normal approximation point
// by point, compacted).
void expose_pixels(const ImageSensorSpec& spec, const Eigen::Array3f* radiance, const float* cos_theta,
                   const FrameKeys& keys, std::size_t begin, std::size_t end, std::uint8_t* rgb) {
  const auto read_noise = static_cast<float>(spec.read_noise_e);
  const Exposure e{read_noise, read_noise * read_noise, static_cast<float>(spec.full_well_e),
                   static_cast<float>(spec.gain_dn_per_e), spec.shot_noise, spec.vignetting};
  const auto expose = e.shot ? (e.vignetting ? expose_channel<true, true> : expose_channel<true, false>)
                             : (e.vignetting ? expose_channel<false, true> : expose_channel<false, false>);
  float plane[3][kChunk];  // the chunk's radiance per channel
  float z[3][kChunk + 1], mean[3][kChunk], dn[3][kChunk], exact[3][kChunk];  // z: one spare for odd m
  std::uint32_t index[kChunk];
  float by_inversion[kChunk], small_mu[kChunk], small_u[kChunk], small_k[kChunk];
  for (std::size_t first = begin; first < end; first += kChunk) {
    const std::size_t m = std::min(kChunk, end - first);
    split_channels(radiance[first].data(), m, plane[0], plane[1], plane[2]);  // R, G, B per pixel
    for (int ch = 0; ch < 3; ++ch) {
      // The chunk's pixels q and q + h (h = ceil(m / 2); chunks start at even pixels) share their
      // channel's Box-Muller draw, index 3 (first / 2 + q) + ch: unique in the frame.
      pair_normals(keys, static_cast<std::uint32_t>(3 * (first / 2) + static_cast<std::size_t>(ch)),
                   static_cast<std::uint32_t>((m + 1) / 2), z[ch]);
      const auto scale = static_cast<float>(spec.sensitivity[ch] * spec.exposure_s);  // e- per W/(m^2 sr)
      expose(e, scale, plane[ch], cos_theta + first, z[ch], static_cast<std::uint32_t>(m), mean[ch], dn[ch], exact[ch]);
      if (!e.shot) continue;
      // The samples needing exact shot noise: those of means below kExactPoissonBelow by inversion,
      // across the whole chunk at once (a dark deep-sea frame's most: the other lanes get mean 0, so
      // k = 0 at once, and keep their counts), and those near the full well by the normal
      // approximation, point by point (compacted: few).
      const auto first_j = static_cast<std::uint32_t>(3 * first + static_cast<std::size_t>(ch));  // pixel i's sample: first_j + 3 i
      const ShotDraws draws = classify(exact[ch], mean[ch], static_cast<std::uint32_t>(m), by_inversion, small_mu);
      if (draws.normal > 0) {
        std::uint32_t large = 0;
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(m); ++i) {
          index[large] = i;
          large += exact[ch][i] != 0.0f && by_inversion[i] == 0.0f ? 1 : 0;
        }
        for (std::uint32_t n = 0; n < large; ++n) {
          const std::uint32_t i = index[n];
          const float mu = mean[ch][i];
          const float shot_e = fast::max(0.0f, mu + __builtin_sqrtf(mu) * normal(keys.poisson, keys.poisson_normal, first_j + 3 * i));
          dn[ch][i] = fast::max(0.0f, fast::min(e.gain * (fast::min(shot_e, e.full_well) + e.read_noise * z[ch][i]), 255.0f));
        }
      }
      if (draws.by_inversion == 0) continue;
      uniforms(keys.poisson, first_j, static_cast<std::uint32_t>(m), small_u);
      poisson_by_inversion(small_mu, small_u, static_cast<std::uint32_t>(m), small_k);
      counts_to_dn(e, small_k, z[ch], static_cast<std::uint32_t>(m), by_inversion, dn[ch]);
    }
    round_to_bytes(dn[0], dn[1], dn[2], m, rgb + 3 * first);
  }
}

}  // namespace

void validate(const ImageSensorSpec& spec) {
  if (!spec.sensitivity.allFinite() || !(spec.sensitivity > 0.0).all()) invalid("sensitivity", "must be positive per channel");
  if (!(spec.exposure_s > 0.0) || !std::isfinite(spec.exposure_s)) invalid("exposure_s", "must be positive [s]");
  if (!(spec.gain_dn_per_e > 0.0) || !std::isfinite(spec.gain_dn_per_e)) invalid("gain", "must be positive [DN/e-]");
  if (!(spec.full_well_e > 0.0) || !std::isfinite(spec.full_well_e)) invalid("full_well_e", "must be positive [e-]");
  if (!(spec.read_noise_e >= 0.0) || !std::isfinite(spec.read_noise_e)) invalid("read_noise_e", "must be >= 0 [e-]");
}

Eigen::Array3d negligible_radiance(const ImageSensorSpec& spec, double counts) {
  validate(spec);
  return counts / (spec.gain_dn_per_e * spec.sensitivity * spec.exposure_s);
}

std::vector<std::uint8_t> expose_rgb8(const ImageSensorSpec& spec, const std::vector<Eigen::Array3f>& radiance,
                                      const std::vector<float>& cos_theta, std::uint64_t key, std::uint64_t frame_index,
                                      const ParallelFor& parallel) {
  validate(spec);
  if (cos_theta.size() != radiance.size()) throw std::invalid_argument("expose_rgb8: one cos_theta per pixel needed");
  if (radiance.size() > kMaxExposurePixels) {
    throw std::invalid_argument("expose_rgb8: at most " + std::to_string(kMaxExposurePixels) + " pixels");
  }
  std::vector<std::uint8_t> rgb(3 * radiance.size());
  const FrameKeys keys = frame_keys(key, frame_index);
  const std::size_t blocks = (radiance.size() + kExposureBlockPixels - 1) / kExposureBlockPixels;
  parallel(blocks, [&](std::size_t block) {
    const std::size_t begin = block * kExposureBlockPixels;
    expose_pixels(spec, radiance.data(), cos_theta.data(), keys, begin,
                  std::min(radiance.size(), begin + kExposureBlockPixels), rgb.data());
  });
  return rgb;
}

}  // namespace hadal::sensors
