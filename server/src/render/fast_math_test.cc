// render/fast_math.h against the C library over a million arguments each, and the same bits whether
// the compiler vectorizes a loop through them for AVX-512, AVX2 or the x86-64 baseline (the renderer's
// kernels are compiled all three ways: HADAL_VECTOR_KERNEL).
#include "hadal/render/fast_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace hadal::render {
namespace {

// Distance in units in the last place between two floats of the same sign.
long ulps(float a, float b) {
  std::int32_t ia, ib;
  std::memcpy(&ia, &a, 4);
  std::memcpy(&ib, &b, 4);
  return std::labs(static_cast<long>(ia) - static_cast<long>(ib));
}

std::vector<float> spread(float lo, float hi, std::size_t n) {
  std::vector<float> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = lo + (hi - lo) * static_cast<float>((i * 7919) % n) / static_cast<float>(n);
  return x;
}

TEST(FastMathTest, LogIsWithinTwoUlpOverThePositiveNormals) {
  long worst = 0;
  for (std::size_t i = 0; i < 1000000; ++i) {
    // Every binade from 2^-126 to 2^127, mantissas spread over each.
    const float x = std::ldexp(1.0f + static_cast<float>(i % 1000) / 1000.0f, static_cast<int>(i % 253) - 126);
    const float expected = static_cast<float>(std::log(static_cast<double>(x)));
    if (std::abs(expected) < 1e-30f) continue;  // log(1) = 0: no ulp scale
    worst = std::max(worst, ulps(fast::log(x), expected));
  }
  EXPECT_LE(worst, 2);
  EXPECT_EQ(fast::log(1.0f), 0.0f);
}

TEST(FastMathTest, AcosCos2PiAndSin2PiAreWithinTheirBounds) {
  double worst_acos = 0.0, worst_cos = 0.0;
  for (float x : spread(-1.0f, 1.0f, 1000000)) {
    worst_acos = std::max(worst_acos, std::abs(fast::acos(x) - std::acos(static_cast<double>(x))));
  }
  for (float u : spread(0.0f, 1.0f, 1000000)) {
    worst_cos = std::max(worst_cos, std::abs(fast::cos_2pi(u) - std::cos(2.0 * M_PI * static_cast<double>(u))));
    worst_cos = std::max(worst_cos, std::abs(fast::sin_2pi(u) - std::sin(2.0 * M_PI * static_cast<double>(u))));
  }
  EXPECT_LT(worst_acos, 3e-7);
  EXPECT_LT(worst_cos, 1e-7 + 4e-7);  // 1e-7 for the polynomials, 4e-7 for u's rounding times 2 pi
  EXPECT_EQ(fast::acos(1.0f), 0.0f);
  EXPECT_NEAR(fast::acos(-1.0f), M_PI, 1e-6);
  EXPECT_EQ(fast::acos(1.5f), 0.0f);  // clamped
  EXPECT_EQ(fast::cos_2pi(0.0f), 1.0f);
  EXPECT_NEAR(fast::cos_2pi(0.5f), -1.0f, 1e-7);
}

// The same loop compiled for the baseline, for AVX2 and for AVX-512.
#define HADAL_TEST_LOOPS(suffix, attribute)                                                 \
  attribute void exp_##suffix(const float* x, float* y, std::size_t n) {                   \
    for (std::size_t i = 0; i < n; ++i) y[i] = fast::exp(x[i]);                             \
  }                                                                                         \
  attribute void log_##suffix(const float* x, float* y, std::size_t n) {                   \
    for (std::size_t i = 0; i < n; ++i) y[i] = fast::log(x[i]);                             \
  }                                                                                         \
  attribute void trig_##suffix(const float* x, float* y, std::size_t n) {                  \
    for (std::size_t i = 0; i < n; ++i) y[i] = fast::acos(2.0f * x[i] - 1.0f) + fast::cos_2pi(x[i]) - fast::sin_2pi(x[i]); \
  }

HADAL_TEST_LOOPS(baseline, )
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
HADAL_TEST_LOOPS(avx2, __attribute__((target("avx2"))))
HADAL_TEST_LOOPS(avx512, __attribute__((target("avx512f"))))
#endif

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
using Loop = void (*)(const float*, float*, std::size_t);

// The loops of one ISA (exp, log, trig) give the baseline's bits over a million arguments each (not a
// multiple of 16: the loops' scalar tails too), and the trig loop the same as one value at a time.
void expect_baseline_bits(Loop exp_isa, Loop log_isa, Loop trig_isa) {
  const std::size_t n = 1000003;
  const std::vector<float> exponent = spread(-100.0f, 100.0f, n), positive = spread(1e-30f, 1e6f, n),
                           unit = spread(0.0f, 1.0f, n);
  std::vector<float> a(n), b(n);
  exp_baseline(exponent.data(), a.data(), n);
  exp_isa(exponent.data(), b.data(), n);
  EXPECT_EQ(std::memcmp(a.data(), b.data(), n * sizeof(float)), 0);
  log_baseline(positive.data(), a.data(), n);
  log_isa(positive.data(), b.data(), n);
  EXPECT_EQ(std::memcmp(a.data(), b.data(), n * sizeof(float)), 0);
  trig_baseline(unit.data(), a.data(), n);
  trig_isa(unit.data(), b.data(), n);
  EXPECT_EQ(std::memcmp(a.data(), b.data(), n * sizeof(float)), 0);
  for (std::size_t i = 0; i < n; i += 997) {
    EXPECT_EQ(a[i], fast::acos(2.0f * unit[i] - 1.0f) + fast::cos_2pi(unit[i]) - fast::sin_2pi(unit[i]));
  }
}
#endif

TEST(FastMathTest, SameBitsVectorizedForAvx2AndForTheBaseline) {
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this CPU has no AVX2: nothing to compare";
  expect_baseline_bits(exp_avx2, log_avx2, trig_avx2);
#else
  GTEST_SKIP() << "function multiversioning is GCC on x86-64 only";
#endif
}

TEST(FastMathTest, SameBitsVectorizedForAvx512AndForTheBaseline) {
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
  if (!__builtin_cpu_supports("avx512f")) GTEST_SKIP() << "this CPU has no AVX-512: nothing to compare";
  expect_baseline_bits(exp_avx512, log_avx512, trig_avx512);
#else
  GTEST_SKIP() << "function multiversioning is GCC on x86-64 only";
#endif
}

}  // namespace
}  // namespace hadal::render
