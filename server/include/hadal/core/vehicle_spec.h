// A vehicle as a scenario describes it (YAML: an entry of `vehicles`, its definition inline or from a
// file under configs/vehicles/): its links, actuators, sensors, lights and fluid model, where it starts,
// and its open-loop schedule. Each part has a spec of its own (geometry/link_spec.h,
// physics/fluid_spec.h, render/light_spec.h; the sensor and actuator kinds' specs). The keys of a vehicle
// entry and of a definition are declared once in config/vehicle_keys.cc; configs/REFERENCE.md shows them.
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/geometry/link_spec.h"
#include "hadal/physics/actuator_specs.h"
#include "hadal/physics/fluid_spec.h"
#include "hadal/physics/joint_servo.h"
#include "hadal/render/light_spec.h"
#include "hadal/sensors/sensor_specs.h"

namespace hadal {

// kObject: a scenario's `objects` entry (a sample, a rock, a crate): no actuators, sensors, lights or joint
// controllers; it rests, sinks or floats, and can be picked up.
enum class VehicleType { kAuv, kRov, kLander, kSurfaceVessel, kGlider, kCrawler, kObject };

// An actuator (YAML: a list of the vehicle definition per kind, e.g. `thrusters`), mounted on a link. Its
// kind (physics/actuator_kinds.h) says what it is, what it takes from the vehicle's control vector and
// what force it adds (physics/actuator_kind.h).
struct ActuatorSpec {
  std::string name;    // unique within the vehicle
  int link_index = 0;  // index into VehicleSpec::links
  physics::ActuatorKindSpec kind;

  // The kind's name ("thruster", ...).
  std::string_view type() const;
  // Entries of the vehicle's control vector this actuator takes.
  std::size_t num_controls() const;
};

// The kind spec of an actuator as kind K's Spec (K must be the actuator's kind).
template <class K>
const typename K::Spec& spec_of(const ActuatorSpec& actuator) {
  return std::get<typename K::Spec>(actuator.kind);
}

// A sensor (YAML: the vehicle definition's `sensors` list). Each is mounted on a link at X_LS (sensor
// frame S), samples at rate_hz in sim time (sample n at the first physics step whose time reaches
// n / rate_hz: no drift for rates that do not divide the physics rate), computes the ideal value from
// the state, then applies its noise (its kind's module, sensors/<kind>_sensor.h), and is published on
// rt/<vehicle>/<name> with header.frame_id `frame_id` and the sample's sim time as stamp.
struct SensorSpec {
  std::string name;      // unique within the vehicle; topic rt/<vehicle>/<name>
  int link_index = 0;    // index into VehicleSpec::links
  Eigen::Isometry3d X_LS = Eigen::Isometry3d::Identity();  // mounting pose in the link frame
  double rate_hz = 10.0;
  std::string frame_id;  // header.frame_id; default "<vehicle>/<name>"
  double latency_s = 0.0;  // captured kinds (sensors/sensor_kind.h): from capture to delivery [s]
  sensors::SensorKindSpec kind;  // the kind (sensors/sensor_kinds.h) and its parameters

  // The kind's YAML type name ("pressure", "imu", ...).
  std::string_view type() const;
  // A captured kind (sensors/sensor_kind.h): its samples are made on the ray-cast workers.
  bool captured() const;
  // A capture's latency in physics steps: delivered at the end of the first step at or after capture +
  // latency_s (1e-6 step of slack for latencies that are whole steps up to rounding).
  std::uint64_t latency_steps(double physics_rate_hz) const;
};

// The kind spec of a sensor as kind K's Spec (K must be the sensor's kind; std::bad_variant_access
// otherwise).
template <class K>
const typename K::Spec& spec_of(const SensorSpec& sensor) {
  return std::get<typename K::Spec>(sensor.kind);
}

// Zero-order-hold keyframe of a scenario schedule: from time (sim time, s) on, the vehicle's actuators
// take this control vector (one normalised setpoint per thruster, in [-1, 1]).
struct SetpointKeyframe {
  double time = 0.0;  // [s]
  std::vector<double> setpoints;
};

// How a vehicle meets the seabed (YAML: the vehicle definition's `seabed_contact`).
//   kRigid  Bullet's rigid contact of its collision shapes with the seabed (friction 0.4, no bounce).
//   kSoil   the soil's Bekker pressure and Janosi-Hanamoto shear under every face of its surface
//           (physics/terramechanics.h, world.soil) instead; Bullet leaves it and the seabed apart.
enum class SeabedContact { kRigid, kSoil };

struct VehicleSpec {
  std::string name;                 // DDS topics are rt/<name>/...
  VehicleType type = VehicleType::kAuv;
  SeabedContact seabed_contact = SeabedContact::kRigid;
  std::string source_file;          // file the vehicle definition came from (scenario or include)
  std::vector<LinkSpec> links;      // links[0] is the base link; links are rigidly attached to B
  std::vector<ActuatorSpec> actuators;  // their controls form the vehicle's control vector, in order
  std::vector<SensorSpec> sensors;
  std::vector<LightSpec> lights;
  // Its acoustic transponder, which USBLs interrogate (sensors/usbl_sensor.h); none by default.
  std::optional<sensors::TransponderSpec> transponder;
  // Groups of an articulated vehicle's joints commanded together (physics/joint_servo.h).
  std::vector<physics::JointControllerSpec> joint_controllers;
  FluidSpec fluid;
  Eigen::Isometry3d X_WB_initial = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_WB_initial = Eigen::Vector3d::Zero();  // initial linear velocity in W [m/s]
  // YAML `static: true`: fixed at X_WB_initial (a prop, a fixed instrument): no forces act on it and it never
  // moves (a static Bullet body others collide with); its sensors still sample.
  bool is_static = false;
  Eigen::Vector3d w_WB_initial = Eigen::Vector3d::Zero();  // initial angular velocity in W [rad/s]
  std::vector<SetpointKeyframe> schedule;   // used until a client first commands the vehicle
  double command_timeout = 1.0;             // watchdog [s of sim time]
  double odometry_rate_hz = 50.0;
  double actuator_state_rate_hz = 20.0;

  int link_index(const std::string& link_name) const;
  // Length of the control vector: the actuators' controls summed.
  std::size_t num_controls() const;
};

const char* to_string(VehicleType type);
std::optional<VehicleType> vehicle_type_from_string(const std::string& text);

}  // namespace hadal
