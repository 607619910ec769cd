// The wall time of a Simulation's step, shared by the benchmarks that compare a model with and without
// something (bench/sensors.cc, bench/acoustics.cc).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "hadal/config/scenario_loader.h"
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

// `--steps N` and `--repetitions R` from the command line, where given.
inline void read_step_options(int argc, char** argv, int& steps, int& repetitions) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--steps") steps = std::atoi(argv[i + 1]);
    else if (arg == "--repetitions") repetitions = std::atoi(argv[i + 1]);
  }
}

// configs/scenarios/default.yaml of the source tree (HADAL_SOURCE_DIR), or nullopt after printing its errors.
inline std::optional<Model> load_default_scenario() {
  const auto loaded = config::load_scenario_file(std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/default.yaml");
  if (!loaded.ok()) {
    for (const auto& e : loaded.errors) std::fprintf(stderr, "%s\n", e.format().c_str());
    return std::nullopt;
  }
  return *loaded.model;
}

}  // namespace hadal::bench
