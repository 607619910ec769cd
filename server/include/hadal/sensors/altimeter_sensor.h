// Single-beam altimeter (YAML `type: altimeter`, sensor_msgs/Range, ULTRASOUND): one ray along the
// sensor frame's x axis (the ROS convention for Range; mount it with x down), the first hit on the
// world (its own vehicle is transparent), plus white noise (channel "range"), quantised, reported when
// the true range lies in [min_range, max_range]; -inf when closer, +inf when nothing is within
// max_range (REP 117). The noise stream advances every sample, in the window or not. Defaults are a
// generic 200 kHz echo-sounder altimeter (no data sheet behind them).
// YAML keys: AltimeterSensor::keys() (server/src/sensors/altimeter_sensor.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/altimeter_spec.h"

namespace sensor_msgs::msg {
class Range;
class RangePubSubType;
}  // namespace sensor_msgs::msg

namespace hadal::sensors {

struct AltimeterSensor {
  static constexpr std::string_view kType = "altimeter";
  static constexpr bool kCastsRays = true;
  static constexpr bool kCaptures = false;
  using Message = sensor_msgs::msg::Range;
  using PubSubType = sensor_msgs::msg::RangePubSubType;

  using Spec = AltimeterSpec;
  struct State {
    NoiseChannelState noise;
    double range = 0.0;  // last sample [m]; -inf / +inf outside the window
  };

  // The range channel at sample period `period` [s].
  static NoiseChannelParams channel(const Spec& spec, double period);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

}  // namespace hadal::sensors
