#include "hadal/sensors/noise.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "hadal/sensors/allan.h"

namespace hadal::sensors {
namespace {

std::uint64_t bits(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// n-sigma bound on the relative error of an Allan deviation estimated from `clusters` independent
// (non-overlapping) clusters: the Allan variance is then a mean of clusters - 1 squared differences,
// chi-square with clusters - 1 degrees of freedom, so the deviation has relative std 1 / sqrt(2 (M - 1)).
// The overlapping estimator has more degrees of freedom, so this is conservative.
double allan_tolerance(double n_sigma, double clusters) { return n_sigma / std::sqrt(2.0 * (clusters - 1.0)); }

// Record of one scalar channel with zero ideal input.
std::vector<double> record(const NoiseChannelParams& params, std::uint64_t key, double dt, std::size_t n) {
  NoiseChannelState state = make_noise_state(params, key);
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = apply_noise(params, state, 0.0, dt);
  return out;
}

NoiseTriadParams full_triad() {
  NoiseTriadParams p;
  for (auto& axis : p.axes) {
    axis.white_noise_density = 1e-3;
    axis.bias_random_walk_density = 1e-5;
    axis.gauss_markov = {{2e-4, 10.0}, {1e-4, 100.0}};
    axis.turn_on_bias = 1e-3;
    axis.turn_on_bias_sigma = 5e-4;
  }
  p.misalignment_sigma = 1e-3;
  p.scale_factor_sigma = 1e-4;
  p.lsb = 1e-5;
  p.min = -5.0;
  p.max = 5.0;
  return p;
}

// ----- random streams --------------------------------------------------------------------------------

// Published reference values: splitmix64 with state 0 gives 0xe220a8397b1dcdaf (Vigna's splitmix64.c),
// FNV-1a 64 of "" is the offset basis and of "a" is 0xaf63dc4c8601ec8c (Fowler/Noll/Vo test suite).
TEST(NoiseRandomTest, SplitmixAndFnvReferenceValues) {
  EXPECT_EQ(splitmix64(0), 0xe220a8397b1dcdafULL);
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cULL);
}

// Golden values from an independent Python implementation of the documented algorithm (key derivation,
// xoshiro256**, polar method with portable_log; CPython evaluates IEEE binary64 without FMA), so these
// also pin the cross-platform stream: any change of algorithm or constant breaks them.
TEST(NoiseRandomTest, GoldenValuesFromReferenceImplementation) {
  const std::uint64_t key = channel_key(42, "auv", "imu", "gyro");
  EXPECT_EQ(key, 0x5c56f16eb77045a2ULL);
  RandomStream a(key);
  EXPECT_EQ(a.next_u64(), 0x3f6d40c41d6cb3daULL);
  EXPECT_EQ(a.next_u64(), 0x5575959220e09012ULL);
  EXPECT_EQ(a.next_u64(), 0x49bcc5b485f0643fULL);
  RandomStream b(key);
  const double normals[] = {-0x1.2f884158bb9fcp+0, -0x1.8feebf3ccc871p-1, -0x1.9bacbba6dd797p+0,
                            0x1.688dc700ef844p-1, 0x1.2f291c980ff9bp-1};
  for (const double expected : normals) EXPECT_EQ(bits(b.normal()), bits(expected));
  RandomStream white(derive_key(key, "white_noise"));
  EXPECT_EQ(white.normal(), -0.905574751803591);
  EXPECT_EQ(white.normal(), 0.18466587762190187);
  EXPECT_EQ(white.normal(), 0.9348507361197804);
}

// portable_exp against libm's exp (glibc's is within 1 ulp): within 3 ulp over the range the ziggurat
// uses and beyond, and exact at 0.
TEST(NoiseRandomTest, PortableExpWithinUlpsOfLibm) {
  EXPECT_EQ(portable_exp(0.0), 1.0);
  RandomStream stream(11);
  for (int i = 0; i < 200000; ++i) {
    const double x = -700.0 + 1400.0 * stream.uniform();
    const double expected = std::exp(x);
    EXPECT_LE(std::abs(portable_exp(x) - expected), 3.0 * (std::nextafter(expected, INFINITY) - expected)) << x;
  }
  for (double x : {-20.0, -0.5, -1e-10, 1e-10, 0.3465, 1.0, 30.0}) {
    EXPECT_NEAR(portable_exp(x), std::exp(x), 4e-16 * std::exp(x)) << x;
  }
}

// The ziggurat's N(0, 1): 2e6 draws in 40 bins of 0.2 on [-4, 4] plus two tails against the normal CDF
// (Pearson's chi-square below 99.17, the 1e-6 upper quantile of chi-square with 41 degrees of freedom,
// so a correct generator fails once in a million seeds), the moments as NormalAndUniformMoments tests
// them, and the tail beyond r = 3.654 (where the ziggurat switches to Marsaglia's tail method) with
// the right frequency within 5 standard errors.
TEST(NoiseRandomTest, ZigguratNormalFollowsTheNormalDistribution) {
  RandomStream stream(channel_key(5, "v", "camera", "image"));
  const int n = 2000000;
  std::vector<double> counts(42, 0.0);
  double sum = 0.0, sum2 = 0.0, sum4 = 0.0;
  int beyond_r = 0;
  for (int i = 0; i < n; ++i) {
    const double x = stream.ziggurat_normal();
    ASSERT_TRUE(std::isfinite(x));
    sum += x;
    sum2 += x * x;
    sum4 += x * x * x * x;
    beyond_r += std::abs(x) > 3.6541528853610088;
    const int bin = x < -4.0 ? 0 : x >= 4.0 ? 41 : 1 + static_cast<int>(std::floor((x + 4.0) / 0.2));
    counts[static_cast<std::size_t>(std::clamp(bin, 0, 41))] += 1.0;
  }
  const auto cdf = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  double chi2 = 0.0;
  for (int b = 0; b < 42; ++b) {
    const double lo = b == 0 ? -INFINITY : -4.0 + 0.2 * (b - 1);
    const double hi = b == 41 ? INFINITY : -4.0 + 0.2 * b;
    const double expected = n * ((std::isfinite(hi) ? cdf(hi) : 1.0) - (std::isfinite(lo) ? cdf(lo) : 0.0));
    chi2 += (counts[static_cast<std::size_t>(b)] - expected) * (counts[static_cast<std::size_t>(b)] - expected) / expected;
  }
  EXPECT_LT(chi2, 99.17);
  const double mean = sum / n, variance = sum2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.0, 4.0 / std::sqrt(n));
  EXPECT_NEAR(variance, 1.0, 4.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(sum4 / n, 3.0, 4.0 * std::sqrt(24.0 / n));
  const double p = std::erfc(3.6541528853610088 / std::sqrt(2.0));
  EXPECT_NEAR(static_cast<double>(beyond_r) / n, p, 5.0 * std::sqrt(p * (1.0 - p) / n));
}

// Same key, same sequence; the ziggurat leaves normal()'s spare alone (a stream that interleaves the two
// gets the polar method's pairs unchanged).
TEST(NoiseRandomTest, ZigguratNormalIsReproducibleAndSeparateFromThePolarSpare) {
  RandomStream a(77), b(77);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.ziggurat_normal(), b.ziggurat_normal());
  RandomStream polar(78), mixed(78);
  const double first = polar.normal(), second = polar.normal();
  EXPECT_EQ(mixed.normal(), first);
  (void)mixed.ziggurat_normal();
  EXPECT_EQ(mixed.normal(), second);  // the spare, kept across the ziggurat draw
}

TEST(NoiseRandomTest, KeysSeparateSeedsNamesAndBoundaries) {
  std::set<std::uint64_t> keys = {
      channel_key(1, "auv", "imu", "gyro"),  channel_key(2, "auv", "imu", "gyro"),
      channel_key(1, "auv2", "imu", "gyro"), channel_key(1, "auv", "imu2", "gyro"),
      channel_key(1, "auv", "imu", "accel"), channel_key(1, "ab", "c", "d"),
      channel_key(1, "a", "bc", "d"),        channel_key(1, "", "", ""),
  };
  EXPECT_EQ(keys.size(), 8u);
  EXPECT_EQ(channel_key(7, "auv", "imu", "gyro"), channel_key(7, "auv", "imu", "gyro"));
}

// 1e6 draws: mean, variance, two-sided 2-sigma tail and kurtosis of N(0, 1), each within 4 standard errors
// (1/sqrt(n), sqrt(2/n), sqrt(p(1-p)/n) with p = 0.0455, sqrt(24/n)); the uniform's mean within 4 sqrt(1/12n).
TEST(NoiseRandomTest, NormalAndUniformMoments) {
  RandomStream stream(channel_key(3, "v", "s", "c"));
  const int n = 1000000;
  double sum = 0.0;
  double sum2 = 0.0;
  double sum4 = 0.0;
  int tail = 0;
  for (int i = 0; i < n; ++i) {
    const double x = stream.normal();
    sum += x;
    sum2 += x * x;
    sum4 += x * x * x * x;
    if (std::abs(x) > 2.0) ++tail;
  }
  const double mean = sum / n;
  const double variance = sum2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.0, 4.0 / std::sqrt(n));
  EXPECT_NEAR(variance, 1.0, 4.0 * std::sqrt(2.0 / n));
  const double p = 0.0455003;
  EXPECT_NEAR(static_cast<double>(tail) / n, p, 4.0 * std::sqrt(p * (1.0 - p) / n));
  EXPECT_NEAR(sum4 / n, 3.0, 4.0 * std::sqrt(24.0 / n));

