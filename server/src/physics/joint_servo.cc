#include "hadal/physics/joint_servo.h"

#include <algorithm>

namespace hadal::physics {

double joint_servo_torque(const JointServoSpec& spec, JointCommandMode mode, double target, double q, double qd) {
  double tau = target;
  switch (mode) {
    case JointCommandMode::kPosition: {
      // kp (q* - q) - kd qd = kd (qd_wanted - qd) with qd_wanted = kp (q* - q) / kd: that rate is what the
      // velocity limit bounds (a PD law without kd has no rate to bound).
      if (spec.kd > 0.0) {
        const double wanted = std::clamp(spec.kp * (target - q) / spec.kd, -spec.velocity_limit, spec.velocity_limit);
        tau = spec.kd * (wanted - qd);
      } else {
        tau = spec.kp * (target - q);
      }
      break;
    }
    case JointCommandMode::kVelocity:
      tau = spec.kd * (std::clamp(target, -spec.velocity_limit, spec.velocity_limit) - qd);
      break;
    case JointCommandMode::kEffort:
      break;
  }
  return std::clamp(tau, -spec.effort_limit, spec.effort_limit);
}

}  // namespace hadal::physics
