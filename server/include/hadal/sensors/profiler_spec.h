// The profiler's spec (sensors/profiler_sensor.h; keys: ProfilerSensor::keys()).
#pragma once

#include "hadal/core/units.h"

namespace hadal::sensors {

struct ProfilerSensor;

struct ProfilerSpec {
  using Kind = ProfilerSensor;
  int beams = 256;
  double fov = 120.0 * kDegToRad;        // whole fan [rad]
  double beam_width = 0.5 * kDegToRad;   // in the fan's plane [rad]
  int rays_per_beam = 10;
  double min_range = 0.5;     // [m]
  double max_range = 50.0;    // [m]
  double noise_stddev = 0.01;  // per beam per scan [m]
  double resolution = 0.005;   // quantisation step [m]; 0: none
};

}  // namespace hadal::sensors