  double usum = 0.0;
  double umin = 1.0;
  double umax = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = stream.uniform();
    usum += u;
    umin = std::min(umin, u);
    umax = std::max(umax, u);
  }
  EXPECT_NEAR(usum / n, 0.5, 4.0 * std::sqrt(1.0 / (12.0 * n)));
  EXPECT_GE(umin, 0.0);
  EXPECT_LT(umax, 1.0);
}

// Within 4 ulp of std::log (the series is exact to 1e-18; the rest is rounding of ~15 operations).
TEST(NoiseRandomTest, PortableLogMatchesStdLog) {
  RandomStream stream(99);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double x = i % 2 == 0 ? stream.uniform() + 0x1.0p-60 : std::ldexp(stream.uniform() + 0.5, i % 2000 - 1000);
    const double reference = std::log(x);
    if (reference == 0.0) continue;
    worst = std::max(worst, std::abs(portable_log(x) - reference) / (std::abs(reference) * 0x1.0p-52));
  }
  EXPECT_LE(worst, 4.0);
  EXPECT_EQ(portable_log(1.0), 0.0);
  EXPECT_EQ(portable_log(0.5), -std::log(2.0));
  EXPECT_NEAR(portable_log(0x1.0p-104), -104.0 * std::log(2.0), 1e-13);
}

