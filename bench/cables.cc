// Cost of the lumped-mass cable (physics/cable.h) on one thread: 300 m of 17 mm armoured tow cable (EA 1e7 N,
// 2.3 kg/m in air: steel-armoured coax class) in 100 segments, at 500 Hz, its top towed at 2 m/s through water
// with a 0.3 m/s current, its bottom end free; the median of R runs of N steps after 60 s of settling. Target
// (issue 43): >= 20x real time. Prints one JSON object.
//   build/bin/hadal_bench_cables [--steps N] [--repetitions R]
#include "hadal/physics/cable.h"
#include "timing.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

int main(int argc, char** argv) {
  int steps = 5000, repetitions = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--steps") == 0) steps = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--repetitions") == 0) repetitions = std::atoi(argv[i + 1]);
  }
  hadal::physics::CableSpec spec;
  spec.length = 300.0;
  spec.segments = 100;
  spec.diameter = 0.017;
  spec.density = 2.3 / spec.area();
  spec.axial_stiffness = 1.0e7;
  spec.damping_s = 1e-4;
  const double dt = 0.002;
  hadal::physics::CableWorld world;
  world.current_W = Eigen::Vector3d(0.3, 0.0, 0.0);
  const Eigen::Vector3d top0(0.0, 0.0, -5.0);
  hadal::physics::CableState state =
      hadal::physics::straight_cable(spec, top0, top0 - Eigen::Vector3d(0.0, 0.0, spec.length));
  double t = 0.0;
  const auto step = [&] {
    const Eigen::Vector3d a = top0 + Eigen::Vector3d(-2.0 * t, 0.0, 0.0);
    const Eigen::Vector3d b = top0 + Eigen::Vector3d(-2.0 * (t + dt), 0.0, 0.0);
    const hadal::physics::CableStepResult r = hadal::physics::step_cable(spec, world, {true, a, b}, {}, dt, state);
    t += dt;
    return r;
  };
  while (t < 60.0) step();
  std::vector<double> costs;
  int substeps = 0;
  for (int r = 0; r < repetitions; ++r) {
    const hadal::bench::Clock::time_point start = hadal::bench::Clock::now();
    for (int k = 0; k < steps; ++k) substeps = step().substeps;
    costs.push_back(hadal::bench::seconds_since(start) / steps);
  }
  const double cost = hadal::bench::median(costs);
  std::printf("{\"benchmark\": \"cable_step\", \"segments\": %d, \"substeps\": %d, \"us_per_step\": %.2f, "
              "\"real_time_factor\": %.1f, \"target\": 20}\n",
              spec.segments, substeps, cost * 1e6, dt / cost);
  return 0;
}
