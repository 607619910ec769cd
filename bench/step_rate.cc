// Free-run step rate of a scenario's simulation core (no DDS): steps per wall second and the
// real-time factor they correspond to. Prints one JSON object per repetition.
//   build/bin/hadal_bench_step_rate [SCENARIO.yaml] [--sim-seconds S] [--repetitions N] [--threads N]
//                                  [--no-cameras]
// The default is configs/scenarios/default.yaml, 60 s of sim time, 3 repetitions, the scenario's
// world.threads (--threads overrides it, as hadald's does); --no-cameras leaves the cameras out (as
// hadald's: the step without rendering). The whole server
// (with DDS publishing) is measured by bench/run_benchmarks.sh through `hadald --mode fast`.
#include "hadal/config/scenario_loader.h"
#include "hadal/core/simulation.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  std::string scenario = std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/default.yaml";
  double sim_seconds = 60.0;
  int repetitions = 3;
  int threads = 0;  // 0: the scenario's
  bool cameras = true;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--sim-seconds" && i + 1 < argc) sim_seconds = std::atof(argv[++i]);
    else if (arg == "--repetitions" && i + 1 < argc) repetitions = std::atoi(argv[++i]);
    else if (arg == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
    else if (arg == "--no-cameras") cameras = false;
    else if (arg.rfind("--", 0) != 0) scenario = arg;
    else {
      std::fprintf(stderr,
                   "usage: hadal_bench_step_rate [SCENARIO.yaml] [--sim-seconds S] [--repetitions N] [--threads N] "
                   "[--no-cameras]\n");
      return 2;
    }
  }
  hadal::config::LoadResult loaded = hadal::config::load_scenario_file(scenario);
  if (!loaded.ok()) {
    for (const auto& e : loaded.errors) std::fprintf(stderr, "%s\n", e.format().c_str());
    return 1;
  }
  hadal::Model& model = *loaded.model;
  if (threads > 0) model.world.threads = threads;
  if (!cameras) hadal::remove_cameras(model);
  const auto steps = static_cast<std::uint64_t>(sim_seconds * model.world.physics_rate_hz);
  for (int r = 0; r < repetitions; ++r) {
    hadal::Simulation sim(model);
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t k = 0; k < steps; ++k) sim.step();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("{\"benchmark\": \"sim_step_rate\", \"scenario\": \"%s\", \"vehicles\": %zu, "
                "\"physics_rate_hz\": %.0f, \"steps\": %llu, \"wall_s\": %.4f, \"steps_per_s\": %.0f, "
                "\"ns_per_step\": %.0f, \"rtf\": %.1f, \"threads\": %d}\n",
                scenario.c_str(), model.vehicles.size(), model.world.physics_rate_hz,
                static_cast<unsigned long long>(steps), wall, static_cast<double>(steps) / wall,
                1e9 * wall / static_cast<double>(steps), sim.time() / wall, model.world.effective_threads());
  }
  return 0;
}