// ----- kernels ---------------------------------------------------------------------------------------

TEST(NoiseProcessTest, WhiteNoiseSigmaIsDensityTimesSqrtRate) {
  // N = 2e-3 at f_s = 400 Hz: sigma = 2e-3 * 20 = 0.04.
  EXPECT_DOUBLE_EQ(white_noise_sigma(2e-3, 1.0 / 400.0), 0.04);
  EXPECT_DOUBLE_EQ(white_noise(2e-3, 0.25, -1.5), -6e-3);
}

TEST(NoiseProcessTest, BiasRandomWalkStep) {
  EXPECT_EQ(bias_random_walk_step(0.5, 1.0, 4.0, 0.25), 1.25);  // 1 + 0.5 * sqrt(4) * 0.25, exact
  EXPECT_EQ(bias_random_walk_step(0.0, 1.0, 4.0, 3.0), 1.0);
}

TEST(NoiseProcessTest, GaussMarkovStepAndLimits) {
  const GaussMarkovParams p{2.0, 10.0};
  const double phi = std::exp(-0.1);
  EXPECT_DOUBLE_EQ(gauss_markov_phi(p, 1.0), phi);
  EXPECT_NEAR(gauss_markov_step(p, 0.5, 1.0, 0.3), phi * 0.5 + std::sqrt(1.0 - phi * phi) * 2.0 * 0.3, 1e-15);
  // tau_c = inf: a constant; tau_c -> 0: white with std sigma.
  EXPECT_EQ(gauss_markov_step({2.0, std::numeric_limits<double>::infinity()}, 0.7, 1.0, 5.0), 0.7);
  EXPECT_EQ(gauss_markov_step({2.0, 1e-300}, 0.7, 1.0, 0.25), 0.5);
}

// Closed form: peak 0.61736 sigma at tau = 1.8926 tau_c; the small-x series meets the closed form at the
// switch (x = 0.1) to 1e-12; limits 2x/3 (random walk) and 2/x (white).
TEST(NoiseProcessTest, GaussMarkovAllanClosedForm) {
  const GaussMarkovParams p{3.0, 20.0};
  const double peak_tau = kGaussMarkovAllanPeakTauRatio * 20.0;
  EXPECT_NEAR(std::sqrt(gauss_markov_allan_variance(p, peak_tau)), kGaussMarkovAllanPeakRatio * 3.0, 1e-12);
  EXPECT_LT(gauss_markov_allan_variance(p, 1.01 * peak_tau), gauss_markov_allan_variance(p, peak_tau));
  EXPECT_LT(gauss_markov_allan_variance(p, 0.99 * peak_tau), gauss_markov_allan_variance(p, peak_tau));
  const double below = gauss_markov_allan_variance(p, std::nextafter(2.0, 0.0));
  const double above = gauss_markov_allan_variance(p, 2.0);
  EXPECT_NEAR(below / above, 1.0, 1e-12);
  EXPECT_NEAR(gauss_markov_allan_variance(p, 1e-6 * 20.0) / (9.0 * 2e-6 / 3.0), 1.0, 1e-5);
  EXPECT_NEAR(gauss_markov_allan_variance(p, 1e6 * 20.0) / (9.0 * 2e-6), 1.0, 1e-5);
}

// Stationary std sigma from the first sample on, lag-1 autocorrelation phi. 2e5 samples with phi = e^-0.1:
// effective independent samples n (1 - phi) / (1 + phi) = 1.0e4, so the std has relative standard error
// 1 / sqrt(2 n_eff) = 0.7 % (4 sigma: 2.8 %), the autocorrelation sqrt((1 - phi^2) / n) = 0.001 (4 sigma 0.004).
TEST(NoiseProcessTest, GaussMarkovStationaryStdAndCorrelation) {
  NoiseChannelParams params;
  params.noise.gauss_markov = {{0.5, 10.0}};
  const double dt = 1.0;
  const std::size_t n = 200000;
  const std::vector<double> x = record(params, channel_key(5, "v", "s", "gm"), dt, n);
  double sum2 = 0.0;
  double lag = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sum2 += x[i] * x[i];
    if (i > 0) lag += x[i] * x[i - 1];
  }
  EXPECT_NEAR(std::sqrt(sum2 / n) / 0.5, 1.0, 0.028);
  EXPECT_NEAR(lag / sum2, std::exp(-0.1), 0.004);
  // Stationary start: the first samples of many channels have std sigma (2e4 channels: 4 sigma = 2 %).
  double first2 = 0.0;
  for (int c = 0; c < 20000; ++c) {
    NoiseChannelState state = make_noise_state(params, channel_key(5, "v", "s", "gm" + std::to_string(c)));
    const double v = apply_noise(params, state, 0.0, dt);
    first2 += v * v;
  }
  EXPECT_NEAR(std::sqrt(first2 / 20000.0) / 0.5, 1.0, 4.0 / std::sqrt(2.0 * 20000.0));
}

TEST(NoiseProcessTest, QuantizationRoundsToNearestLsb) {
  EXPECT_EQ(quantize(0.3, 0.25), 0.25);
  EXPECT_EQ(quantize(0.375, 0.25), 0.5);    // tie: away from zero
  EXPECT_EQ(quantize(-0.375, 0.25), -0.5);  // tie: away from zero
  EXPECT_EQ(quantize(-0.124, 0.25), 0.0);
  EXPECT_EQ(quantize(1000.49 * 0x1.0p-10, 0x1.0p-10), 1000.0 * 0x1.0p-10);
  EXPECT_EQ(quantize(0.26, 0.1), 3.0 * 0.1);
  EXPECT_EQ(quantize(0.123456789, 0.0), 0.123456789);
}

