// The fin's spec (physics/fin.h; keys: FinActuator::keys()).
#pragma once

#include <Eigen/Core>

#include <limits>

#include "hadal/core/units.h"

namespace hadal::physics {

struct FinActuator;

struct FinSpec {
  using Kind = FinActuator;
  Eigen::Vector3d p_LF = Eigen::Vector3d::Zero();        // centre of pressure in L [m]
  Eigen::Vector3d hinge_axis_L = Eigen::Vector3d::UnitY();  // a, unit
  Eigen::Vector3d chord_L = Eigen::Vector3d::UnitX();    // c0, unit
  double area = 0.0;                                     // S [m^2]
  double aspect_ratio = 0.0;                             // AR (effective)
  double max_angle = 25.0 * kDegToRad;                   // delta_max [rad] (YAML: max_angle_deg)
  double max_rate = 60.0 * kDegToRad;                    // omega_s [rad/s] (YAML: max_rate_deg_per_s)
  double lift_slope = 0.0;                               // C_La [1/rad]; Helmbold's from AR by default
  double stall_angle = 30.0 * kDegToRad;                 // alpha_s [rad] (YAML: stall_angle_deg)
  double drag_coefficient = 0.01;                        // C_D0
  double oswald_efficiency = 0.9;                        // e_O
};

}  // namespace hadal::physics
