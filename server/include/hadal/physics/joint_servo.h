// A joint's servo (issue 40's joint actuators; docs/ARCHITECTURE.md, "Articulated vehicles"): the torque
// (revolute) or force (prismatic) a motor behind a gearbox puts on its joint, from ros2_control's three
// command kinds. Hadal's own law, applied as a joint torque each step (explicit, so its gains are bounded
// by the step: kd dt / I_joint < 2 and kp dt^2 / I_joint < 1 keep it stable):
//   position q*:  tau = kp (q* - q) - kd qd, the rate it asks for kept within +-velocity_limit (a target
//                 far away is approached at the velocity limit: tau = kd (+-velocity_limit - qd))
//   velocity qd*: tau = kd (clamp(qd*, +-velocity_limit) - qd)
//   effort tau*:  tau = tau*
// and in every mode |tau| <= effort_limit. Gains and limits are at the joint (the motor's own times the
// gear ratio, and its speed divided by it). A saturated servo's torque is constant and damps nothing:
// only the joint's own damping (JointSpec::damping) then settles a swing.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "hadal/config/key_table_fwd.h"

namespace hadal::config {
struct VehicleContext;
}

namespace hadal::physics {

enum class JointCommandMode { kPosition, kVelocity, kEffort };

struct JointServoSpec {
  double kp = 0.0;  // [N m/rad] or [N/m]
  double kd = 0.0;  // [N m s/rad] or [N s/m]
  double effort_limit = std::numeric_limits<double>::infinity();    // [N m] or [N], > 0
  double velocity_limit = std::numeric_limits<double>::infinity();  // [rad/s] or [m/s], > 0
};

// The joint torque for the command `target` at joint position q and rate qd (see above).
double joint_servo_torque(const JointServoSpec& spec, JointCommandMode mode, double target, double q, double qd);

const char* to_string(JointCommandMode mode);

// A group of joints commanded together, ros2_control's shape (YAML `joint_controllers`): a position,
// velocity or effort group whose command is one value per joint, in `joints` order. The gains are the
// group's; each joint's effort and velocity limits are its own (links[].joint). A joint is in at most one
// group; a joint in none takes efforts (Simulation::set_joint_efforts).
struct JointControllerSpec {
  std::string name;
  JointCommandMode mode = JointCommandMode::kEffort;
  std::vector<int> joints;  // indices of the vehicle's moving joints (in the order of its links)
  double kp = 0.0;          // [N m/rad or N/m]: position
  double kd = 0.0;          // [N m s/rad or N s/m]: position (optional), velocity
};

// The keys of one entry of `joint_controllers`.
const config::KeyTable<JointControllerSpec, config::VehicleContext>& joint_controller_keys();

}  // namespace hadal::physics
