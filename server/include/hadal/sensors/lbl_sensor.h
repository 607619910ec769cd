// Long-baseline acoustic positioning (YAML `type: lbl`, hadal_msgs/LblRanges): a vehicle's transceiver that
// interrogates every beacon of world.acoustics.beacons and measures its range to each from the two-way
// travel time (docs/ARCHITECTURE.md, "Acoustic positioning"). The exchanges are the USBL's
// (sensors/acoustic_interrogation.h), with the beacons fixed in W and the vehicle moving:
//   two-way time   tau = t_f - t_i - turnaround_s (the beacon's, known to the system)
//   range          r = c_bar tau / 2 + n_r, c_bar the harmonic-mean sound speed of the reply's path: the mean
//                  of the two legs (the vehicle moves between interrogation and reception), unbiased,
//                  n_r ~ N(0, sigma_r^2), sigma_r = range_stddev max(1, 10^((SNR_ref - SNR) / 20))
// A range is published when its reply arrives, stamped with that time. No range from a beacon that did
// not hear the interrogation, whose reply is too weak, is hidden by the seabed or a body, or lies beyond
// max_range. Deliberately left out: ray bending, multipath, clock drift. Solving the position from the
// ranges is the navigation filter's job, not the sensor's.
// YAML keys: LblSensor::keys() (server/src/sensors/lbl_sensor.cc), shown in configs/REFERENCE.md.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/sensors/acoustic_interrogation.h"
#include "hadal/sensors/lbl_spec.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"

namespace hadal_msgs::msg {
class LblRanges;
class LblRangesPubSubType;
}  // namespace hadal_msgs::msg

namespace hadal::sensors {

struct LblRange {
  double stamp = 0.0;               // reception of the reply [s]
  double interrogation_time = 0.0;  // [s]
  std::uint64_t interrogation = 0;
  int beacon = -1;                  // index in world.acoustics.beacons
  std::string beacon_name;
  Eigen::Vector3d p_Wbeacon = Eigen::Vector3d::Zero();  // [m]
  double travel_time = 0.0;         // two-way, turnaround removed [s]
  double range = 0.0;               // [m]
  double range_variance = 0.0;      // [m^2]
  double snr_db = 0.0;
};

struct LblSensor {
  static constexpr std::string_view kType = "lbl";
  static constexpr bool kCastsRays = true;  // occlusion
  static constexpr bool kCaptures = false;
  using Message = hadal_msgs::msg::LblRanges;
  using PubSubType = hadal_msgs::msg::LblRangesPubSubType;

  using Spec = LblSpec;
  struct State {
    RandomStream range_noise;
    InterrogationState interrogation;
    std::vector<LblRange> ranges;  // those of the last step that had any
  };

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  // An interrogation of every beacon.
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static std::optional<double> advance(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
  // A link per interrogation and reply in flight (sensor_kind.h).
  static void acoustic_links(const SampleContext& context, const Spec& spec, const State& state,
                             std::vector<AcousticLink>& out);
};

}  // namespace hadal::sensors