TEST(NoiseProcessTest, ClippingSaturates) {
  EXPECT_EQ(clip(5.0, -1.0, 2.0), 2.0);
  EXPECT_EQ(clip(-5.0, -1.0, 2.0), -1.0);
  EXPECT_EQ(clip(0.5, -1.0, 2.0), 0.5);
  EXPECT_EQ(clip(std::numeric_limits<double>::infinity(), -1.0, 2.0), 2.0);
  EXPECT_TRUE(std::isnan(clip(std::nan(""), -1.0, 2.0)));  // faults stay visible
}

// Dyadic entries: every product and sum is exact, so the result is compared with ==.
// (I + S) x = (3, 3, -9); M (3, 3, -9) = (3 + 0.375 + 2.25, 1.5 + 3, 0.1875 - 9).
TEST(NoiseProcessTest, ScaleAndMisalignmentExact) {
  Eigen::Matrix3d m;
  m << 1.0, 0.125, -0.25, 0.5, 1.0, 0.0, 0.0, 0.0625, 1.0;
  const Eigen::Vector3d s(0.5, -0.25, 0.125);
  const Eigen::Vector3d x(2.0, 4.0, -8.0);
  const Eigen::Vector3d expected(5.625, 4.5, -8.8125);
  EXPECT_EQ(scale_and_misalign(m, s, x), expected);

  NoiseTriadParams params;
  params.misalignment = m;
  params.scale_factor = s;
  NoiseTriadState state = make_noise_state(params, 1);
  EXPECT_EQ(measure(params, state, x, 0.01), expected);

  NoiseChannelParams scalar;
  scalar.scale_factor = 0.5;
  NoiseChannelState scalar_state = make_noise_state(scalar, 1);
  EXPECT_EQ(measure(scalar, scalar_state, 3.0, 0.01), 4.5);
}

TEST(NoiseProcessTest, ZeroNoiseIsIdentity) {
  NoiseTriadParams params;
  NoiseTriadState state = make_noise_state(params, 17);
  const Eigen::Vector3d x(0.1, -2.0 / 3.0, 1e-9);
  EXPECT_EQ(measure(params, state, x, 0.005), x);
  NoiseChannelParams scalar;
  NoiseChannelState scalar_state = make_noise_state(scalar, 17);
  EXPECT_EQ(measure(scalar, scalar_state, 1.0 / 3.0, 0.005), 1.0 / 3.0);
}

// Sensor terms (temperature, vibration) enter before quantization, clipping comes last.
TEST(NoiseProcessTest, OutputStageOrder) {
  NoiseChannelParams params;
  params.lsb = 0.25;
  params.max = 1.2;
  NoiseChannelState state = make_noise_state(params, 1);
  EXPECT_EQ(measure(params, state, 0.0, 0.01, 0.3), 0.25);
  EXPECT_EQ(measure(params, state, 1.0, 0.01, 0.26), 1.2);  // 1.26 -> 1.25 -> clipped to 1.2
  NoiseTriadParams triad;
  triad.lsb = 0.5;
  triad.min = -1.0;
  triad.max = 1.0;
  NoiseTriadState triad_state = make_noise_state(triad, 1);
  EXPECT_EQ(measure(triad, triad_state, Eigen::Vector3d(0.2, -3.0, 0.8), 0.01, Eigen::Vector3d(0.1, 0.0, 0.0)),
            Eigen::Vector3d(0.5, -1.0, 1.0));
}

// Turn-on draws: b0 = fixed + sigma w per axis, scale and off-diagonal misalignment drawn once; the
// diagonal of M stays 1. Over 2e4 channels the drawn std is sigma within 4 standard errors (2 %).
TEST(NoiseProcessTest, TurnOnDraws) {
  NoiseTriadParams params;
  for (auto& axis : params.axes) {
    axis.turn_on_bias = 0.1;
    axis.turn_on_bias_sigma = 0.01;
  }
  params.misalignment_sigma = 1e-3;
  params.scale_factor_sigma = 2e-4;
  const int n = 20000;
  double bias2 = 0.0;
  double off2 = 0.0;
  double scale2 = 0.0;
  for (int c = 0; c < n; ++c) {
    const NoiseTriadState s = make_noise_state(params, channel_key(9, "v", "imu", "gyro" + std::to_string(c)));
    bias2 += (s.axes[1].turn_on_bias - 0.1) * (s.axes[1].turn_on_bias - 0.1);
    // transform = M (I + S): column 0 is (1 + s_x) (1, m10, m20).
    const double sx = s.transform(0, 0) - 1.0;
    scale2 += sx * sx;
    off2 += (s.transform(1, 0) / s.transform(0, 0)) * (s.transform(1, 0) / s.transform(0, 0));
  }
  const double tolerance = 4.0 / std::sqrt(2.0 * n);
  EXPECT_NEAR(std::sqrt(bias2 / n) / 0.01, 1.0, tolerance);
  EXPECT_NEAR(std::sqrt(scale2 / n) / 2e-4, 1.0, tolerance);
  EXPECT_NEAR(std::sqrt(off2 / n) / 1e-3, 1.0, tolerance);
}

