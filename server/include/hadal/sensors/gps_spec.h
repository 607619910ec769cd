// The GPS receiver's spec (sensors/gps_sensor.h; keys: GpsSensor::keys()).
#pragma once


namespace hadal::sensors {

struct GpsSensor;

struct GpsSpec {
  using Kind = GpsSensor;
  double horizontal_stddev = 1.5;  // per horizontal axis, per fix [m]
  double vertical_stddev = 3.0;    // [m]
};

}  // namespace hadal::sensors
