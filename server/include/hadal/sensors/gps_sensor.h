// GPS receiver (YAML `type: gps`, sensor_msgs/NavSatFix): a fix only while the antenna (the sensor's
// origin S) is above the water surface, STATUS_NO_FIX with NaN position otherwise; the antenna position
// p_WS plus east, north and up white noise (channel "position"; the streams advance with or without a
// fix, so a dive does not shift later fixes), converted to WGS84 latitude, longitude [deg] and
// ellipsoidal height [m] with W as the local ENU frame at world.origin. Covariance diagonal in ENU,
// COVARIANCE_TYPE_DIAGONAL_KNOWN.
// YAML keys: GpsSensor::keys() (server/src/sensors/gps_sensor.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/gps_spec.h"

namespace sensor_msgs::msg {
class NavSatFix;
class NavSatFixPubSubType;
}  // namespace sensor_msgs::msg

namespace hadal::sensors {

struct GpsSensor {
  static constexpr std::string_view kType = "gps";
  static constexpr bool kCastsRays = false;
  static constexpr bool kCaptures = false;
  using Message = sensor_msgs::msg::NavSatFix;
  using PubSubType = sensor_msgs::msg::NavSatFixPubSubType;

  using Spec = GpsSpec;
  struct State {
    NoiseTriadState noise;  // east, north, up [m]
    bool fix = false;       // last sample
    double latitude_deg = std::numeric_limits<double>::quiet_NaN();
    double longitude_deg = std::numeric_limits<double>::quiet_NaN();
    double height_m = std::numeric_limits<double>::quiet_NaN();  // above the ellipsoid
  };

  // The east, north, up noise triad at sample period `period` [s] (white noise of stddev sigma per fix
  // is a density sigma sqrt(period)).
  static NoiseTriadParams position_noise(const Spec& spec, double period);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

}  // namespace hadal::sensors