TEST(NoiseProcessTest, ValidationNamesTheField) {
  NoiseChannelParams p;
  p.noise.gauss_markov = {{1.0, 0.0}};
  try {
    make_noise_state(p, 1);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("noise.gauss_markov[0].correlation_time_s"), std::string::npos) << e.what();
  }
  p.noise.gauss_markov.assign(kMaxGaussMarkovTerms + 1, {1.0, 1.0});
  EXPECT_THROW(make_noise_state(p, 1), std::invalid_argument);
  NoiseTriadParams t;
  t.axes[2].white_noise_density = -1.0;
  try {
    make_noise_state(t, 1);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("axes[2].white_noise_density"), std::string::npos) << e.what();
  }
  t = NoiseTriadParams();
  t.min = 1.0;
  t.max = 0.0;
  EXPECT_THROW(make_noise_state(t, 1), std::invalid_argument);
  t = NoiseTriadParams();
  t.lsb = -1.0;
  EXPECT_THROW(make_noise_state(t, 1), std::invalid_argument);
}

// ----- determinism and state -------------------------------------------------------------------------

std::vector<std::uint64_t> triad_stream(const NoiseTriadParams& params, std::uint64_t key, int n) {
  NoiseTriadState state = make_noise_state(params, key);
  std::vector<std::uint64_t> out;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d m = measure(params, state, Eigen::Vector3d(0.1, 0.2, -0.98), 0.005);
    for (int k = 0; k < 3; ++k) out.push_back(bits(m[k]));
  }
  return out;
}

TEST(NoiseStateTest, SameSeedBitIdenticalOtherSeedOrNameDiffers) {
  const NoiseTriadParams params = full_triad();
  const auto reference = triad_stream(params, channel_key(11, "auv", "imu", "gyro"), 2000);
  EXPECT_EQ(triad_stream(params, channel_key(11, "auv", "imu", "gyro"), 2000), reference);
  for (const std::uint64_t other : {channel_key(12, "auv", "imu", "gyro"), channel_key(11, "auv2", "imu", "gyro"),
                                    channel_key(11, "auv", "imu2", "gyro"), channel_key(11, "auv", "imu", "accel")}) {
    const auto stream = triad_stream(params, other, 2000);
    int equal = 0;
    for (std::size_t i = 0; i < stream.size(); ++i) equal += stream[i] == reference[i];
    EXPECT_LT(equal, 60) << "streams of different keys should (almost) never agree";  // quantized: rare ties
  }
}

TEST(NoiseStateTest, CopyRestoreContinuesBitIdentically) {
  const NoiseTriadParams params = full_triad();
  NoiseTriadState state = make_noise_state(params, channel_key(1, "auv", "imu", "gyro"));
  const Eigen::Vector3d ideal(0.01, -0.02, 0.03);
  for (int i = 0; i < 777; ++i) measure(params, state, ideal, 0.005);  // odd count: a spare normal is cached
  const NoiseTriadState snapshot = state;
  EXPECT_EQ(snapshot, state);
  std::vector<std::uint64_t> first;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d m = measure(params, state, ideal, 0.005);
    for (int k = 0; k < 3; ++k) first.push_back(bits(m[k]));
  }
  const NoiseTriadState end = state;
  EXPECT_NE(end, snapshot);
  state = snapshot;
  std::vector<std::uint64_t> second;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d m = measure(params, state, ideal, 0.005);
    for (int k = 0; k < 3; ++k) second.push_back(bits(m[k]));
  }
  EXPECT_EQ(first, second);
  EXPECT_EQ(state, end);

  NoiseChannelParams scalar;
  scalar.noise = params.axes[0];
  NoiseChannelState s = make_noise_state(scalar, 3);
  measure(scalar, s, 1.0, 0.01);
  const NoiseChannelState copy = s;
  const double a = measure(scalar, s, 1.0, 0.01);
  s = copy;
  EXPECT_EQ(bits(measure(scalar, s, 1.0, 0.01)), bits(a));
}

// Each process draws from its own sub-stream: adding processes leaves the others' realisation unchanged
// (the paper's white-noise-only vs full comparison uses the same white noise).
TEST(NoiseStateTest, ProcessesDrawFromIndependentSubstreams) {
  NoiseChannelParams white_only;
  white_only.noise.white_noise_density = 1e-3;
  NoiseChannelParams full = white_only;
  full.noise.bias_random_walk_density = 1e-5;
  full.noise.gauss_markov = {{1e-4, 50.0}};
  full.noise.turn_on_bias_sigma = 1e-3;
  NoiseChannelParams gm_only;
  gm_only.noise.gauss_markov = full.noise.gauss_markov;
  const std::uint64_t key = channel_key(4, "auv", "imu", "gyro_x");
  NoiseChannelState a = make_noise_state(white_only, key);
  NoiseChannelState b = make_noise_state(full, key);
  NoiseChannelState c = make_noise_state(gm_only, key);
  for (int i = 0; i < 1001; ++i) {
    apply_noise(white_only, a, 0.0, 0.01);
    apply_noise(full, b, 0.0, 0.01);
    apply_noise(gm_only, c, 0.0, 0.01);
  }
  EXPECT_EQ(a.streams.white_noise, b.streams.white_noise);
  EXPECT_EQ(b.streams.gauss_markov, c.streams.gauss_markov);
  EXPECT_EQ(bits(b.axis.gauss_markov[0]), bits(c.axis.gauss_markov[0]));
  EXPECT_NE(a.streams.white_noise, a.streams.gauss_markov);
}

