#include "hadal/physics/ocean.h"

#include <gtest/gtest.h>

#include <cmath>
#include <thread>
#include <vector>

#include "hadal/physics/seawater.h"

namespace hadal::physics {
namespace {

constexpr double kG = 9.80665;
constexpr double kPatm = 101325.0;

WaterSpec ramp_water() {
  WaterSpec water;
  water.density_model = DensityModel::kRamp;  // defaults: 1025 kg/m^3, +3.075 kg/m^3 at 1000 m
  return water;
}

WaterSpec ctd_water() {
  WaterSpec water;
  water.density_model = DensityModel::kCtd;
  water.ctd = {{0.0, 20.0, 35.5}, {200.0, 12.0, 35.0}, {1000.0, 4.0, 34.6}, {6000.0, 1.5, 34.7}};
  return water;
}

// Closed forms are evaluated with a different algebraic arrangement; 1e-9 relative is far above rounding.
TEST(OceanTest, ConstantWaterPressureIsTheClosedFormIntegral) {
  WaterSpec water;
  water.density = 1030.0;
  const Ocean ocean(water, kG, 0);
  for (const double d : {1000.0, 6000.0}) {
    EXPECT_NEAR(ocean.pressure(d), kPatm + 1030.0 * kG * d, 1e-9 * ocean.pressure(d));
    EXPECT_EQ(ocean.density(d), 1030.0);
  }
  EXPECT_EQ(ocean.pressure(-5.0), kPatm);  // above the surface: atmospheric
}

TEST(OceanTest, RampDensityAndPressure) {
  const Ocean ocean(ramp_water(), kG, 0);
  EXPECT_DOUBLE_EQ(ocean.density(0.0), 1025.0);
  EXPECT_DOUBLE_EQ(ocean.density(500.0), 1025.0 + 3.075 / 2.0);
  EXPECT_DOUBLE_EQ(ocean.density(1000.0), 1028.075);
  EXPECT_DOUBLE_EQ(ocean.density(6000.0), 1028.075);
  // integral_0^1000 (1025 + 3.075 s / 1000) ds = 1025000 + 1537.5; below: + 1028.075 * 5000.
  const double p1000 = kPatm + kG * (1025000.0 + 1537.5);
  const double p6000 = p1000 + kG * 1028.075 * 5000.0;
  EXPECT_NEAR(ocean.pressure(1000.0), p1000, 1e-9 * p1000);
  EXPECT_NEAR(ocean.pressure(6000.0), p6000, 1e-9 * p6000);
  // Continuous slope at the pycnocline: dp/dd = rho g on both sides.
  EXPECT_NEAR((ocean.pressure(1000.001) - ocean.pressure(999.999)) / 0.002, 1028.075 * kG, 1e-3);
}

// Independent integration: implicit trapezoid (fixed-point iterated) on a 0.02 m grid, second order,
// error ~ L h^2 g rho'' / 12 << 1e-3 Pa; the table (RK4 at 0.5 m + Hermite) must match to 1e-9 relative
// (~0.06 Pa at 6000 m), which bounds interpolation and the RK4 error at the CTD kinks.
TEST(OceanTest, CtdPressureMatchesIndependentIntegration) {
  const WaterSpec water = ctd_water();
  const Ocean ocean(water, kG, 0);
  auto rho = [&](double d, double p) {
    return density_eos80(ocean.salinity(d), its90_to_ipts68(ocean.temperature(d)), (p - kPatm) / 1e4);
  };
  const double h = 0.02;
  double p = kPatm, d = 0.0;
  for (const double target : {123.37, 1000.0, 4321.01, 6000.0}) {
    while (d < target - 1e-9) {
      const double step = std::min(h, target - d);
      const double f0 = kG * rho(d, p);
      double p_next = p + step * f0;
      for (int i = 0; i < 3; ++i) p_next = p + 0.5 * step * (f0 + kG * rho(d + step, p_next));
      p = p_next;
      d += step;
    }
    EXPECT_NEAR(ocean.pressure(target), p, 1e-9 * p) << "depth " << target;
    EXPECT_NEAR(ocean.density(target), rho(target, p), 1e-6) << "depth " << target;
  }
}

// The table OceanFluid reads is what pressure() and density() interpolate: equal at the nodes (the Hermite
// and linear weights there are exactly 1 and 0).
TEST(OceanTest, CtdTableHoldsPressureAndDensityAtTheNodes) {
  const Ocean ocean(ctd_water(), kG, 0);
  const auto nodes = static_cast<std::size_t>(Ocean::kTableDepth / Ocean::kTableStep) + 1;
  ASSERT_EQ(ocean.table_pressure().size(), nodes);
  ASSERT_EQ(ocean.table_density().size(), nodes);
  for (const std::size_t k : {std::size_t{0}, std::size_t{1}, std::size_t{401}, nodes / 2, nodes - 1}) {
    const double depth = static_cast<double>(k) * Ocean::kTableStep;
    EXPECT_EQ(ocean.table_pressure()[k], ocean.pressure(depth)) << "node " << k;
    EXPECT_EQ(ocean.table_density()[k], ocean.density(depth)) << "node " << k;
  }
  EXPECT_EQ(ocean.table_pressure()[0], kPatm);
  EXPECT_TRUE(Ocean(ramp_water(), kG, 0).table_pressure().empty());
}

TEST(OceanTest, CtdProfileInterpolatesTemperatureAndSalinity) {
  const Ocean ocean(ctd_water(), kG, 0);
  EXPECT_DOUBLE_EQ(ocean.temperature(100.0), 16.0);
  EXPECT_DOUBLE_EQ(ocean.salinity(600.0), 34.8);
  EXPECT_DOUBLE_EQ(ocean.temperature(9000.0), 1.5);  // held below the last row
  EXPECT_DOUBLE_EQ(ocean.temperature(-3.0), 20.0);   // held above the first
  // Density at the surface is EOS-80 at zero sea pressure.
  EXPECT_NEAR(ocean.density(0.0), density_eos80(35.5, its90_to_ipts68(20.0), 0.0), 1e-12);
}

TEST(OceanTest, NonCtdTemperatureSalinityAndSoundSpeed) {
  WaterSpec water;
  water.temperature = 20.0;
  water.salinity = 35.0;
  water.atmospheric_pressure = kPatm;
  const Ocean ocean(water, kG, 0);
  EXPECT_EQ(ocean.temperature(3000.0), 20.0);
  EXPECT_EQ(ocean.salinity(3000.0), 35.0);
  // At the surface: Chen-Millero c(35, 20.0048 (T68), 0) = 1521.47 m/s; UNESCO 1983 table value 1521.5.
  EXPECT_NEAR(ocean.sound_speed(0.0), 1521.5, 0.05);
  EXPECT_DOUBLE_EQ(ocean.sound_speed(2000.0),
                   sound_speed_unesco(35.0, its90_to_ipts68(20.0), (ocean.pressure(2000.0) - kPatm) / 1e4));
}

// A sonar's absorption: Francois & Garrison at the water's temperature, salinity, depth and pH, per metre;
// above the surface the surface's.
TEST(OceanTest, SoundAbsorptionIsFrancoisGarrisonAtTheWatersProperties) {
  WaterSpec water;
  water.temperature = 4.0;
  water.salinity = 34.7;
  water.ph = 7.9;
  const Ocean ocean(water, kG, 0);
  EXPECT_DOUBLE_EQ(ocean.sound_absorption_db_per_m(1500.0, 400e3),
                   absorption_francois_garrison_db_per_km(400e3, 4.0, 34.7, 1500.0, 7.9) / 1000.0);
  EXPECT_DOUBLE_EQ(ocean.sound_absorption_db_per_m(-5.0, 400e3), ocean.sound_absorption_db_per_m(0.0, 400e3));
  EXPECT_GT(ocean.sound_absorption_db_per_m(100.0, 900e3), ocean.sound_absorption_db_per_m(100.0, 400e3));
}

TEST(OceanTest, KappaIsOneMinusPressureOverBulkModulus) {
  WaterSpec water = ramp_water();
  water.bulk_modulus = 2.2e9;
  const Ocean ocean(water, kG, 0);
  for (const double d : {0.0, 1000.0, 6000.0}) {
    EXPECT_DOUBLE_EQ(ocean.kappa(d), 1.0 - ocean.pressure(d) / 2.2e9);
  }
  EXPECT_NEAR(ocean.kappa(6000.0), 1.0 - 60.6e6 / 2.2e9, 1e-3);  // ~2.8 % compression at 6 km
}

TEST(OceanTest, BatchSamplingMatchesScalarQueries) {
  WaterSpec water = ramp_water();
  water.surface_z = 10.0;
  const Ocean ocean(water, kG, 0);
  const std::vector<float> z = {20.0f, 10.0f, -490.0f, -5990.0f};
  std::vector<float> rho(z.size()), p(z.size());
  const double offset = ocean.pressure(3000.0);
  ocean.sample(z.data(), z.size(), rho.data(), p.data(), offset);
  for (std::size_t i = 0; i < z.size(); ++i) {
    const double d = 10.0 - z[i];
    EXPECT_FLOAT_EQ(rho[i], static_cast<float>(ocean.density(d)));
    EXPECT_FLOAT_EQ(p[i], static_cast<float>(ocean.pressure(d) - offset));
  }
}

TEST(OceanTest, UniformAndShearCurrent) {
  WaterSpec water;
  water.surface_z = 5.0;
  water.current.uniform_W = Eigen::Vector3d(0.2, -0.1, 0.0);
  water.current.shear_surface_W = Eigen::Vector3d(0.5, 0.0, 0.0);
  water.current.shear_decay_depth = 40.0;
  const Ocean ocean(water, kG, 0);
  const Eigen::Vector3d surface = ocean.current_W(Eigen::Vector3d(3, 4, 5), 12.0);
  EXPECT_NEAR((surface - Eigen::Vector3d(0.7, -0.1, 0.0)).norm(), 0.0, 1e-15);
  const Eigen::Vector3d at_decay = ocean.current_W(Eigen::Vector3d(0, 0, -35.0), 0.0);
  EXPECT_NEAR(at_decay.x(), 0.2 + 0.5 * std::exp(-1.0), 1e-15);
  const Eigen::Vector3d deep = ocean.current_W(Eigen::Vector3d(0, 0, -2000.0), 0.0);
  EXPECT_NEAR((deep - water.current.uniform_W).norm(), 0.0, 1e-15);  // exp(-50) ~ 2e-22

  const std::vector<float> x = {0, 1}, y = {0, 1}, z = {5.0f, -35.0f};
  std::vector<float> vx(2), vy(2), vz(2);
  ocean.sample_current(x.data(), y.data(), z.data(), 2, 0.0, vx.data(), vy.data(), vz.data());
  EXPECT_FLOAT_EQ(vx[0], 0.7f);
  EXPECT_FLOAT_EQ(vx[1], static_cast<float>(at_decay.x()));
  EXPECT_FLOAT_EQ(vy[1], -0.1f);
}

WaterSpec gauss_markov_water(double sigma, double tau) {
  WaterSpec water;
  water.current.gauss_markov_sigma_W = Eigen::Vector3d(sigma, 2.0 * sigma, 0.5 * sigma);
  water.current.gauss_markov_time_constant = tau;
  return water;
}

TEST(OceanTest, GaussMarkovIsAFunctionOfSeedAndTime) {
  const WaterSpec water = gauss_markov_water(0.1, 60.0);
  const Ocean a(water, kG, 42), b(water, kG, 42), c(water, kG, 43);
  // Query b out of order (far time first) and from several threads: values must not depend on that.
  const Eigen::Vector3d b_late = b.gauss_markov_current_W(5000.3);
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i) threads.emplace_back([&b, i] { b.gauss_markov_current_W(1000.0 * i + 7.0); });
  for (auto& thread : threads) thread.join();
  for (const double t : {0.0, 0.4, 17.25, 999.9, 5000.3}) {
    EXPECT_EQ(a.gauss_markov_current_W(t), b.gauss_markov_current_W(t));
    EXPECT_NE(a.gauss_markov_current_W(t), c.gauss_markov_current_W(t));
  }
  EXPECT_EQ(b_late, a.gauss_markov_current_W(5000.3));
  EXPECT_EQ(a.gauss_markov_current_W(-1.0), a.gauss_markov_current_W(0.0));
}

// Sampled on the generation grid (h = tau / 64) over T = 5000 tau. For an OU process the sample std has
// relative std ~ sqrt(tau / (2 T)) = 1 %, the lag-tau autocorrelation and the mean (in sigmas)
// ~ sqrt(2 tau / T) = 2 %: bounds are 4 sigma of those, with the seed fixed.
TEST(OceanTest, GaussMarkovStatistics) {
  const double sigma = 0.1, tau = 10.0;
  const Ocean ocean(gauss_markov_water(sigma, tau), kG, 7);
  const std::size_t lag = 64, n = 5000 * lag;
  std::vector<Eigen::Vector3d> g(n);
  for (std::size_t k = 0; k < n; ++k) g[k] = ocean.gauss_markov_current_W(static_cast<double>(k) * tau / 64.0);
  const Eigen::Vector3d configured = Eigen::Vector3d(sigma, 2.0 * sigma, 0.5 * sigma);
  for (int axis = 0; axis < 3; ++axis) {
    double mean = 0.0;
    for (const auto& v : g) mean += v[axis];
    mean /= static_cast<double>(n);
    double variance = 0.0, covariance = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      variance += (g[k][axis] - mean) * (g[k][axis] - mean);
      if (k + lag < n) covariance += (g[k][axis] - mean) * (g[k + lag][axis] - mean);
    }
    variance /= static_cast<double>(n);
    covariance /= static_cast<double>(n - lag);
    EXPECT_NEAR(mean / configured[axis], 0.0, 0.08) << "axis " << axis;
    EXPECT_NEAR(std::sqrt(variance) / configured[axis], 1.0, 0.04) << "axis " << axis;
    EXPECT_NEAR(covariance / variance, std::exp(-1.0), 0.08) << "axis " << axis;
  }
}

TEST(OceanTest, NoGaussMarkovWhenSigmaIsZero) {
  const Ocean ocean(WaterSpec{}, kG, 1);
  EXPECT_EQ(ocean.gauss_markov_current_W(100.0), Eigen::Vector3d::Zero());
}

TEST(OceanTest, WorldConstructorUsesGravityAndSeed) {
  WorldSpec world;
  world.gravity_W = Eigen::Vector3d(0, 0, -9.0);
  const Ocean ocean(world);
  EXPECT_EQ(ocean.gravity(), 9.0);
  EXPECT_DOUBLE_EQ(ocean.pressure(100.0), kPatm + 1025.0 * 9.0 * 100.0);
}

}  // namespace
}  // namespace hadal::physics
