#include "hadal/physics/thruster.h"

#include <cmath>

namespace hadal::physics {

Thruster::Thruster(const ThrusterSpec& spec, const Eigen::Isometry3d& X_BL, double water_density,
                   double dt)
    : p_BT_(X_BL * spec.p_LT),
      axis_B_((X_BL.linear() * spec.axis_L).normalized()),
      max_rotor_speed_(spec.max_rotor_speed),
      // -expm1(-x) = 1 - exp(-x) without cancellation when dt << tau.
      response_per_step_(
          spec.rotor_time_constant > 0.0 ? -std::expm1(-dt / spec.rotor_time_constant) : 1.0),
      thrust_gain_(spec.thrust_coefficient * water_density * std::pow(spec.propeller_diameter, 4)),
      torque_gain_(-spec.handedness * spec.torque_coefficient * water_density *
                   std::pow(spec.propeller_diameter, 5)) {}

ThrusterWrench Thruster::wrench(double n, const Eigen::Isometry3d& X_WB, double surface_z) const {
  ThrusterWrench out;
  out.p_WT = X_WB * p_BT_;
  if (out.p_WT.z() > surface_z) return out;  // in air
  const Eigen::Vector3d axis_W = X_WB.linear() * axis_B_;
  out.thrust = thrust_in_water(n);
  out.torque = torque_in_water(n);
  out.f_W = out.thrust * axis_W;
  out.tau_W = out.torque * axis_W;
  return out;
}

}  // namespace hadal::physics