// ----- Allan deviation of the simulated processes (IEEE 952) -----------------------------------------

// White rate noise N at 100 Hz for 1e4 s: sigma(1 s) = N. 1e4 independent 1-s clusters: 4 sigma = 2.8 %;
// sigma(10 s) = N / sqrt(10) with 1e3 clusters: 4 sigma = 8.9 %.
TEST(NoiseAllanTest, WhiteNoiseDensityAtOneSecond) {
  NoiseChannelParams params;
  params.noise.white_noise_density = arw_to_noise_density(0.15);  // STIM300 ARW, 4.36e-5 rad/s/sqrt(Hz)
  const double dt = 0.01;
  const std::vector<double> x = record(params, channel_key(1, "auv", "imu", "gyro_x"), dt, 1000000);
  const auto curve = overlapping_allan_deviation(x, dt, {100, 1000});
  const double n = params.noise.white_noise_density;
  EXPECT_NEAR(curve[0].deviation / n, 1.0, allan_tolerance(4.0, 1e4));
  EXPECT_NEAR(curve[1].deviation / (n / std::sqrt(10.0)), 1.0, allan_tolerance(4.0, 1e3));
  std::printf("[ figures  ] white: sigma(1 s) / N = %.4f, sigma(10 s) sqrt(10) / N = %.4f\n", curve[0].deviation / n,
              curve[1].deviation * std::sqrt(10.0) / n);
}

// Rate random walk K at 1 Hz for 1e6 s: sigma(tau) = K sqrt(tau / 3) (times sqrt(1 + 1 / (2 m^2)) for
// m-sample clusters of a discrete walk), slope +1/2. tau = 10 s: 1e5 clusters, 4 sigma = 0.9 %;
// tau = 1000 s: 1e3 clusters, 4 sigma = 8.9 %; the slope over two decades has standard error
// sqrt(0.0022^2 + 0.022^2) / ln(100) = 0.005, 4 sigma = 0.02.
TEST(NoiseAllanTest, RateRandomWalkSlopeAndLevel) {
  NoiseChannelParams params;
  params.noise.bias_random_walk_density = rrw_to_random_walk_density(10.0);
  const double k = params.noise.bias_random_walk_density;
  const std::vector<double> x = record(params, channel_key(1, "auv", "imu", "gyro_y"), 1.0, 1000000);
  const auto curve = overlapping_allan_deviation(x, 1.0, {10, 1000});
  auto expected = [k](double m) { return k * std::sqrt(m / 3.0) * std::sqrt(1.0 + 1.0 / (2.0 * m * m)); };
  EXPECT_NEAR(curve[0].deviation / expected(10.0), 1.0, allan_tolerance(4.0, 1e5));
  EXPECT_NEAR(curve[1].deviation / expected(1000.0), 1.0, allan_tolerance(4.0, 1e3));
  const double slope = allan_slope(curve, 10.0, 1000.0);
  EXPECT_NEAR(slope, 0.5, 0.02);
  // The fit over the whole curve (tau 1 s .. 1e5 s) reads K back; dominated by the short taus, it is
  // good to about the tau = 10 s point's 4 sigma (1 %); asserted to 3 %. The discrete walk's excess
  // K^2 dt / (6 m) = (K dt / sqrt(6))^2 / tau is white-noise shaped, and the fit finds it as N (10 %).
  const AllanFit fit = fit_allan_terms(overlapping_allan_deviation(x, 1.0));
  EXPECT_NEAR(fit.rate_random_walk_density / k, 1.0, 0.03);
  EXPECT_NEAR(fit.white_noise_density / (k * 1.0 / std::sqrt(6.0)), 1.0, 0.1);
  std::printf("[ figures  ] rrw: sigma(10 s) / K sqrt(tau/3) = %.4f, sigma(1000 s) / .. = %.4f, slope %.4f,"
              " fit K %.4f, N %.3g, B %.3g\n",
              curve[0].deviation / expected(10.0), curve[1].deviation / expected(1000.0), slope,
              fit.rate_random_walk_density / k, fit.white_noise_density, fit.bias_instability);
}

// One Gauss-Markov process from bias_instability_to_gauss_markov (B = 0.5 deg/h, tau_c = 100 s) at 1 Hz
// for 1e6 s: its Allan curve peaks at 0.664 B near tau = 189 s. Issue 5 accepts 30 %; with ~5000
// clusters at the peak the estimate is good to 4 sigma = 5.7 %, which is what is asserted (the 30 % bound
// is implied). Sampling at dt = tau_c / 100 changes the closed form by < 0.5 %.
TEST(NoiseAllanTest, GaussMarkovBiasInstabilityFloor) {
  const double b = deg_per_h_to_rad_per_s(0.5);
  NoiseChannelParams params;
  params.noise.gauss_markov = {bias_instability_to_gauss_markov(b, 100.0)};
  const std::vector<double> x = record(params, channel_key(1, "auv", "imu", "gyro_z"), 1.0, 1000000);
  const auto curve = overlapping_allan_deviation(x, 1.0, log_spaced_cluster_sizes(x.size(), 20, 2000));
  AllanPoint peak;
  for (const AllanPoint& p : curve) {
    if (p.deviation > peak.deviation) peak = p;
  }
  const double floor = kBiasInstabilityAllanFactor * b;
  EXPECT_NEAR(peak.deviation / floor, 1.0, allan_tolerance(4.0, 1e6 / 189.0));
  EXPECT_NEAR(peak.deviation / floor, 1.0, 0.30);
  EXPECT_NEAR(peak.tau_s / (kGaussMarkovAllanPeakTauRatio * 100.0), 1.0, 0.3);  // flat top: position is loose
  std::printf("[ figures  ] gauss-markov: peak / 0.664 B = %.4f at tau = %.0f s (expected %.0f s)\n",
              peak.deviation / floor, peak.tau_s, kGaussMarkovAllanPeakTauRatio * 100.0);
}

