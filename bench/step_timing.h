// The wall time of a Simulation's step, shared by the benchmarks that compare a model with and without
// something (bench/sensors.cc, bench/acoustics.cc).
#pragma once

#include "hadal/core/simulation.h"
#include "timing.h"

namespace hadal::bench {

// Median over `repetitions` fresh simulations of the mean wall time per step of `steps` steps, after 100 steps
// of warm-up [s].
inline double median_seconds_per_step(const Model& model, int steps, int repetitions) {
  std::vector<double> times;
  for (int r = 0; r < repetitions; ++r) {
    Simulation sim(model);
    for (int k = 0; k < 100; ++k) sim.step();
    const Clock::time_point start = Clock::now();
    for (int k = 0; k < steps; ++k) sim.step();
    times.push_back(seconds_since(start) / steps);
  }
  return median(std::move(times));
}

}  // namespace hadal::bench
