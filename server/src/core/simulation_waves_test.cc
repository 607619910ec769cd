// Waves on a floating body (physics/waves.h through physics/ocean_fluid.h and the face kernel): a 10 m square box
// barge of 1 m draft heaves in calm water at its natural period 2 pi sqrt((m + m_a) / (rho g A_wp)), and in long
// regular waves it follows the surface (heave response -> 1).
#include <gtest/gtest.h>

#include <cmath>
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

// Regular waves of 0.3 m and 20 s (lambda 624 m, 62 times the barge): after 40 s its heave, projected on the wave's
// frequency over the next three periods, has the wave's amplitude and phase at its centre within 5 % and 5 deg (linear
// theory's response 1 / (1 - (omega / omega_n)^2) is 1.02 here; measured 1.034, 2.7 deg). The per-face lift is off:
// with the default C_L 1 the heave's amplitude stays within 1 % but it leads the wave by 12.5 deg and the barge surges
// 2.2 m instead of ~0.3-0.6 m, a force of the lift term in the orbital flow that is issue 44's to resolve next.
TEST(SimulationWavesTest, InLongWavesABargeFollowsTheSurface) {
  Simulation sim(barge("{spectrum: regular, regular: [{amplitude: 0.3, period: 20}]}", 0.0,
                       "{model: surface, hydrodynamics: {lift: 0.0}}"));
  const double omega = 2.0 * kPi / 20.0;
  double c = 0.0, s = 0.0, mean = 0.0, cx = 0.0, sx = 0.0;
  int n = 0;
  for (int k = 1; k <= 200 * 100; ++k) {  // 100 s
    sim.step();
    const double t = k / 200.0;
    if (t <= 40.0) continue;
    const double z = sim.state().vehicles[0].body.X_WB.translation().z();
    c += z * std::cos(omega * t);
    s += z * std::sin(omega * t);
    const double x = sim.state().vehicles[0].body.X_WB.translation().x();
    cx += x * std::cos(omega * t);
    sx += x * std::sin(omega * t);
    mean += z;
    ++n;
  }
  // The wave at the barge: eta = a cos(-omega t) = a cos(omega t), so the heave's cos part carries a.
  const double amplitude = 2.0 * std::hypot(c, s) / n, phase = std::atan2(s, c);
  EXPECT_NEAR(amplitude / 0.3, 1.0, 0.05) << "heave amplitude " << amplitude << " m";
  EXPECT_NEAR(phase, 0.0, 5.0 * kPi / 180.0) << "amplitude " << amplitude << " surge " << 2.0 * std::hypot(cx, sx) / n
                                             << " at " << std::atan2(sx, cx) * 180 / kPi << " deg";
  EXPECT_NEAR(mean / n, 0.0, 0.02);  // it floats at its draft
}

}  // namespace
}  // namespace hadal