// The bank's closed-form Allan deviation is flat at 0.664 B within [-2 %, +1 %] over the requested range.
TEST(NoiseAllanTest, GaussMarkovBankClosedFormIsFlat) {
  const double ranges[][2] = {{1.0, 1e4}, {1.0, 1e5}, {1.0, 3.3}, {10.0, 1e4}, {0.3, 7.0}, {1.0, 1e7}, {5.0, 5.0}};
  for (const auto& range : ranges) {
    const auto bank = bias_instability_to_gauss_markov_bank(2.0, range[0], range[1]);
    for (int i = 0; i <= 400; ++i) {
      const double tau = range[0] * std::pow(range[1] / range[0], i / 400.0);
      double variance = 0.0;
      for (const GaussMarkovParams& term : bank) variance += gauss_markov_allan_variance(term, tau);
      const double ratio = std::sqrt(variance) / (kBiasInstabilityAllanFactor * 2.0);
      EXPECT_GT(ratio, 0.98) << "range " << range[0] << ".." << range[1] << " tau " << tau;
      EXPECT_LT(ratio, 1.011) << "range " << range[0] << ".." << range[1] << " tau " << tau;
    }
  }
}

// The simulated bank (B = 0.5 deg/h over [10 s, 1000 s], five terms) at 2 Hz for 5e5 s: every point of
// the curve in [10 s, 1000 s] within 15 % of 0.664 B (2 % model ripple + 4 sigma with 500 clusters at
// 1000 s, 12.7 %), and the minimum there — the floor a datasheet reader takes — within the 30 %.
TEST(NoiseAllanTest, GaussMarkovBankFloorIsFlat) {
  const double b = deg_per_h_to_rad_per_s(0.5);
  NoiseChannelParams params;
  params.noise.gauss_markov = bias_instability_to_gauss_markov_bank(b, 10.0, 1000.0);
  const double dt = 0.5;
  const std::vector<double> x = record(params, channel_key(2, "auv", "imu", "gyro_z"), dt, 1000000);
  const auto curve = overlapping_allan_deviation(x, dt, log_spaced_cluster_sizes(x.size(), 10, 2000));
  const double floor = kBiasInstabilityAllanFactor * b;
  double lowest = 1e300;
  double highest = 0.0;
  for (const AllanPoint& p : curve) {
    if (p.tau_s < 10.0 || p.tau_s > 1000.0) continue;
    EXPECT_NEAR(p.deviation / floor, 1.0, 0.15) << "tau " << p.tau_s;
    lowest = std::min(lowest, p.deviation / floor);
    highest = std::max(highest, p.deviation / floor);
  }
  EXPECT_NEAR(allan_minimum(curve, 10.0, 1000.0).deviation / floor, 1.0, 0.30);
  std::printf("[ figures  ] bank [10 s, 1000 s]: sigma / 0.664 B in [%.4f, %.4f]\n", lowest, highest);
}

// A whole channel in the terms (white + bias-instability bank + rate random walk), scaled so that
// its floor falls within a 1e5 s record at 10 Hz: N = 1e-3 u/sqrt(Hz), 0.664 B = 1e-4 u, K chosen so that
// K sqrt(tau / 3) reaches the floor at 1e5 s. Expected: sigma(1 s) = sqrt(N^2 + (0.664 B)^2) = 1.005 N
// (4 sigma with 1e5 clusters: 0.9 %, plus the 0.5 % floor share), the minimum over [100 s, 1000 s]
// (>= 100 clusters) within 30 % of 0.664 B, and the slope well above 0 past the bank (RRW rises).
TEST(NoiseAllanTest, FullChannelReadout) {
  const double n = 1e-3;
  const double floor = 1e-4;
  const double b = floor / kBiasInstabilityAllanFactor;
  NoiseChannelParams params;
  params.noise.white_noise_density = n;
  params.noise.gauss_markov = bias_instability_to_gauss_markov_bank(b, 1.0, 1e4);
  params.noise.bias_random_walk_density = floor / std::sqrt(1e5 / 3.0);
  const double dt = 0.1;
  const std::vector<double> x = record(params, channel_key(3, "auv", "imu", "gyro_x"), dt, 1000000);
  const auto curve = overlapping_allan_deviation(x, dt, log_spaced_cluster_sizes(x.size(), 10, 10000));
  const AllanReadout readout = read_allan(curve);
  EXPECT_NEAR(readout.deviation_at_1s / n, std::sqrt(1.0 + (floor / n) * (floor / n)), allan_tolerance(4.0, 1e5));
  const AllanPoint minimum = allan_minimum(curve, 100.0, 1000.0);
  EXPECT_NEAR(minimum.deviation / floor, 1.0, 0.30);
  // The least-squares fit over the whole curve: N to 1 % (many short clusters), B to 15 % (its term
  // only shows above ~100 s, 100-1000 clusters). K is not observable here: at the longest tau (1000 s)
  // its term is 1 % of the floor's.
  const AllanFit fit = fit_allan_terms(curve);
  EXPECT_NEAR(fit.white_noise_density / n, 1.0, 0.01);
  EXPECT_NEAR(fit.bias_instability / b, 1.0, 0.15);
  std::printf("[ figures  ] full channel fit: N %.4f, B %.4f of configured\n", fit.white_noise_density / n,
              fit.bias_instability / b);
  std::printf("[ figures  ] full channel: sigma(1 s) / N = %.4f, min over [100, 1000] s / 0.664 B = %.4f at %.0f s,"
              " global min / 0.664 B = %.4f at %.0f s\n",
              readout.deviation_at_1s / n, minimum.deviation / floor, minimum.tau_s, readout.floor.deviation / floor,
              readout.floor.tau_s);
}

