// e^x, ln x and acos x in single precision as branch-free scalar code: inside a loop over float arrays
// the compiler turns them into SIMD (GCC -O3 vectorizes render/frame.cc's per-pixel passes through
// them), and they give the same bits on every x86-64 CPU (IEEE operations only, no FMA contraction on
// the baseline ISA, no libm). Accuracy (render/fast_math_test.cc, against std:: over 1e6 arguments):
//   fast::exp   Cephes expf: x = n ln 2 + r, |r| <= ln 2 / 2, a degree-7 polynomial for e^r times 2^n;
//               within 2 ulp for x in [-87.3, 88]; x below gives e^-87.3 ~ 1.2e-38 (no denormals),
//               above gives e^88.
//   fast::log   Cephes logf: x = m 2^e with m in [sqrt(1/2), sqrt(2)), a degree-9 polynomial in m - 1;
//               within 2 ulp for positive normal x (what the renderer passes: ratios of distances >= 1).
//   fast::acos  Cephes asinf's polynomial on [0, 1/2], acos(x) = 2 asin(sqrt((1 - x) / 2)) above it and
//               pi - acos(-x) below zero; within 3e-7 rad on [-1, 1] (clamped outside).
//   fast::cos_2pi, sin_2pi  cos(2 pi u) and sin(2 pi u) for u in [0, 1] (below), within 1e-7.
#pragma once

#include <cstdint>
#include <cstring>

// Functions whose loops call these are marked HADAL_VECTOR_KERNEL: compiled for AVX-512, AVX2 and the
// baseline, every version giving the same bits.
#include "hadal/core/vector_kernel.h"

namespace hadal::render::fast {

inline float from_bits(std::int32_t bits) {
  float x;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

inline std::int32_t to_bits(float x) {
  std::int32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return bits;
}

inline float min(float a, float b) { return b < a ? b : a; }
inline float max(float a, float b) { return a < b ? b : a; }

inline float exp(float x) {
  constexpr float kLog2e = 1.44269504088896341f;
  constexpr float kC1 = 0.693359375f;  // ln 2 split: C1 + C2 (Cephes), C1 exact in 9 bits
  constexpr float kC2 = -2.12194440e-4f;
  const float clamped = max(min(x, 88.0f), -87.3365447505531f);
  // n = round(x log2 e) by floor(x log2 e + 1/2); truncation then a step down for negative t.
  const float t = clamped * kLog2e + 0.5f;
  float n = static_cast<float>(static_cast<std::int32_t>(t));
  n = n > t ? n - 1.0f : n;
  const float r = (clamped - n * kC1) - n * kC2;
  float p = 1.9875691500e-4f;
  p = p * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  p = (p * (r * r) + r) + 1.0f;
  // 2^n from the exponent bits (n in [-126, 127] after the clamp).
  return p * from_bits((static_cast<std::int32_t>(n) + 127) << 23);
}

inline float log(float x) {
  constexpr float kSqrtHalf = 0.707106781186547524f;
  const std::int32_t bits = to_bits(x);
  std::int32_t e = ((bits >> 23) & 0xff) - 126;
  float m = from_bits((bits & 0x807fffff) | 0x3f000000);  // mantissa in [0.5, 1)
  const bool low = m < kSqrtHalf;
  e = low ? e - 1 : e;
  m = low ? (m + m) - 1.0f : m - 1.0f;
  const float z = m * m;
  float p = 7.0376836292e-2f;
  p = p * m - 1.1514610310e-1f;
  p = p * m + 1.1676998740e-1f;
  p = p * m - 1.2420140846e-1f;
  p = p * m + 1.4249322787e-1f;
  p = p * m - 1.6668057665e-1f;
  p = p * m + 2.0000714765e-1f;
  p = p * m - 2.4999993993e-1f;
  p = p * m + 3.3333331174e-1f;
  const float fe = static_cast<float>(e);
  float y = m * z * p;
  y = y + fe * -2.12194440e-4f;
  y = y - 0.5f * z;
  return (m + y) + fe * 0.693359375f;
}

inline float acos(float x) {
  constexpr float kPi = 3.14159265358979f;
  constexpr float kHalfPi = 1.57079632679490f;
  const float a = min(1.0f, x < 0.0f ? -x : x);
  const bool wide = a > 0.5f;
  const float z = wide ? 0.5f * (1.0f - a) : a * a;
  const float s = wide ? __builtin_sqrtf(z) : a;  // asin's argument
  float p = 4.2163199048e-2f;
  p = p * z + 2.4181311049e-2f;
  p = p * z + 4.5470025998e-2f;
  p = p * z + 7.4953002686e-2f;
  p = p * z + 1.6666752422e-1f;
  const float asin_s = s + s * z * p;
  const float acos_a = wide ? 2.0f * asin_s : kHalfPi - asin_s;
  return x < 0.0f ? kPi - acos_a : acos_a;
}

// cos(2 pi u) and sin(2 pi u) for u in [0, 1]: the nearest quarter turn q / 4 split off exactly, then
// Cephes' sinf and cosf polynomials on the remaining |2 pi (u - q / 4)| <= pi / 4; within 1e-7
// (absolute).
struct QuarterTurn {
  std::int32_t q;      // the quarter turns, mod 4
  float sin_r, cos_r;  // of the rest
};
inline QuarterTurn quarter_turn(float u) {
  const float quarter = static_cast<float>(static_cast<std::int32_t>(4.0f * u + 0.5f));  // u >= 0: floor
  const float r = (u - 0.25f * quarter) * 6.28318530717958648f;
  const float r2 = r * r;
  const float sin_r = r + r * r2 * (-1.6666654611e-1f + r2 * (8.3321608736e-3f + r2 * -1.9515295891e-4f));
  const float cos_r = (1.0f - 0.5f * r2) + r2 * r2 * (4.166664568298827e-2f + r2 * (-1.388731625493765e-3f + r2 * 2.443315711809948e-5f));
  return QuarterTurn{static_cast<std::int32_t>(quarter) & 3, sin_r, cos_r};
}
inline float cos_2pi(float u) {
  const QuarterTurn t = quarter_turn(u);
  const float even = t.q == 0 ? t.cos_r : -t.cos_r;  // q = 0 or 2
  const float odd = t.q == 1 ? -t.sin_r : t.sin_r;   // q = 1 or 3
  return (t.q & 1) != 0 ? odd : even;
}
inline float sin_2pi(float u) {
  const QuarterTurn t = quarter_turn(u);
  const float even = t.q == 0 ? t.sin_r : -t.sin_r;  // q = 0 or 2
  const float odd = t.q == 1 ? t.cos_r : -t.cos_r;   // q = 1 or 3
  return (t.q & 1) != 0 ? odd : even;
}

}  // namespace hadal::render::fast
