// Magnetometer (YAML `type: magnetometer`, sensor_msgs/MagneticField, tesla in the sensor frame S):
// sensors/magnetometer.h's chain at the sensor's position p_WS,
//   B_W     = WMM2025(geodetic of p_WS, world.date + t) in W's axes + the world's dipoles
//             (world.magnetic_dipoles: wrecks, pipelines),
//   B_S     = S_S (R_SW B_W + R_SB B_hard_B),   B_hard_B the vehicle's hard-iron dipoles,
// then the noise triad (channel "magnetic_field"): noise, quantisation, range per sensor axis.
// The decimal year of sim time t is world.date + t / (365.25 d) (a Julian year: within 1e-5 of the
// calendar's). Covariance: N^2 rate_hz + lsb^2 / 12 per axis.
// YAML keys: MagnetometerSensor::keys() (server/src/sensors/magnetometer_sensor.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <Eigen/Core>

#include <string>
#include <string_view>
#include <vector>

#include "hadal/sensors/magnetometer.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/magnetometer_spec.h"

namespace sensor_msgs::msg {
class MagneticField;
class MagneticFieldPubSubType;
}  // namespace sensor_msgs::msg

namespace hadal::sensors {

struct MagnetometerSensor {
  static constexpr std::string_view kType = "magnetometer";
  static constexpr bool kCastsRays = false;
  static constexpr bool kCaptures = false;
  using Message = sensor_msgs::msg::MagneticField;
  using PubSubType = sensor_msgs::msg::MagneticFieldPubSubType;

  using Spec = MagnetometerSpec;
  struct State {
    MagnetometerState noise;
    Eigen::Vector3d B_S = Eigen::Vector3d::Zero();  // last sample [T]
  };

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

}  // namespace hadal::sensors