// ----- datasheet conversions and presets -------------------------------------------------------------

// Hand-computed: 1 deg/sqrt(h) = pi / 180 / 60 rad/s/sqrt(Hz) = 2.908882086657216e-4; 0.125 of that is
// 3.63610260832152e-5; 0.065 ft/s/sqrt(h) = 0.019812 m/s/sqrt(h) -> 3.302e-4 (the CSV's own figure);
// 60 ug/sqrt(Hz) = 5.88399e-4; 1 deg/h = 4.84813681109536e-6 rad/s; 1 deg/h/sqrt(h) = pi / 180 / 216000
// = 8.080228018492267e-8 rad/s^2/sqrt(Hz); 1 m/s/h/sqrt(h) = 1 / 216000 m/s^3/sqrt(Hz).
TEST(NoiseDatasheetTest, Conversions) {
  EXPECT_NEAR(arw_to_noise_density(1.0), 2.908882086657216e-4, 1e-19);
  EXPECT_NEAR(arw_to_noise_density(0.125), 3.63610260832152e-5, 1e-19);
  EXPECT_NEAR(vrw_to_noise_density(0.065 * kFootInMeters), 3.302e-4, 1e-18);
  EXPECT_NEAR(vrw_to_noise_density(0.06), 1e-3, 1e-18);
  EXPECT_NEAR(micro_g_per_sqrt_hz_to_noise_density(60.0), 5.88399e-4, 1e-18);
  EXPECT_NEAR(deg_per_h_to_rad_per_s(1.0), 4.84813681109536e-6, 1e-20);
  EXPECT_NEAR(milli_g_to_mps2(1.0), 9.80665e-3, 1e-18);
  EXPECT_NEAR(micro_g_to_mps2(25.0), 2.4516625e-4, 1e-19);
  EXPECT_NEAR(rrw_to_random_walk_density(1.0), 8.080228018492267e-8, 1e-22);
  EXPECT_NEAR(accel_rrw_to_random_walk_density(1.0), 4.6296296296296296e-6, 1e-21);
  // 0.664 B: sqrt(2 ln 2 / pi).
  EXPECT_NEAR(kBiasInstabilityAllanFactor, std::sqrt(2.0 * std::log(2.0) / kPi), 1e-15);
}

// sigma = 0.66428 / 0.61736 B = 1.07600 B (single); 0.66428 / 0.77585 B = 0.85619 B (bank, one term per
// decade from a decade below tau_min to a decade above tau_max, tau_c = peak / 1.8926).
TEST(NoiseDatasheetTest, BiasInstabilityMappings) {
  const GaussMarkovParams single = bias_instability_to_gauss_markov(2.0, 100.0);
  EXPECT_NEAR(single.sigma, 2.0 * 1.0759975729152143, 1e-12);
  EXPECT_EQ(single.correlation_time_s, 100.0);
  const auto bank = bias_instability_to_gauss_markov_bank(2.0, 1.0, 1e4);
  ASSERT_EQ(bank.size(), 7u);
  for (std::size_t k = 0; k < bank.size(); ++k) {
    EXPECT_NEAR(bank[k].sigma, 2.0 * 0.8561942571169366, 1e-12);
    EXPECT_NEAR(bank[k].correlation_time_s * kGaussMarkovAllanPeakTauRatio, std::pow(10.0, k - 1.0),
                1e-12 * std::pow(10.0, k - 1.0));
  }
  EXPECT_EQ(bias_instability_to_gauss_markov_bank(1.0, 1.0, 1e7).size(), 10u);
  EXPECT_THROW(bias_instability_to_gauss_markov_bank(1.0, 1.0, 1e8), std::invalid_argument);
  EXPECT_THROW(bias_instability_to_gauss_markov(1.0, 0.0), std::invalid_argument);
}

// Figures per sample become a channel: density sigma sqrt(T), so a sample's white noise is sigma again
// (white_noise_sigma), with the resolution and range as given.
TEST(NoiseChannelTest, PerSampleWhiteNoiseFigures) {
  const NoiseChannelParams c = per_sample_white_noise(0.05, 0.1, 0.01, 0.3, 100.0);
  EXPECT_DOUBLE_EQ(white_noise_sigma(c.noise.white_noise_density, 0.1), 0.05);
  EXPECT_EQ(c.lsb, 0.01);
  EXPECT_EQ(c.min, 0.3);
  EXPECT_EQ(c.max, 100.0);
  EXPECT_TRUE(std::isinf(per_sample_white_noise(1.0, 1.0, 0.0).max));
}

}  // namespace
}  // namespace hadal::sensors
