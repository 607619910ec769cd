// State: everything that evolves during a run (docs/ARCHITECTURE.md, "Model and state"). A plain copyable
// value: Simulation::state() snapshots it after every step and Simulation::set_state() restores it.
#pragma once

#include "hadal/physics/cable.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "hadal/physics/actuator_kinds.h"
#include "hadal/physics/joint_trajectory.h"
#include "hadal/sensors/sensor_kinds.h"

namespace hadal {

// Pose and velocity of a vehicle body frame B in the world W.
struct RigidBodyState {
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_WB = Eigen::Vector3d::Zero();  // velocity of B's origin, expressed in W [m/s]
  Eigen::Vector3d w_WB = Eigen::Vector3d::Zero();  // angular velocity of B, expressed in W [rad/s]
};

// Bits of VehicleState::faults (reported per vehicle on rt/hadal/status).
enum VehicleFault : std::uint32_t {
  kFaultNone = 0,
  kFaultCommandTimeout = 1u << 0,  // watchdog: no fresh client command, controls held at zero
  kFaultNonFiniteState = 1u << 1,  // NaN/Inf detected in the body state; the vehicle was reset
};

enum class CommandSource : std::uint8_t { kNone, kSchedule, kClient };

// A capture taken and not yet delivered (sensors/sensor_kind.h, asynchronous capture): the snapshot its
// rays see and the step at which its sample is due.
struct PendingCapture {
  double time = 0.0;             // sim time of the snapshot [s]
  std::uint64_t step_count = 0;  // of the snapshot
  std::uint64_t due_step = 0;    // delivered at the end of this step (capture + latency)
  std::vector<Eigen::Isometry3d> X_WB;  // every ray body's pose at the snapshot (Simulation::ray_body_poses)
  Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();  // the sensor's mounting in B then (it may move)
};

// A sensor's evolving part: its kind's State (noise streams, biases, the last sample; same alternative
// as the spec's kind), when it last sampled and, for a captured kind, the captures in flight. Part of
// the state, so a restored SimState continues every sensor stream bit-identically.
struct SensorState {
  std::uint64_t samples = 0;  // samples delivered so far (a publisher sends the sample when it changes)
  double stamp = 0.0;         // sim time of the last sample (a capture's: its snapshot's) [s]
  sensors::SensorKindState kind;
  std::vector<PendingCapture> captures;  // oldest first
};

// The kind state of a sensor as kind K's State (K must be the sensor's kind).
template <class K>
const typename K::State& state_of(const SensorState& sensor) {
  return std::get<typename K::State>(sensor.kind);
}

// The state of an actuator as kind K's State (K must be the actuator's kind).
template <class K>
const typename K::State& state_of(const physics::ActuatorKindState& actuator) {
  return std::get<typename K::State>(actuator);
}

struct VehicleState {
  RigidBodyState body;
  std::vector<physics::ActuatorKindState> actuators;  // one per ActuatorSpec, same order and kind
  CommandSource command_source = CommandSource::kNone;
  std::vector<double> client_controls;  // last accepted client command: a whole control vector
  double last_command_time = -std::numeric_limits<double>::infinity();  // sim time [s]
  std::uint32_t faults = kFaultNone;
  std::uint64_t fault_resets = 0;  // how many times the non-finite policy reset this vehicle
  std::vector<SensorState> sensors;  // one per SensorSpec, same order
  // Contact wrench Bullet applied to the body in the last step, at the centre of mass in the B axes
  // of that step's start [N; N m]; zero without contact. Added-mass vehicles feed it into the next
  // step (physics/added_mass.h).
  Eigen::Matrix<double, 6, 1> contact_wrench_B = Eigen::Matrix<double, 6, 1>::Zero();
  // Soil contact (seabed_contact soil, physics/terramechanics.h): per face of the vehicle's surface, its
  // shear displacement in the soil, in W [m]; empty until the vehicle first touches soil.
  std::vector<Eigen::Vector3d> soil_shear_W;
  // An articulated vehicle's moving joints (physics/articulation.h; one each, in body order), empty for a
  // rigid vehicle: coordinates q [rad or m], rates [rad/s or m/s], and the effort each joint's motor
  // applied in the last step [N m or N].
  std::vector<double> joint_positions;
  std::vector<double> joint_velocities;
  std::vector<double> joint_efforts;
  // The command each joint holds (the last accepted): a position, rate or effort as its joint controller
  // takes it (an effort for a joint in none) [rad or m, rad/s or m/s, N m or N]; joint_efforts is what its
  // motor applied in the last step.
  std::vector<double> joint_targets;
  // The rate of each joint's position target (a trajectory's, fed forward by the position law; zero for a
  // held command) [rad/s or m/s].
  std::vector<double> joint_target_rates;
  // Each joint's effort bound from its last command besides its joint's effort_limit (a gripper's
  // max_effort, physics/joint_servo.h) [N m or N]; +inf: none.
  std::vector<double> joint_effort_caps;
  // Per joint controller (VehicleSpec::joint_controllers' order): the trajectory its position group follows
  // (physics/joint_trajectory.h), or none. Shared, never changed in place: a copied state keeps its own.
  std::vector<std::shared_ptr<const physics::JointTrajectory>> joint_trajectories;
  // An articulated vehicle: the generalised force Bullet's constraints (contacts, locked joints' locks)
  // applied in the last step, measured from its velocity change, fed into the next step's generalised
  // solve (implicit joint servos, friction, limits and damping, added mass) as contact_wrench_B is for a rigid
  // vehicle (physics/articulated_dynamics.h; base centre-of-mass force and moment in W, then the joints)
  // [N, N m]; empty until the first step.
  std::vector<double> constraint_force;
  // An articulated vehicle with force_torque sensors: per link (VehicleSpec::links), the wrench its parent
  // applied on it and on everything beyond it across its joint over the last step at whose end one of those
  // sensors sampled (only they read it, so the steps between leave it as it was), in the link's frame L
  // about L's origin (the joint), force then torque [N; N m] (physics/articulated_dynamics.h); zero for a
  // link on no moving joint. Empty for other vehicles.
  std::vector<Eigen::Matrix<double, 6, 1>> joint_wrenches_L;
};

struct SimState {
  double time = 0.0;  // sim time [s]
  std::uint64_t step_count = 0;
  std::vector<VehicleState> vehicles;  // one per VehicleSpec, same order
  std::vector<physics::CableState> cables;  // one per Model::cables entry, same order
};

}  // namespace hadal
