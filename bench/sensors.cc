// Cost of sensor sampling inside Simulation::step. For each sensor of the default AUV
// (configs/vehicles/torpedo_auv.yaml) the vehicle is simulated with kCopies copies of that sensor, all
// sampling at the physics rate (every step), and with no sensor; the difference of the median step
// times divided by kCopies is the cost of one sample (ideal value + noise chain) -- the copies lift it
// well above the run-to-run noise of a ~6.5 us step. The default AUV's sensor load is then
// sum_i rate_i x cost_i, as a share of one core. Last, the wall time a captured sensor's scan (the
// profiler) adds to the step that waits for it. Prints one JSON object per measurement.
//   build/bin/hadal_bench_sensors [--steps N] [--repetitions R]
#include "hadal/config/scenario_loader.h"
#include "hadal/core/simulation.h"
#include "hadal/core/units.h"
#include "step_timing.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace {

constexpr int kCopies = 20;

}  // namespace

int main(int argc, char** argv) {
  int steps = 20000, repetitions = 7;
  hadal::bench::read_step_options(argc, argv, steps, repetitions);
  const std::optional<hadal::Model> loaded = hadal::bench::load_default_scenario();
  if (!loaded) return 1;
  hadal::Model base = *loaded;
  base.vehicles.resize(1);
  const std::vector<hadal::SensorSpec> sensors = base.vehicles[0].sensors;
  base.vehicles[0].sensors.clear();
  const double physics_hz = base.world.physics_rate_hz;
  const double without = hadal::bench::median_seconds_per_step(base, steps, repetitions);
  double load = 0.0;
  for (const hadal::SensorSpec& sensor : sensors) {
    hadal::Model with = base;
    with.vehicles[0].sensors.clear();
    for (int c = 0; c < kCopies; ++c) {
      hadal::SensorSpec every_step = sensor;
      every_step.rate_hz = physics_hz;
      every_step.name = sensor.name + "_" + std::to_string(c);
      with.vehicles[0].sensors.push_back(every_step);
    }
    const double cost = std::max(hadal::bench::median_seconds_per_step(with, steps, repetitions) - without, 0.0) / kCopies;
    load += cost * sensor.rate_hz;
    std::printf("{\"benchmark\": \"sensor_sample_cost\", \"sensor\": \"%s\", \"type\": \"%s\", \"ns_per_sample\": %.0f, "
                "\"configured_rate_hz\": %.0f, \"core_share_at_rate\": %.3e}\n",
                sensor.name.c_str(), std::string(sensor.type()).c_str(), cost * 1e9,
                sensor.rate_hz, cost * sensor.rate_hz);
  }
  std::printf("{\"benchmark\": \"default_auv_sensor_load\", \"sensors\": %zu, \"step_without_sensors_ns\": %.0f, "
              "\"core_share\": %.3e, \"target\": 0.05}\n",
              sensors.size(), without * 1e9, load);

  // A captured sensor: the default profiler (256 beams x 10 rays, sensors/profiler_sensor.h) looking down
  // from the AUV, one scan every 10th step with no latency, so each scan's wall time on the ray-cast
  // workers (all hardware threads) adds to the step that waits for it: the stepping thread's wall time
  // per scan, rays and all.
  {
    hadal::Model with = base;
    hadal::SensorSpec profiler;
    profiler.name = "profiler";
    profiler.frame_id = "auv/profiler";
    profiler.X_LS.linear() = Eigen::AngleAxisd(hadal::kPi / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    profiler.rate_hz = physics_hz / 10.0;
    const hadal::sensors::ProfilerSensor::Spec spec;
    profiler.kind.emplace<hadal::sensors::ProfilerSensor::Spec>(spec);
    with.vehicles[0].sensors.push_back(std::move(profiler));
    const double per_scan = std::max(hadal::bench::median_seconds_per_step(with, steps, repetitions) - without, 0.0) * 10.0;
    const double rays = static_cast<double>(spec.beams) * spec.rays_per_beam;
    std::printf("{\"benchmark\": \"captured_sensor_cost\", \"sensor\": \"profiler\", \"rays_per_scan\": %.0f, "
                "\"ns_per_scan\": %.0f, \"rays_per_s\": %.3e}\n",
                rays, per_scan * 1e9, per_scan > 0.0 ? rays / per_scan : 0.0);
  }
  return 0;
}
