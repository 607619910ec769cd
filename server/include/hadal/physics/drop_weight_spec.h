// The drop weight's spec (physics/drop_weight.h; keys: DropWeightActuator::keys()).
#pragma once

#include <Eigen/Core>

#include <limits>

#include "hadal/core/units.h"

namespace hadal::physics {

struct DropWeightActuator;

struct DropWeightSpec {
  using Kind = DropWeightActuator;
  Eigen::Vector3d p_LW = Eigen::Vector3d::Zero();  // the weight's centre in L [m]
  double mass = 0.0;                               // [kg]
  double volume = 0.0;                             // displaced [m^3]
  // Triggers: release_altitude [m] above the seabed (-infinity: none), release_time_s sim time [s]
  // (+infinity: none).
  double release_altitude = -std::numeric_limits<double>::infinity();
  double release_time_s = std::numeric_limits<double>::infinity();
};

}  // namespace hadal::physics
