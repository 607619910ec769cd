// The altimeter's spec (sensors/altimeter_sensor.h; keys: AltimeterSensor::keys()).
#pragma once

#include "hadal/core/units.h"

namespace hadal::sensors {

struct AltimeterSensor;

struct AltimeterSpec {
  using Kind = AltimeterSensor;
  double min_range = 0.3;                    // [m]
  double max_range = 100.0;                  // [m]
  double noise_stddev = 0.01;                // white noise per sample [m]
  double resolution = 0.001;                 // quantisation step [m]; 0: none
  double field_of_view = 6.0 * kDegToRad;     // full beam width, reported only [rad]
};

}  // namespace hadal::sensors
