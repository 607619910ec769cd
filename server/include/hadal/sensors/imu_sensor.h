// IMU (YAML `type: imu`, sensor_msgs/Imu): angular rate and specific force at the sensor's mounting
// point in the sensor frame S,
//   w_S = R_SW w_WB,   f_S = R_SW (a_WBcm + alpha x r + w x (w x r) - g_W),   r = p_WS - p_WBcm,
// with a_WBcm and alpha the mean accelerations over the physics step that ends at the sample (exact for
// Bullet's semi-implicit step); then the paper's error chain per triad (sensors/noise.h: misalignment
// and scale, bias random walk, Gauss-Markov bias instability, white noise), temperature drift
// (T - T_ref) k_T with the ocean's temperature at the sensor, thruster vibration A sin(2 pi f t) with f
// the named thruster's rotor speed times its blade count, quantisation and range. Random streams:
// channels "gyro" and "accel". No orientation estimate (orientation_covariance[0] = -1); covariances
// N^2 rate_hz per axis from the white noise.
// YAML keys: ImuSensor::keys() (server/src/sensors/imu_sensor.cc). Data-sheet units are converted on load
// with the IEEE 952 conversions of sensors/noise.h.
#pragma once

#include <Eigen/Core>

#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/config/preset.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/imu_spec.h"

namespace sensor_msgs::msg {
class Imu;
class ImuPubSubType;
}  // namespace sensor_msgs::msg

namespace hadal::sensors {

struct ImuSensor {
  static constexpr std::string_view kType = "imu";
  static constexpr bool kCastsRays = false;
  static constexpr bool kCaptures = false;
  static constexpr bool kOnMovingLink = false;  // its rates and accelerations are the body's
  using Message = sensor_msgs::msg::Imu;
  using PubSubType = sensor_msgs::msg::ImuPubSubType;

  using Spec = ImuSpec;
  using Figures = ImuFigures;
  struct State {
    NoiseTriadState gyro;
    NoiseTriadState accel;
    Eigen::Vector3d angular_velocity_S = Eigen::Vector3d::Zero();  // last sample [rad/s]
    Eigen::Vector3d specific_force_S = Eigen::Vector3d::Zero();    // last sample [m/s^2]
  };

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

// ---------------------------------------------------------------------------------------------------
// IMU data-sheet presets (docs/reference/sensors/imu_datasheet_figures.csv, rows not marked unverified;
// each preset names its source)
// ---------------------------------------------------------------------------------------------------

// HG1700, HG9900, Primus 200, STIM300 (10 g) and the Xsens MTi-300 noise densities (its bias figures
// are unverified and left out); the KVH 1750 and iXblue rows are unverified and not presets.
const config::Presets<ImuDatasheet>& imu_presets();

struct ImuNoiseParams {
  NoiseTriadParams gyro;   // [rad/s]
  NoiseTriadParams accel;  // [m/s^2]
};
// A datasheet as triad parameters: ARW/VRW -> white noise, RRW -> bias random walk, bias instability ->
// bias_instability_to_gauss_markov_bank(B, bank_tau_min_s, bank_tau_max_s), ppm -> scale_factor_sigma,
// misalignment -> misalignment_sigma, range -> min/max. No quantization (no LSB listed).
ImuNoiseParams imu_noise_params(const ImuDatasheet& sheet, double bank_tau_min_s = 1.0, double bank_tau_max_s = 1e5);

}  // namespace hadal::sensors
