// Pressure sensor (YAML `type: pressure`, sensor_msgs/FluidPressure): absolute pressure at the sensor's
// origin S from the ocean model (atmospheric above the surface),
//   p_ideal = p(max(d(p_WS), 0)),   d = water.surface_z - z,
// then a constant `offset` (the channel's turn-on bias) and white noise of `noise_stddev` per sample,
// quantisation to `resolution` and clipping to [0, range_pa] (sensors/noise.h, one scalar channel
// "pressure"). The message's variance is
// noise_stddev^2 + resolution^2 / 12.
// YAML keys: PressureSensor::keys() (server/src/sensors/pressure_sensor.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/pressure_spec.h"

namespace sensor_msgs::msg {
class FluidPressure;
class FluidPressurePubSubType;
}  // namespace sensor_msgs::msg

namespace hadal::sensors {

struct PressureSensor {
  static constexpr std::string_view kType = "pressure";
  static constexpr bool kCastsRays = false;
  static constexpr bool kCaptures = false;
  using Message = sensor_msgs::msg::FluidPressure;
  using PubSubType = sensor_msgs::msg::FluidPressurePubSubType;

  using Spec = PressureSpec;
  struct State {
    NoiseChannelState noise;
    double pressure = 0.0;  // last sample, absolute [Pa]
  };

  // The noise channel at sample period `period` [s]: white noise of stddev sigma per sample is a
  // density sigma sqrt(period).
  static NoiseChannelParams channel(const Spec& spec, double period);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

}  // namespace hadal::sensors
