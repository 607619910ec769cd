// Ultra-short baseline acoustic positioning (YAML `type: usbl`, hadal_msgs/UsblFixes): a transceiver on a
// vessel (or any vehicle) that interrogates every other vehicle's transponder (YAML `transponder:` in a
// vehicle definition) and fixes each reply's range and direction in its frame S (docs/ARCHITECTURE.md,
// "Acoustic positioning").
//
// One interrogation per sample (rate_hz, the interrogation rate), emitted from p_WS at the sample time t_i.
// Through the acoustic channel (sensors/acoustic_channel.h: straight rays, harmonic-mean sound speed,
// spreading + Francois–Garrison absorption, Wenz noise in the band, occlusion by the seabed and bodies),
// as every two-way ranging device (sensors/acoustic_interrogation.h):
//   1. the interrogation reaches transponder T (position p_WT = X_WB p_BT, moving with its vehicle) at t_a,
//      the time its wavefront meets T's track; T hears it when SL_usbl - TL - NL >= T's threshold and the
//      path is clear;
//   2. T replies at t_r = t_a + turnaround_s from where it is then;
//   3. the reply reaches the transceiver (moving too) at t_f; it is detected when
//      SNR = SL_T - TL - NL + DI >= detection_threshold_db, it arrives from within cone_half_angle of -z_S,
//      the slant range is within max_range and the path is clear.
// A detected reply is a fix stamped t_f (the true latency: two travel times and the turnaround):
//   two-way time   tau = t_f - t_i - turnaround_s (T's turnaround is known to the system)
//   range          r = c_bar tau / 2 + n_r,  c_bar the harmonic-mean sound speed of the reply's path (a
//                  system with the true sound-velocity profile: unbiased), n_r ~ N(0, sigma_r^2); for a
//                  moving transponder the mean of its two legs, as a real USBL's two-way range
//   direction      u_S, the unit vector from the transceiver at t_f to T at t_r in S, turned by two
//                  independent angles ~ N(0, sigma_b^2) about axes across it
//   errors         sigma = sigma_0 max(1, 10^((SNR_ref - SNR) / 20)): the configured figure at and above the
//                  reference SNR, growing as 1 / sqrt(SNR) below it (the Cramer–Rao scaling of time and
//                  phase-difference estimates)
//   position       p_S = r u_S; bearing = atan2(y_S, x_S), elevation = asin(z_S / r) (negative below);
//                  covariance in S: sigma_r^2 u u^T + (r sigma_b)^2 (I - u u^T)
//   geo-referenced p_W = X_WS(t_f) p_S (the transceiver's true pose: no attitude or heading error) and its
//                  WGS84 latitude, longitude and ellipsoidal height (world.origin; sensors/geodesy.h).
// Each exchange's draws come from the sensor's streams ("range", "bearing") in the order fixes arrive.
// Deliberately left out: ray bending, multipath, the transceiver's attitude sensor, clock drift.
// YAML keys: UsblSensor::keys() (server/src/sensors/usbl_sensor.cc), shown in configs/REFERENCE.md.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/sensors/acoustic_interrogation.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/usbl_spec.h"

namespace hadal_msgs::msg {
class UsblFixes;
class UsblFixesPubSubType;
}  // namespace hadal_msgs::msg

namespace hadal::sensors {

struct UsblFix {
  double stamp = 0.0;               // reception of the reply [s]
  double interrogation_time = 0.0;  // [s]
  int target = -1;                  // the transponder's vehicle (SimState index)
  std::string target_name;          // its name
  double travel_time = 0.0;         // two-way, turnaround removed [s]
  double range = 0.0;               // measured slant range [m]
  double bearing = 0.0;             // [rad]
  double elevation = 0.0;           // [rad]
  Eigen::Vector3d p_S = Eigen::Vector3d::Zero();     // measured position of the transponder in S [m]
  Eigen::Matrix3d covariance_S = Eigen::Matrix3d::Zero();  // [m^2]
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();     // the same in W [m]
  double latitude_deg = 0.0, longitude_deg = 0.0, height = 0.0;  // WGS84; height above the ellipsoid [m]
  double snr_db = 0.0;
  std::uint64_t interrogation = 0;  // the interrogation's index (0, 1, ...)
};

struct UsblSensor {
  static constexpr std::string_view kType = "usbl";
  static constexpr bool kCastsRays = true;  // occlusion
  static constexpr bool kCaptures = false;
  using Message = hadal_msgs::msg::UsblFixes;
  using PubSubType = hadal_msgs::msg::UsblFixesPubSubType;

  using Spec = UsblSpec;

  struct State {
    RandomStream range_noise;
    RandomStream bearing_noise;
    InterrogationState interrogation;  // exchanges in flight (sensors/acoustic_interrogation.h)
    std::vector<UsblFix> fixes;        // those of the last step that had any
  };

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  // An interrogation of every transponder but the sensor's own vehicle's.
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static std::optional<double> advance(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
  // A link per interrogation and reply in flight (sensor_kind.h).
  static void acoustic_links(const SampleContext& context, const Spec& spec, const State& state,
                             std::vector<AcousticLink>& out);
};

}  // namespace hadal::sensors
