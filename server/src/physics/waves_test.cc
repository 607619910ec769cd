// The sea state (physics/waves.h) against closed forms: a sampled JONSWAP sea's record has the target's significant
// height and peak period; each component obeys the dispersion relation and its pressure and orbital velocity decay
// as linear theory says in finite and deep water; Wheeler stretching makes the total pressure zero at the moving
// surface; the same seed gives the same waves.
#include "hadal/physics/waves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <complex>
#include <cstring>
#include <numbers>
#include <vector>

namespace hadal::physics {
namespace {

constexpr double kG = 9.80665, kRho = 1025.0, kPi = std::numbers::pi;

WaveSpec jonswap(double hs, double tp) {
  WaveSpec spec;
  spec.spectrum = WaveSpectrum::kJonswap;
  spec.significant_height = hs;
  spec.peak_period = tp;
  spec.ramp_time = 0.0;  // the full sea from t = 0
  return spec;
}

// A 6 h record of the surface at one point (4 Hz) of a JONSWAP sea, Hs 2 m, Tp 8 s: its standard deviation gives Hs
// within 2 % (the sampled components hold exactly (Hs / 4)^2 of variance; a finite record's variance scatters by
// a few tenths of a per cent), and its Welch periodogram (2048-sample Hann segments, 0.002 Hz bins) peaks within one
// of the spectrum's sampling bins (3.5 f_p / N = 0.0034 Hz) of 1 / Tp.
TEST(WavesTest, AJonswapSeasRecordHasItsSignificantHeightAndPeakPeriod) {
  const WaveSpec spec = jonswap(2.0, 8.0);
  const Waves waves(spec, 0.0, kRho, kG, 7);
  ASSERT_EQ(waves.components().size(), 128u);
  EXPECT_NEAR(waves.significant_height(), 2.0, 1e-12);
  // One component in each of the 128 bins of [0.5, 4] omega_p, at a random place in it: frequencies on an even grid
  // would repeat the record's wave groups every 2 pi / d_omega (5 minutes here).
  const double omega_p = 2.0 * kPi / 8.0, d_omega = 3.5 * omega_p / 128.0;
  double spread = 0.0;
  for (std::size_t i = 0; i < waves.components().size(); ++i) {
    const double in_bin = (waves.components()[i].omega - 0.5 * omega_p) / d_omega - static_cast<double>(i);
    EXPECT_GE(in_bin, 0.0);
    EXPECT_LT(in_bin, 1.0);
    spread += (in_bin - 0.5) * (in_bin - 0.5) / 128.0;
  }
  EXPECT_GT(std::sqrt(spread), 0.2);  // a uniform offset's is 0.29
  const double dt = 0.25;
  const int n = 6 * 3600 * 4;
  std::vector<double> eta(n);
  double mean = 0.0;
  for (int i = 0; i < n; ++i) mean += (eta[i] = waves.surface_height(3.0, -4.0, i * dt)) / n;
  double variance = 0.0;
  for (double e : eta) variance += (e - mean) * (e - mean) / n;
  EXPECT_NEAR(4.0 * std::sqrt(variance), 2.0, 0.02 * 2.0);
  // Welch, over the band 0.04 - 0.4 Hz only (direct DFT of each segment at those bins).
  const int m = 2048;
  const int first = static_cast<int>(0.04 * m * dt), last = static_cast<int>(0.4 * m * dt);
  std::vector<double> power(last + 1, 0.0);
  for (int start = 0; start + m <= n; start += m / 2) {
    for (int b = first; b <= last; ++b) {
      std::complex<double> sum = 0.0;
      for (int j = 0; j < m; ++j) {
        const double window = 0.5 - 0.5 * std::cos(2.0 * kPi * j / (m - 1));
        sum += window * (eta[start + j] - mean) * std::polar(1.0, -2.0 * kPi * b * j / m);
      }
      power[b] += std::norm(sum);
    }
  }
  // The peak frequency as the S^4-weighted mean frequency (Young 1995's estimator: a periodogram's highest bin
  // scatters by a few bins around a JONSWAP peak this broad).
  double weighted = 0.0, weights = 0.0;
  for (int b = first; b <= last; ++b) {
    const double w = std::pow(power[b], 4.0);
    weighted += w * b / (m * dt);
    weights += w;
  }
  const double f_peak = weighted / weights, f_p = 1.0 / 8.0;
  EXPECT_NEAR(f_peak, f_p, 3.5 * f_p / 128.0) << "peak at " << 1.0 / f_peak << " s";
}

// A regular wave, 1 m, 8 s, in 30 m of water: omega^2 = g k tanh(k h) (1e-12); under its crest the dynamic pressure
// is rho g a cosh(k (z + h)) / cosh(k h) and the horizontal orbital velocity a omega cosh(k (z + h)) / sinh(k h), a
// quarter period later the vertical one a omega sinh(k (z + h)) / sinh(k h) (1e-6 relative, down to the seabed). In
// deep water the same wave's decay is exp(k z): at half a wavelength down e^-pi = 4.3 %, at a wavelength 0.19 %.
TEST(WavesTest, PressureAndVelocityDecayAsLinearTheorySays) {
  WaveSpec spec;
  spec.spectrum = WaveSpectrum::kRegular;
  spec.regular = {{1.0, 8.0, 0.0, 0.0}};
  spec.depth = 30.0;
  spec.ramp_time = 0.0;
  const Waves waves(spec, 0.0, kRho, kG, 1);
  const WaveComponent& c = waves.components().front();
  const double h = 30.0, a = 1.0, omega = 2.0 * kPi / 8.0, k = c.k;
  EXPECT_NEAR(omega * omega, kG * k * std::tanh(k * h), 1e-12);
  for (double z : {-0.5, -3.0, -10.0, -29.0}) {
    const Eigen::Vector3d p(0.0, 0.0, z);  // under the crest at t = 0 (the surface 1 m up: z' = 30 (z - 1) / 31)
    const double zs = h * (z - 1.0) / (h + 1.0);
    EXPECT_NEAR(waves.dynamic_pressure(p, 0.0), kRho * kG * a * std::cosh(k * (zs + h)) / std::cosh(k * h),
                1e-6 * kRho * kG * a);
    EXPECT_NEAR(waves.velocity_W(p, 0.0).x(), a * omega * std::cosh(k * (zs + h)) / std::sinh(k * h), 1e-6);
    EXPECT_NEAR(waves.velocity_W(p, 0.0).z(), 0.0, 1e-12);
    // Under the crest the water accelerates down, a omega^2 sinh(k (z' + h)) / sinh(k h), and not along the wave.
    EXPECT_NEAR(waves.acceleration_W(p, 0.0).z(), -a * omega * omega * std::sinh(k * (zs + h)) / std::sinh(k * h), 1e-6);
    EXPECT_NEAR(waves.acceleration_W(p, 0.0).x(), 0.0, 1e-12);
    // A quarter period later the surface at x = 0 is at its mean height (no stretching) on its way down: the water
    // sinks there and accelerates against the wave's travel.
    const double t = 2.0;
    EXPECT_NEAR(waves.surface_height(0.0, 0.0, t), 0.0, 1e-12);
    EXPECT_NEAR(waves.velocity_W(p, t).z(), -a * omega * std::sinh(k * (z + h)) / std::sinh(k * h), 1e-6);
    EXPECT_NEAR(waves.acceleration_W(p, t).x(), -a * omega * omega * std::cosh(k * (z + h)) / std::sinh(k * h), 1e-6);
    EXPECT_NEAR(waves.dynamic_pressure(p, t), 0.0, 1e-6);
  }
  spec.depth = std::numeric_limits<double>::infinity();
  const Waves deep(spec, 0.0, kRho, kG, 1);
  const double kd = omega * omega / kG, lambda = 2.0 * kPi / kd;
  EXPECT_NEAR(deep.components().front().k, kd, 1e-15);
  const double surface = deep.dynamic_pressure(Eigen::Vector3d(0.0, 0.0, 0.0), 2.0);  // a node: 0
  EXPECT_NEAR(surface, 0.0, 1e-9);
  const double crest = kRho * kG * a;
  EXPECT_NEAR(deep.dynamic_pressure(Eigen::Vector3d(0.0, 0.0, -0.5 * lambda), 0.0), crest * std::exp(-kd * (0.5 * lambda + 1.0)),
              1e-6 * crest);
  EXPECT_LT(deep.dynamic_pressure(Eigen::Vector3d(0.0, 0.0, -0.5 * lambda), 0.0), 0.05 * crest);
  EXPECT_LT(deep.dynamic_pressure(Eigen::Vector3d(0.0, 0.0, -lambda), 0.0), 0.002 * crest);
}

// Wheeler stretching: in a short-crested JONSWAP sea (Hs 4 m, Tp 10 s, s = 5) over 40 m of water, at the moving
// surface the hydrostatic rho g (surface_z - z) and the dynamic pressure cancel (1e-9 of rho g Hs), and above it the
// water neither moves nor presses.
TEST(WavesTest, AtTheMovingSurfaceTheTotalPressureIsZero) {
  WaveSpec spec = jonswap(4.0, 10.0);
  spec.spreading = 5.0;
  spec.depth = 40.0;
  const Waves waves(spec, 2.0, kRho, kG, 3);
  for (int i = 0; i < 50; ++i) {
    const double x = 13.0 * i - 200.0, y = 7.0 * i, t = 1.7 * i;
    const double eta = waves.surface_height(x, y, t);
    const Eigen::Vector3d at(x, y, eta);
    EXPECT_NEAR(kRho * kG * (2.0 - eta) + waves.dynamic_pressure(at, t), 0.0, 1e-9 * kRho * kG * 4.0);
    const Eigen::Vector3d above(x, y, eta + 0.01);
    EXPECT_EQ(waves.dynamic_pressure(above, t), 0.0);
    EXPECT_TRUE(waves.velocity_W(above, t).isZero());
    EXPECT_TRUE(waves.acceleration_W(above, t).isZero());
  }
  // The spread directions scatter about the mean (0), both ways.
  double lo = 0.0, hi = 0.0;
  for (const WaveComponent& c : waves.components()) lo = std::min(lo, c.direction), hi = std::max(hi, c.direction);
  EXPECT_LT(lo, -0.3);
  EXPECT_GT(hi, 0.3);
}

// The orbital acceleration is the time derivative of the orbital velocity (central difference) in a short-crested
// sea of a millimetre (1e-3 relative: at larger heights the stretching's own motion, which the acceleration leaves
// out as linear theory does, adds a term of order ak).
TEST(WavesTest, TheAccelerationIsTheVelocitysRate) {
  WaveSpec spec = jonswap(1e-3, 9.0);
  spec.spreading = 10.0;
  spec.depth = 60.0;
  spec.ramp_time.reset();  // the default build-up, 18 s: its rate is in the acceleration too
  const Waves waves(spec, 0.0, kRho, kG, 11);
  const Eigen::Vector3d p(5.0, -3.0, -6.0);
  for (double t : {0.5, 3.3, 17.9, 25.0}) {
    const double h = 1e-4;
    const Eigen::Vector3d rate = (waves.velocity_W(p, t + h) - waves.velocity_W(p, t - h)) / (2.0 * h);
    EXPECT_LT((waves.acceleration_W(p, t) - rate).norm(), 1e-3 * rate.norm()) << t;
    EXPECT_GT(rate.norm(), 0.0);
  }
}

// The build-up: by default two peak periods (regular waves: two of the longest period); calm at t = 0, half the sea at
// half the build-up time (r = (1 - cos(pi / 2)) / 2), the full sea, to the bit, from then on.
TEST(WavesTest, TheSeaBuildsUpFromCalm) {
  WaveSpec spec = jonswap(2.0, 8.0);
  const Waves full(spec, 0.0, kRho, kG, 5);
  spec.ramp_time.reset();
  const Waves built(spec, 0.0, kRho, kG, 5);
  EXPECT_EQ(built.ramp_time(), 16.0);
  const Eigen::Vector3d p(3.0, 4.0, -2.0);
  EXPECT_EQ(built.surface_height(3.0, 4.0, 0.0), 0.0);
  EXPECT_EQ(built.velocity_W(p, 0.0), Eigen::Vector3d::Zero());
  EXPECT_EQ(built.dynamic_pressure(p, 0.0), 0.0);
  EXPECT_NEAR(built.surface_height(3.0, 4.0, 8.0), 0.5 * full.surface_height(3.0, 4.0, 8.0), 1e-15);
  EXPECT_NEAR(built.surface_slope(3.0, 4.0, 8.0).x(), 0.5 * full.surface_slope(3.0, 4.0, 8.0).x(), 1e-15);
  for (double t : {16.0, 16.5, 100.0}) {
    EXPECT_EQ(built.surface_height(3.0, 4.0, t), full.surface_height(3.0, 4.0, t)) << t;
    EXPECT_EQ(built.velocity_W(p, t), full.velocity_W(p, t)) << t;
    EXPECT_EQ(built.acceleration_W(p, t), full.acceleration_W(p, t)) << t;
    EXPECT_EQ(built.dynamic_pressure(p, t), full.dynamic_pressure(p, t)) << t;
  }
  WaveSpec regular;
  regular.spectrum = WaveSpectrum::kRegular;
  regular.regular = {{0.5, 6.0, 0.0, 0.0}, {0.2, 11.0, 1.0, 0.0}, {0.0, 30.0, 0.0, 0.0}};
  EXPECT_EQ(Waves(regular, 0.0, kRho, kG, 1).ramp_time(), 22.0);  // an empty component does not count
}

// The dynamic pressure's gradient (Waves::kinematics, analytic through Wheeler's stretched z') is its central
// difference (1e-6 of rho g a k; h = 1 mm), under the moving surface of a short-crested sea over 25 m of water and over
// deep water, down to 2 mm under the surface (where the stretching's slope terms matter most); and the kinematics
// agree with the single queries to the bit.
TEST(WavesTest, ThePressureGradientIsTheRateOfThePressure) {
  for (const double depth : {25.0, std::numeric_limits<double>::infinity()}) {
    WaveSpec spec = jonswap(3.0, 9.0);
    spec.spreading = 6.0;
    spec.depth = depth;
    const Waves waves(spec, 1.0, kRho, kG, 17);
    for (int i = 0; i < 30; ++i) {
      const double x = 11.0 * i - 150.0, y = 5.0 * i - 40.0, t = 2.3 * i + 1.0;
      const double eta = waves.surface_height(x, y, t);
      for (const double below : {0.002, 0.7, 6.0}) {
        const Eigen::Vector3d p(x, y, eta - below);
        const WaveKinematics k = waves.kinematics(p, t);
        ASSERT_TRUE(k.wet);
        Eigen::Vector3d rate;
        const double h = 1e-3;
        for (int axis = 0; axis < 3; ++axis) {
          Eigen::Vector3d step = Eigen::Vector3d::Zero();
          step[axis] = h;
          rate[axis] = (waves.dynamic_pressure(p + step, t) - waves.dynamic_pressure(p - step, t)) / (2.0 * h);
        }
        EXPECT_LT((k.pressure_gradient_W - rate).norm(), 1e-6 * kRho * kG * 3.0 * 0.05)
            << depth << " " << i << " " << below << ": " << k.pressure_gradient_W.transpose() << " vs "
            << rate.transpose();
        EXPECT_EQ(k.dynamic_pressure, waves.dynamic_pressure(p, t));
        EXPECT_EQ(k.velocity_W, waves.velocity_W(p, t));
        EXPECT_EQ(k.surface_height, eta);
        EXPECT_EQ(k.slope, waves.surface_slope(x, y, t));
      }
    }
  }
}

// Same seed, same waves to the bit; another seed, other waves of the same height.
TEST(WavesTest, SameSeedSameWaves) {
  WaveSpec spec = jonswap(2.0, 8.0);
  spec.spreading = 4.0;
  const Waves a(spec, 0.0, kRho, kG, 42), b(spec, 0.0, kRho, kG, 42), c(spec, 0.0, kRho, kG, 43);
  ASSERT_EQ(a.components().size(), b.components().size());
  EXPECT_EQ(std::memcmp(a.components().data(), b.components().data(), a.components().size() * sizeof(WaveComponent)), 0);
  EXPECT_NE(a.surface_height(1.0, 2.0, 3.0), c.surface_height(1.0, 2.0, 3.0));
  EXPECT_NEAR(c.significant_height(), 2.0, 1e-12);
  EXPECT_FALSE(Waves().enabled());
  EXPECT_EQ(Waves().surface_height(1.0, 2.0, 3.0), 0.0);
}

}  // namespace
}  // namespace hadal::physics
