// The track's spec (physics/track.h; keys: TrackActuator::keys()).
#pragma once

#include <Eigen/Core>

#include <limits>

#include "hadal/core/units.h"

namespace hadal::physics {

struct TrackActuator;

struct TrackSpec {
  using Kind = TrackActuator;
  Eigen::Vector3d direction_L = Eigen::Vector3d::UnitX();
  double sprocket_radius = 0.0;        // r [m]
  double max_speed_rad_s = 0.0;        // omega_0 (YAML: max_rpm)
  double stall_torque = 0.0;           // [N m]
  double torque_constant = 1.0;        // [N m/A]
  double drive_inertia = 0.5;          // [kg m^2]
  double speed_time_constant_s = 0.2;  // [s]
};

}  // namespace hadal::physics
