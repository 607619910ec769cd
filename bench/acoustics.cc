// Cost of acoustic positioning and modems against the default scenario's step (configs/scenarios/default.yaml without
// its camera and sonar, whose captures would swamp the figure). The lander on the seabed carries a USBL
// interrogating at 1 Hz the AUV's transponder 12 m away, and the AUV an LBL ranging at 1 Hz to four beacons
// 150-400 m away. A whole step's time varies by ~3 % from run to run, far more than the acoustics cost, so
// the two are measured apart: the step (median of Simulation runs), and the acoustics alone, run as the
// simulation runs them (each sensor's advance() at every physics step, sample() once a second) through the
// real acoustic channel and ray-cast world, over the state of that simulation. Target (issue 42): < 2 % of
// the step with a USBL at 1 Hz and four modems with traffic: two on each vehicle (EvoLogics S2CR 18/34), each
// sending a 64-byte packet every 2 s to the other vehicle's modems, staggered so some overlap and collide. Prints
// one JSON object per measurement.
//   build/bin/hadal_bench_acoustics [--steps N] [--repetitions R]
#include "hadal/config/scenario_loader.h"
#include "hadal/core/simulation.h"
#include "hadal/core/units.h"
#include "hadal/geometry/scene_rays.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/physics/ocean.h"
#include "hadal/sensors/lbl_sensor.h"
#include "hadal/sensors/modem_sensor.h"
#include "hadal/sensors/sample_context.h"
#include "hadal/sensors/usbl_sensor.h"
#include "step_timing.h"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

hadal::SensorSpec sensor(const std::string& name, hadal::sensors::SensorKindSpec kind) {
  hadal::SensorSpec spec;
  spec.name = name;
  spec.frame_id = name;
  spec.rate_hz = 1.0;
  spec.kind = std::move(kind);
  return spec;
}

}  // namespace

