// A joint's servo (issue 40's joint actuators; docs/ARCHITECTURE.md, "Articulated vehicles"): the torque
// (revolute) or force (prismatic) a motor behind a gearbox puts on its joint, from ros2_control's three
// command kinds. Hadal's own law:
//   position q*:  tau = kp (q* - q) + kd (qd* - qd), the rate it asks for (kp (q* - q) / kd + qd*) kept
//                 within +-velocity_limit (a target far away is approached at the velocity limit: tau =
//                 kd (+-velocity_limit - qd)); qd* is the target's own rate, 0 for a plain position command
//                 and the interpolated rate while a trajectory is followed (physics/joint_trajectory.h)
//   velocity qd*: tau = kd (clamp(qd*, +-velocity_limit) - qd)
//   effort tau*:  tau = tau*
// and in every mode |tau| <= effort_limit. A gripper (JointControllerSpec below) drives each finger by the
// position law, its target the gripper's command times the finger's multiplier. Gains and limits are at the
// joint (the motor's own times the gear ratio, and its speed divided by it). A saturated servo's torque is constant and damps nothing:
// only the joint's own damping (JointSpec::damping) then settles a swing.
//
// The simulation takes the law implicitly over each step (joint_servo_step, solved with the vehicle's
// equations of motion: physics/articulated_dynamics.h), at the step's end state q + dt qd', qd' = qd +
// dt qdd: stable for any gain and joint inertia (an explicit law would need kd dt / I < 2, which a light
// wrist on a stiff arm's gains breaks), and the same law at rest.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "hadal/config/key_table_fwd.h"

namespace hadal::config {
struct VehicleContext;
}

namespace hadal::physics {

// kGripper: a gripper group's joints, each under the position law (a motor never runs in this mode).
enum class JointCommandMode { kPosition, kVelocity, kEffort, kGripper };

struct JointServoSpec {
  double kp = 0.0;  // [N m/rad] or [N/m]
  double kd = 0.0;  // [N m s/rad] or [N s/m]
  double effort_limit = std::numeric_limits<double>::infinity();    // [N m] or [N], > 0
  double velocity_limit = std::numeric_limits<double>::infinity();  // [rad/s] or [m/s], > 0
};

// The law over a step of dt: tau = torque - D qdd until the torque passes the effort limit (then the limit,
// D = 0). dt = 0 gives the law at (q, qd).
struct ServoStep {
  double torque = 0.0;  // [N m] or [N], not yet limited
  double D = 0.0;       // [N m s^2/rad] or [N s^2/m]: the torque's change per unit qdd over the step
};
ServoStep joint_servo_step(const JointServoSpec& spec, JointCommandMode mode, double target, double q, double qd,
                           double dt, double target_rate = 0.0);

// The joint torque for the command `target` (and, for a position, its rate target_rate) at joint position q
// and rate qd (see above): the law at (q, qd), within the effort limit.
double joint_servo_torque(const JointServoSpec& spec, JointCommandMode mode, double target, double q, double qd,
                          double target_rate = 0.0);

const char* to_string(JointCommandMode mode);

// A group of joints commanded together, ros2_control's shape (YAML `joint_controllers`): a position,
// velocity or effort group whose command is one value per joint, in `joints` order. Gains are per joint
// (YAML: one number for every joint of the group, or a list, one per joint: a wrist needs far smaller
// gains than a shoulder for the same step); each joint's effort and velocity limits are its own
// (links[].joint). A joint is in at most one group; a joint in none takes efforts
// (Simulation::set_joint_efforts).
//
// A gripper (YAML `type: gripper`; ros2_control's gripper controllers, control_msgs/GripperCommand's two
// fields) moves its fingers together: its command is [position] or [position, max_effort]. Finger j is
// held by the position law at multipliers[j] x position (URDF's mimic joints: a parallel gripper's two
// fingers at 1 and 1 when both open positive, 1 and -1 when mirrored), each finger's effort within
// max_effort [N m or N] when the command gives one (else within its joint's effort_limit): how hard the
// fingers squeeze what they hold, which they hold by contact and friction only.
struct JointControllerSpec {
  std::string name;
  JointCommandMode mode = JointCommandMode::kEffort;
  std::vector<int> joints;  // indices of the vehicle's moving joints (in the order of its links)
  std::vector<double> kp;   // per joint of `joints` [N m/rad or N/m]: position, gripper; empty otherwise
  std::vector<double> kd;   // per joint [N m s/rad or N s/m]: position, gripper (0: none), velocity
  std::vector<double> multipliers;  // gripper: per joint, its position per unit of the command; else empty

  // The number of values a command has: one per joint, or a gripper's 1 (position) or 2 (and max_effort).
  std::size_t max_command_values() const { return mode == JointCommandMode::kGripper ? 2 : joints.size(); }
  std::size_t min_command_values() const { return mode == JointCommandMode::kGripper ? 1 : joints.size(); }
};

// The keys of one entry of `joint_controllers`.
const config::KeyTable<JointControllerSpec, config::VehicleContext>& joint_controller_keys();

}  // namespace hadal::physics
