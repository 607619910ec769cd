// What a sensor kind's sample() may read (sensors/sensor_kind.h): the state at the end of the step that
// reaches the sample time, the sensor's mounting, the world and ocean, the shared environment and the
// world's ray-cast scene posed at that state.
#pragma once

#include <Eigen/Geometry>

#include <vector>

#include "hadal/core/model.h"
#include "hadal/core/state.h"
#include "hadal/sensors/sensor_kind.h"

namespace hadal::physics {
class Ocean;
}
namespace hadal::geometry {
class SceneRays;
}

namespace hadal::sensors {

struct SampleContext {
  double time = 0.0;       // sim time of the sample, the state's [s]
  double period = 0.0;     // nominal sample period 1 / rate_hz [s]
  double step_size = 0.0;  // physics step [s]
  const WorldSpec& world;
  const physics::Ocean& ocean;
  SensorEnvironment& environment;
  const SimState& state;
  int vehicle_index = 0;  // the sensor's vehicle (its body index in ray casts)
  const Eigen::Isometry3d& X_BS;  // mounting pose of S in B
  // The vehicle's composite centre of mass in B, and the motion at the start of the step that ends at
  // this sample (for mean accelerations over the step).
  const Eigen::Vector3d& p_BBcm;
  const Eigen::Vector3d& v_WBcm_step_start;  // [m/s], in W
  const Eigen::Vector3d& w_WB_step_start;    // [rad/s], in W
  // The world's ray-cast scene (seabed and every vehicle's surface); null unless some sensor of the
  // simulation casts rays. SceneRays::cast poses the bodies at `state` first.
  geometry::SceneRays* rays = nullptr;
  // The sensor's spec (its link and its mounting X_LS in the link's frame).
  const SensorSpec* sensor = nullptr;
  // The ray body the sensor is mounted on (geometry/world_scene.h), which its rays pass through; -1: the
  // vehicle's base body (vehicle_index).
  int ray_body = -1;
  // Every vehicle's spec, in SimState order (a USBL's transponders); null where a test samples without.
  const std::vector<VehicleSpec>* vehicles = nullptr;

  int own_ray_body() const { return ray_body >= 0 ? ray_body : vehicle_index; }

  const VehicleState& vehicle() const { return state.vehicles[static_cast<std::size_t>(vehicle_index)]; }
  const RigidBodyState& body() const { return vehicle().body; }
  // Position of S's origin and orientation of S in W.
  Eigen::Vector3d p_WS() const { return body().X_WB * X_BS.translation(); }
  Eigen::Matrix3d R_WS() const { return body().X_WB.linear() * X_BS.linear(); }
};

}  // namespace hadal::sensors
