// Single-beam altimeter (YAML `type: altimeter`, sensor_msgs/Range, ULTRASOUND): one ray along the
// sensor frame's x axis (the ROS convention for Range; mount it with x down), the first hit on the
// world (its own vehicle is transparent), plus white noise (channel "range"), quantised, reported when
// the true range lies in [min_range, max_range]; -inf when closer, +inf when nothing is within
// max_range (REP 117). The noise stream advances every sample, in the window or not. Defaults are a
// generic 200 kHz echo-sounder altimeter (no data sheet behind them).
// YAML keys (configs/REFERENCE.md): min_range [m] (0.3), max_range [m] (100), noise_stddev [m] (0.01,
// per sample), resolution [m] (0.001; 0: none), field_of_view_deg (6, reported only).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"

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

  struct Spec {
    using Kind = AltimeterSensor;
    double min_range = 0.3;                    // [m]
    double max_range = 100.0;                  // [m]
    double noise_stddev = 0.01;                // white noise per sample [m]
    double resolution = 0.001;                 // quantisation step [m]; 0: none
    double field_of_view = 6.0 * kDegToRad;     // full beam width, reported only [rad]
  };
  struct State {
    NoiseChannelState noise;
    double range = 0.0;  // last sample [m]; -inf / +inf outside the window
  };

  // The range channel at sample period `period` [s].
  static NoiseChannelParams channel(const Spec& spec, double period);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

}  // namespace hadal::sensors
