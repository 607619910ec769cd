// The force/torque sensor's spec (sensors/force_torque_sensor.h; keys: ForceTorqueSensor::keys()).
#pragma once

#include <limits>

namespace hadal::sensors {

struct ForceTorqueSensor;

struct ForceTorqueSpec {
  using Kind = ForceTorqueSensor;
  // Which side's wrench: false (child_to_parent, Gazebo's default) the wrench the link and what hangs on
  // it apply on its parent; true (parent_to_child) the parent's on the link.
  bool parent_to_child = false;
  double force_noise_stddev = 0.0;   // white noise per sample, each axis [N]
  double torque_noise_stddev = 0.0;  // [N m]
  double force_offset_stddev = 0.0;  // 1-sigma of a zero offset drawn per run, each axis [N]
  double torque_offset_stddev = 0.0;  // [N m]
  double force_resolution = 0.0;      // quantisation step [N]; 0: none
  double torque_resolution = 0.0;     // [N m]
  double force_range_n = std::numeric_limits<double>::infinity();     // readings clip to +-range, each axis
  double torque_range_nm = std::numeric_limits<double>::infinity();
};

}  // namespace hadal::sensors
