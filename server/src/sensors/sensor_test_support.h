// Test support for sensor kinds (unit tests beside the code): a world to sample a kind in the way the
// simulation does, without Bullet. The test sets the vehicles' states and the motion at the start of
// the step; the kind's sample() sees exactly what the simulation would hand it.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "hadal/core/model.h"
#include "hadal/core/state.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/geometry/scene_rays.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/physics/ocean.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors::testing {

class SensorTestWorld {
 public:
  // The model's world and vehicles (bodies at X_WB_initial, v_WB_initial); with_rays builds the world's
  // ray-cast scene (seabed and the vehicles' surfaces).
  explicit SensorTestWorld(Model model_in, bool with_rays = false)
      : model(std::move(model_in)),
        ocean(model.world),
        environment(model.world.origin) {
    for (const VehicleSpec& vehicle : model.vehicles) {
      VehicleState& v = state.vehicles.emplace_back();
      v.body.X_WB = vehicle.X_WB_initial;
      v.body.v_WB = vehicle.v_WB_initial;
      for (const ActuatorSpec& actuator : vehicle.actuators) {
        v.actuators.push_back(std::visit(
            [](const auto& spec) -> physics::ActuatorKindState { return typename std::decay_t<decltype(spec)>::Kind::State{}; },
            actuator.kind));
      }
    }
    if (with_rays) rays = std::make_unique<geometry::SceneRays>(geometry::build_world_scene(model, "threads=1"));
  }

  template <class K>
  typename K::State initial_state(const typename K::Spec& spec, double rate_hz, const std::string& sensor = "sensor",
                                  int vehicle = 0) {
    return K::initial_state(spec, SensorSetup{model.world.seed, model.vehicles[static_cast<std::size_t>(vehicle)].name,
                                              sensor, 1.0 / rate_hz, environment});
  }

  // One sample at the state's time, of a sensor mounted at X_BS on `vehicle`, sampling at rate_hz.
  template <class K>
  void sample(const typename K::Spec& spec, typename K::State& sensor_state, const Eigen::Isometry3d& X_BS,
              double rate_hz, int vehicle = 0) {
    K::sample(context(X_BS, rate_hz, vehicle), spec, sensor_state);
  }

  // The context a sample of a sensor mounted at X_BS (kept alive by the caller) on `vehicle` gets, sampling at
  // rate_hz, at the state's time (for kinds driven step by step: advance() and sample()).
  SampleContext context(const Eigen::Isometry3d& X_BS, double rate_hz, int vehicle = 0) {
    return SampleContext{state.time, 1.0 / rate_hz, step_size, model.world, ocean, environment, state,
                         vehicle, X_BS, p_BBcm, v_WBcm_step_start, w_WB_step_start, rays.get(),
                         sensor_spec, -1, &model.vehicles};
  }

  RigidBodyState& body(int vehicle = 0) { return state.vehicles[static_cast<std::size_t>(vehicle)].body; }

  Model model;
  physics::Ocean ocean;
  SensorEnvironment environment;
  SimState state;
  std::unique_ptr<geometry::SceneRays> rays;
  double step_size = 0.002;  // [s]
  // The composite centre of mass in B, and the motion at the start of the step that ends at the sample.
  Eigen::Vector3d p_BBcm = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WBcm_step_start = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_step_start = Eigen::Vector3d::Zero();
  // The sampled sensor's spec, for kinds that read their link or X_LS (SampleContext::sensor).
  const SensorSpec* sensor_spec = nullptr;
};

// Steps the world by dt up to `until` as the simulation steps a kind whose samples are events (sensor_kind.h):
// advance() every step, then sample() every `every` steps from step 0, for a sensor mounted at X_BS on vehicle
// 0. `move(t)` (if any) places the bodies before each step's sensor work; `arrived(state)` is called after each
// advance() that returns a sample.
template <class K>
void step_events(SensorTestWorld& world, const typename K::Spec& spec, typename K::State& state,
                 const Eigen::Isometry3d& X_BS, double until, double dt, int every,
                 const std::function<void(double)>& move, const std::function<void(const typename K::State&)>& arrived) {
  const double rate_hz = 1.0 / (dt * every);
  for (std::uint64_t step = 0; static_cast<double>(step) * dt <= until; ++step) {
    world.state.step_count = step;
    world.state.time = static_cast<double>(step) * dt;
    if (move) move(world.state.time);
    const SampleContext context = world.context(X_BS, rate_hz);
    if (K::advance(context, spec, state)) arrived(state);
    if (step % static_cast<std::uint64_t>(every) == 0) K::sample(context, spec, state);
  }
}

// One capture of kind K (one that captures by scene work: a camera, a sonar) of the sensor mounted at X_BS on
// `vehicle`, at the world's state, as the simulation makes it: the kind's work on a 2-worker ray-cast service.
// The capture's time is step x world.step_size.
template <class K>
typename K::Capture capture(SensorTestWorld& world, const typename K::Spec& spec, const typename K::State& state,
                            const Eigen::Isometry3d& X_BS, std::uint64_t step = 0, int vehicle = 0) {
  std::vector<Eigen::Isometry3d> X_WB;
  for (const VehicleState& v : world.state.vehicles) X_WB.push_back(v.body.X_WB);
  const CaptureContext context{world.step_size * static_cast<double>(step), step, X_WB, vehicle, X_BS, &world.model,
                               &world.ocean};
  typename K::Capture out;
  const CaptureWork work = K::capture(context, spec, state, out);
  geometry::RaycastService service(world.rays->scene().view(), {2});
  service.submit(X_WB, work).get();
  return out;
}

// Sample i of little-endian float32 samples (a sonar image's bytes).
inline float float32_sample(const std::vector<std::uint8_t>& bytes, std::size_t i) {
  if (4 * i + 4 > bytes.size()) throw std::out_of_range("float32_sample: past the end");
  float v = 0.0f;
  std::memcpy(&v, bytes.data() + 4 * i, sizeof v);
  return v;
}

// A world with the water surface at z = 0, a plane seabed at `seabed_z`, one vehicle "auv" without
// geometry at p_W (rays pass through it unless it has links with collisions).
inline Model one_vehicle_world(const Eigen::Vector3d& p_W, double seabed_z = -100.0) {
  Model model;
  model.world.water.surface_z = 0.0;
  model.world.seabed.z = seabed_z;
  VehicleSpec vehicle;
  vehicle.name = "auv";
  LinkSpec hull;
  hull.name = "hull";
  hull.mass = 1.0;
  vehicle.links = {hull};
  vehicle.X_WB_initial.translation() = p_W;
  model.vehicles = {vehicle};
  return model;
}

// The pose with rotation R and translation p.
inline Eigen::Isometry3d pose(const Eigen::Vector3d& p, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = p;
  return X;
}

// R = Rz(yaw) Ry(pitch) Rx(roll) [rad].
inline Eigen::Matrix3d rpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace hadal::sensors::testing
