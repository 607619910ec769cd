// Side-scan sonar (YAML `type: sidescan`, marine_acoustic_msgs/RawSonarImage on rt/<vehicle>/<sensor>/port
// and .../starboard): two beams looking to either side of S's x axis (mount S like the vehicle: x forward,
// y to port, z up), each depressed by `depression` below S's x-y plane:
//   port axis (0, cos d, -sin d), starboard axis (0, -cos d, -sin d), u = x_S (along track),
// horizontal_beam_width wide along track and vertical_beam_width across (in the plane of y_S and z_S).
// Each ping (render/sonar.h) casts rays_per_cell x bins rays per side (along_rays along track, the rest
// across: from the axis down to nadir and as far up, 2 (90 deg - d), or the vertical beam if wider, weighted
// by the beam pattern), so each range bin of a side gets rays_per_cell rays on average and the first bottom
// return, weak under the pattern, comes from straight below (the altitude), as in a real record; one ping is
// one line of the waterfall a survey builds as the vehicle moves.
// Message per side: sample_rate c / (2 bin) [Hz] with c the sound speed at the sonar, samples_per_beam the
// bins, sample0 = round(min_range / bin) (sample i spans ranges (sample0 + i) bin to (sample0 + i + 1) bin:
// exact when min_range is a whole number of bins, as the default 0),
// tx_delays [0], tx_angles [0], rx_angles [-(pi/2 - d)] port, [+(pi/2 - d)] starboard (+ to starboard),
// image one beam of uint8 or float32 samples (sensors/sonar.h); ping_info per side.
// YAML keys: SidescanSensor::keys() (server/src/sensors/sidescan_sensor.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/config/preset.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/sonar.h"
#include "hadal/sensors/sidescan_spec.h"

namespace marine_acoustic_msgs::msg {
class RawSonarImage;
class RawSonarImagePubSubType;
}  // namespace marine_acoustic_msgs::msg

namespace hadal::sensors {

struct SidescanSensor {
  static constexpr std::string_view kType = "sidescan";
  static constexpr bool kCastsRays = false;
  static constexpr bool kCaptures = true;

  static constexpr int kPort = 0;  // beam index of each side
  static constexpr int kStarboard = 1;

  using Spec = SidescanSpec;
  struct State {
    std::uint64_t noise_key = 0;
    double sound_speed_m_per_s = 0.0;
    std::vector<std::uint8_t> port, starboard;  // the last ping's samples per side
  };
  struct Capture {
    render::SonarWater water;
    std::vector<std::uint8_t> port, starboard;
  };

  struct PortTopic {
    static constexpr std::string_view kSuffix = "port";
    static constexpr bool kInMonitor = false;
    using Message = marine_acoustic_msgs::msg::RawSonarImage;
    using PubSubType = marine_acoustic_msgs::msg::RawSonarImagePubSubType;
    static void fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
  };
  struct StarboardTopic {
    static constexpr std::string_view kSuffix = "starboard";
    static constexpr bool kInMonitor = false;
    using Message = marine_acoustic_msgs::msg::RawSonarImage;
    using PubSubType = marine_acoustic_msgs::msg::RawSonarImagePubSubType;
    static void fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
  };
  using Topics = TopicList<PortTopic, StarboardTopic>;

  static void make_ping(Spec& spec);
  // One side's message (side kPort or kStarboard).
  static void fill_side(const Spec& spec, const State& state, const MessageHeader& header, int side,
                        marine_acoustic_msgs::msg::RawSonarImage& msg);

  static const config::KeyTable<Spec, SensorReader>& keys();
  // Nothing along x_S: it looks to both sides.
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static CaptureWork capture(const CaptureContext& context, const Spec& spec, const State& state, Capture& out);
  static void deliver(const SampleContext& context, const Spec& spec, State& state, Capture&& capture);
};

// A product's figures (a preset's, config/preset.h).
struct SidescanFigures {
  double frequency_hz = 0.0;
  double horizontal_beam_width_deg = 0.0;
  double vertical_beam_width_deg = 0.0;
  double depression_deg = 0.0;  // the arrays' look-down below horizontal
  double max_range = 0.0;  // the preset's receive window [m] (at most the product's maximum)
  int bins = 0;            // samples over the window
  double rate_hz = 0.0;    // pings per second, a working setting within the product's limit

  // Its figures into a spec (the keys the file gives override them).
  void apply(SidescanSpec& spec) const;
};
const config::Presets<SidescanFigures>& sidescan_presets();

}  // namespace hadal::sensors