int main(int argc, char** argv) {
  int steps = 20000, repetitions = 7;
  hadal::bench::read_step_options(argc, argv, steps, repetitions);
  const std::optional<hadal::Model> loaded = hadal::bench::load_default_scenario();
  if (!loaded) return 1;
  hadal::Model model = *loaded;
  for (hadal::VehicleSpec& vehicle : model.vehicles) {
    std::erase_if(vehicle.sensors, [](const hadal::SensorSpec& s) { return s.type() == "camera" || s.type() == "fls"; });
  }
  const double step_s = hadal::bench::median_seconds_per_step(model, steps, repetitions);

  // The acoustics over the state the scenario reaches after 1 s.
  model.vehicles[0].transponder = hadal::sensors::TransponderSpec{};
  model.world.acoustics.beacons = {{"a", Eigen::Vector3d(150.0, 0.0, -95.0)},
                                   {"b", Eigen::Vector3d(0.0, 250.0, -95.0)},
                                   {"c", Eigen::Vector3d(-300.0, 0.0, -95.0)},
                                   {"d", Eigen::Vector3d(0.0, -400.0, -95.0)}};
  hadal::sensors::UsblSpec usbl;
  usbl.cone_half_angle = 180.0 * hadal::kDegToRad;
  const hadal::sensors::LblSpec lbl;
  const hadal::SensorSpec usbl_sensor = sensor("usbl", usbl), lbl_sensor = sensor("lbl", lbl);
  hadal::Simulation sim(model);
  const double dt = 1.0 / model.world.physics_rate_hz;
  while (sim.state().time < 1.0) sim.step();
  hadal::SimState state = sim.state();
  // Four modems, two per vehicle, added to the model and the state (modems read each other's there).
  hadal::sensors::ModemSpec modem;
  hadal::sensors::modem_presets()[2].figures.apply(modem);  // evologics_s2cr_18_34
  struct Modem {
    int vehicle = 0, sensor = 0;
  };
  std::vector<Modem> modems;
  for (int v = 0; v < 2; ++v) {
    for (const char* name : {"modem_a", "modem_b"}) {
      hadal::VehicleSpec& vehicle = model.vehicles[static_cast<std::size_t>(v)];
      vehicle.sensors.push_back(sensor(name, modem));
      modems.push_back({v, static_cast<int>(vehicle.sensors.size()) - 1});
    }
  }
  const hadal::physics::Ocean ocean(model.world);
  hadal::sensors::SensorEnvironment environment(model.world.origin);
  hadal::geometry::SceneRays rays(hadal::geometry::build_world_scene(model, "threads=1"));
  const Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const auto context = [&](int vehicle, const hadal::SensorSpec& spec) {
    return hadal::sensors::SampleContext{state.time, 1.0, dt,   model.world, ocean, environment, state,
                                         vehicle,    X_BS, zero, zero,       zero,  &rays,       &spec,
                                         -1,         &model.vehicles};
  };
  hadal::sensors::UsblSensor::State usbl_state = hadal::sensors::UsblSensor::initial_state(
      usbl, hadal::sensors::SensorSetup{model.world.seed, "lander", "usbl", 1.0, environment});
  hadal::sensors::LblSensor::State lbl_state = hadal::sensors::LblSensor::initial_state(
      lbl, hadal::sensors::SensorSetup{model.world.seed, "auv", "lbl", 1.0, environment});
  for (const Modem& m : modems) {
    hadal::VehicleSpec& vehicle = model.vehicles[static_cast<std::size_t>(m.vehicle)];
    hadal::SensorState& out = state.vehicles[static_cast<std::size_t>(m.vehicle)].sensors.emplace_back();
    out.kind = hadal::sensors::ModemSensor::initial_state(
        modem, hadal::sensors::SensorSetup{model.world.seed, vehicle.name,
                                           vehicle.sensors[static_cast<std::size_t>(m.sensor)].name, 1.0, environment});
  }
  const auto modem_state = [&](const Modem& m) -> hadal::sensors::ModemSensor::State& {
    return std::get<hadal::sensors::ModemSensor::State>(
        state.vehicles[static_cast<std::size_t>(m.vehicle)].sensors[static_cast<std::size_t>(m.sensor)].kind);
  };
  const int per_second = static_cast<int>(model.world.physics_rate_hz);
  std::uint64_t packets = 0, refused = 0;  // over every measurement
  std::uint64_t fixes = 0, ranges = 0;
  // One measurement: the positioning sensors, the modems or both, from the same state each repetition.
  const hadal::SimState start_state = state;
  const hadal::sensors::UsblSensor::State usbl_start = usbl_state;
  const hadal::sensors::LblSensor::State lbl_start = lbl_state;
  const auto measure = [&](bool positioning, bool with_modems) {
    std::vector<double> costs;
    for (int r = 0; r < repetitions; ++r) {
      state = start_state;
      usbl_state = usbl_start;
      lbl_state = lbl_start;
      const hadal::bench::Clock::time_point start = hadal::bench::Clock::now();
      for (int k = 0; k < steps; ++k) {
        state.time += dt;
        ++state.step_count;
        if (positioning) {
          if (hadal::sensors::UsblSensor::advance(context(1, usbl_sensor), usbl, usbl_state)) fixes += usbl_state.fixes.size();
          if (hadal::sensors::LblSensor::advance(context(0, lbl_sensor), lbl, lbl_state)) ranges += lbl_state.ranges.size();
          if (k % per_second == 0) {
            hadal::sensors::UsblSensor::sample(context(1, usbl_sensor), usbl, usbl_state);
            hadal::sensors::LblSensor::sample(context(0, lbl_sensor), lbl, lbl_state);
          }
        }
        if (!with_modems) continue;
        for (std::size_t i = 0; i < modems.size(); ++i) {
          const Modem& m = modems[i];
          const hadal::VehicleSpec& vehicle = model.vehicles[static_cast<std::size_t>(m.vehicle)];
          if (k % (2 * per_second) == static_cast<int>(i) * per_second / 7) {
            refused += !hadal::sensors::ModemSensor::send(model.vehicles, m.vehicle, m.sensor, modem, modem_state(m),
                                                          state.time, model.vehicles[1 - m.vehicle].name,
                                                          std::vector<std::uint8_t>(64, static_cast<std::uint8_t>(k)))
                            .empty();
          }
          if (hadal::sensors::ModemSensor::advance(
                  context(m.vehicle, vehicle.sensors[static_cast<std::size_t>(m.sensor)]), modem, modem_state(m))) {
            packets += modem_state(m).delivered.size();
          }
        }
      }
      costs.push_back(hadal::bench::seconds_since(start) / steps);
    }
    return hadal::bench::median(costs);
  };
  const double positioning_s = measure(true, false);
  const double modems_s = measure(false, true);
  const double cost_s = measure(true, true);
  std::printf("{\"benchmark\": \"acoustics_step_cost\", \"step_ns\": %.0f, \"positioning_ns_per_step\": %.1f, "
              "\"modems_ns_per_step\": %.1f, \"acoustics_ns_per_step\": %.1f, \"share_of_step\": %.5f, "
              "\"usbl_fixes\": %llu, \"lbl_ranges\": %llu, \"modems\": %zu, \"packets_decoded\": %llu, "
              "\"sends_refused\": %llu, \"target\": 0.02}\n",
              step_s * 1e9, positioning_s * 1e9, modems_s * 1e9, cost_s * 1e9, cost_s / step_s,
              static_cast<unsigned long long>(fixes), static_cast<unsigned long long>(ranges), modems.size(),
              static_cast<unsigned long long>(packets), static_cast<unsigned long long>(refused));
  return 0;
}
