// The thruster's spec (physics/thruster.h; keys: ThrusterActuator::keys()).
#pragma once

#include <Eigen/Core>

#include <limits>

#include "hadal/core/units.h"

namespace hadal::physics {

struct ThrusterActuator;

struct ThrusterSpec {
  using Kind = ThrusterActuator;
  Eigen::Vector3d p_LT = Eigen::Vector3d::Zero();     // propeller position in L [m]
  Eigen::Vector3d axis_L = Eigen::Vector3d::UnitX();  // unit thrust direction for n > 0, in L
  double propeller_diameter = 0.0;                    // D [m]
  double thrust_coefficient = 0.0;                    // K_T [-]
  double torque_coefficient = 0.05;                   // K_Q [-]
  double rotor_time_constant_s = 0.1;                 // tau [s], >= 0 (0: rotor follows at once)
  double max_rotor_speed_rev_s = 0.0;                 // n_max [rev/s] (YAML: max_rpm)
  int handedness = 1;                                 // +1 right-handed, -1 left-handed propeller
};

}  // namespace hadal::physics
