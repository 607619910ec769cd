// The buoyancy engine's spec (physics/buoyancy_engine.h; keys: BuoyancyEngineActuator::keys()).
#pragma once

#include <Eigen/Core>

#include <limits>

#include "hadal/core/units.h"

namespace hadal::physics {

struct BuoyancyEngineActuator;

struct BuoyancyEngineSpec {
  using Kind = BuoyancyEngineActuator;
  Eigen::Vector3d p_LE = Eigen::Vector3d::Zero();  // the bladder's centre in L [m]
  double max_volume_change = 0.0;                  // Delta V_max [m^3]
  double pump_rate = 0.0;                          // q [m^3/s]
  double efficiency = 0.5;                         // eta, in (0, 1]
};

}  // namespace hadal::physics
