// Waves on a floating body (physics/waves.h through physics/ocean_fluid.h and the face kernel): a 10 m square box
// barge of 1 m draft heaves in calm water at its natural period 2 pi sqrt((m + m_a) / (rho g A_wp)), and in long
// regular waves it follows the surface (heave response -> 1).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include "hadal/config/scenario_loader.h"
#include "hadal/core/simulation.h"

namespace hadal {
namespace {

constexpr double kG = 9.80665, kRho = 1025.0, kPi = std::numbers::pi;

// The barge: 10 x 10 x 2 m, 102.5 t (a 1 m draft), its centre of mass 0.5 m below the box's centre, at 200 Hz; `waves`
// the world.waves map, or "" for calm water; `drop` how far above its floating draft it is let go [m].
Model barge(const std::string& waves, double drop, const std::string& fluid = "{model: surface}") {
  // Its own file per test (ctest -j runs the tests of this binary at once).
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("hadal_waves_barge_" + test + "_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << "world:\n  physics_rate_hz: 200\n  water: {density: 1025.0}\n  seabed: {type: plane, z: -500}\n" +
                             (waves.empty() ? std::string() : "  waves: " + waves + "\n") + R"(vehicles:
  - name: barge
    type: surface_vessel
    initial_pose: {position: [0, 0, )" + std::to_string(drop) + R"(]}
    links:
      - name: hull
        mass: 102500
        center_of_mass: [0, 0, -0.5]
        inertia: {ixx: 888333, iyy: 888333, izz: 1708333}
        collisions: [{shape: box, size: [10, 10, 2]}]
    fluid: )" + fluid + "\n";
  const config::LoadResult loaded = config::load_scenario_file(path.string());
  std::filesystem::remove(path);
  EXPECT_TRUE(loaded.model) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  return *loaded.model;
}

// Let go 5 cm above its draft (B at the waterline when floating), it heaves at 2 pi sqrt((m + m_a) / (rho g A_wp))
// with m_a the heave added mass the simulation gives it afloat (the fitted ellipsoid's, scaled by the submerged
// fraction 0.5), within 3 % (the quadratic drag of its bottom adds < 0.1 %).
TEST(SimulationWavesTest, ABargeHeavesAtItsNaturalPeriod) {
  Simulation sim(barge("", 0.05));
  const double m_a = 0.5 * sim.added_mass(0)(2, 2);
  const double expected = 2.0 * kPi * std::sqrt((102500.0 + m_a) / (kRho * kG * 100.0));
  std::vector<double> crossings;
  double previous = sim.state().vehicles[0].body.X_WB.translation().z();
  for (int k = 1; k <= 6000; ++k) {  // 30 s
    sim.step();
    const double z = sim.state().vehicles[0].body.X_WB.translation().z();
    if (previous > 0.0 && z <= 0.0) crossings.push_back((k - 1 + previous / (previous - z)) / 200.0);
    previous = z;
  }
  ASSERT_GE(crossings.size(), 4u);
  const double period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  EXPECT_NEAR(period, expected, 0.03 * expected) << "m_a " << m_a << " kg";
}

// Regular waves of 0.3 m and 20 s (lambda 624 m, 62 times the barge), built up over the default two periods, and the
// default fluid coefficients: from 40 s on, a least-squares fit of [1, t, cos, sin](omega t) to each motion over the
// next three periods gives, against linear theory for a body much smaller than the wave:
// - heave: the wave's amplitude and phase at its centre within 2 % and 2 deg (the response 1 / (1 - (omega /
//   omega_n)^2) is 1.04 for the bare hydrostatics, less with the added mass moving with the water; measured 1.000);
// - pitch: the surface's slope k a (0.17 deg), in phase with -d eta / dx (bow up on the rising face), within 5 % and
//   5 deg (the pitch resonance at 2 s is far; measured +2.4 %);
// - surge: the water's excursion at its centre of mass, a e^(k z_cm), 90 deg behind the heave, within 3 % and 5 deg
//   (Froude-Krylov plus the added mass times the water's acceleration, Morison's inertia, move it with the water;
//   drag on its faces is the rest; measured -0.4 %);
// - drift: the mean surge speed under 2 cm/s (second order: the steady drift force, no more).
// Without the build-up it keeps the orbital velocity it missed at the start as a drift of -a omega (9.4 cm/s); without
// the added mass's share of the water's acceleration its surge is m / (m + m_a) of the water's; without the dynamic
// pressure's gradient in the faces' centre-of-pressure moments its pitch is a third of the slope.
TEST(SimulationWavesTest, InLongWavesABargeFollowsTheSurface) {
  Simulation sim(barge("{spectrum: regular, regular: [{amplitude: 0.3, period: 20}]}", 0.0));
  const double a = 0.3, omega = 2.0 * kPi / 20.0, k = omega * omega / kG;
  // Normal equations of the fit x(t) ~ c0 + c1 (t - 70) + c2 cos(omega t) + c3 sin(omega t), per motion.
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Matrix<double, 4, 3> rhs = Eigen::Matrix<double, 4, 3>::Zero();
  for (int step = 1; step <= 200 * 100; ++step) {  // 100 s
    sim.step();
    const double t = step / 200.0;
    if (t <= 40.0) continue;
    const Eigen::Isometry3d& X = sim.state().vehicles[0].body.X_WB;
    const Eigen::Vector4d basis(1.0, t - 70.0, std::cos(omega * t), std::sin(omega * t));
    normal += basis * basis.transpose();
    // Pitch about y: x_B tilted down by theta gives R(2, 0) = -sin(theta).
    rhs += basis * Eigen::RowVector3d(X.translation().z(), std::asin(-X.linear()(2, 0)), X.translation().x());
  }
  const Eigen::Matrix<double, 4, 3> fit = normal.ldlt().solve(rhs);
  const auto amplitude = [&](int m) { return std::hypot(fit(2, m), fit(3, m)); };
  const auto phase = [&](int m) { return std::atan2(fit(3, m), fit(2, m)); };  // of A cos(omega t - phase)
  std::printf("heave %.4f m at %.2f deg, pitch %.5f rad at %.2f deg, surge %.4f m at %.2f deg, drift %.4f m/s\n",
              amplitude(0), phase(0) * 180 / kPi, amplitude(1), phase(1) * 180 / kPi, amplitude(2),
              phase(2) * 180 / kPi, fit(1, 2));
  // The wave at x = 0: eta = a cos(omega t); its slope d eta / dx = a k sin(omega t), so the bow-up pitch
  // -slope = a k cos(omega t + pi / 2); the water's excursion a e^(k z) sin(omega t).
  EXPECT_NEAR(amplitude(0) / a, 1.0, 0.02);
  EXPECT_NEAR(phase(0), 0.0, 2.0 * kPi / 180.0);
  EXPECT_NEAR(fit(0, 0), 0.0, 0.01);  // it floats at its draft
  EXPECT_NEAR(amplitude(1) / (a * k), 1.0, 0.05);
  EXPECT_NEAR(phase(1), -kPi / 2.0, 5.0 * kPi / 180.0);
  const double z_cm = -0.5;
  EXPECT_NEAR(amplitude(2) / (a * std::exp(k * z_cm)), 1.0, 0.03);
  EXPECT_NEAR(phase(2), kPi / 2.0, 5.0 * kPi / 180.0);
  EXPECT_LT(std::abs(fit(1, 2)), 0.02);
}

}  // namespace
}  // namespace hadal
