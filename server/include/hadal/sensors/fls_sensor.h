// Forward-looking imaging sonar (YAML `type: fls`, marine_acoustic_msgs/ProjectedSonarImage on
// rt/<vehicle>/<sensor>): a fan of `beams` beams over fov in S's x-y plane, beam k at azimuth
//   phi_k = -fov/2 + (k + 1/2) fov / beams   about z_S from x_S (positive to port, y_S),
// each beam_width wide in the fan and vertical_aperture across it (its axis (cos phi, sin phi, 0), u along
// the fan, v = z_S up); tilt it down with the mounting pose. Each ping (render/sonar.h) casts
// rays_per_cell x bins rays per beam (azimuth_rays across the beam, the rest across the vertical aperture),
// so that a range bin of a beam gets rays_per_cell rays on average; echoes are Lambert backscatter through
// spreading and Francois-Garrison absorption, with speckle, receiver noise and TVG (sensors/sonar.h).
// Message (the UW-APL Oculus driver's convention, which sonar_image_proc reads): beam_directions in the
// sonar frame of marine_acoustic_msgs (z forward = x_S, x up = z_S, y = -y_S), beam k = (0, -sin phi_k,
// cos phi_k); ranges the bin centres [m]; image range-major (sample of beam k in bin b at index
// b * beams + k), uint8 or float32 (sensors/sonar.h); ping_info the frequency, the sound speed at the sonar,
// rx_beamwidths the beam width and tx_beamwidths the vertical aperture per beam [rad]. header.frame_id
// is the sensor's frame_id, stamped with the ping's time.
// Captured like a camera (sensors/sensor_kind.h): rendered on the ray-cast workers from the snapshot,
// published latency_s later; streams keyed by world.seed, vehicle, sensor and the ping's step.
// YAML keys: FlsSensor::keys() (server/src/sensors/fls_sensor.cc), shown in
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
#include "hadal/sensors/fls_spec.h"

namespace marine_acoustic_msgs::msg {
class ProjectedSonarImage;
class ProjectedSonarImagePubSubType;
}  // namespace marine_acoustic_msgs::msg
namespace sensor_msgs::msg {
class Image;
}

namespace hadal::sensors {

struct FlsSensor {
  static constexpr std::string_view kType = "fls";
  static constexpr bool kCastsRays = false;  // pinged on the workers
  static constexpr bool kCaptures = true;

  using Spec = FlsSpec;
  struct State {
    std::uint64_t noise_key = 0;
    double sound_speed_m_per_s = 0.0;  // of the last ping
    std::vector<std::uint8_t> image;   // the last ping's samples (range-major)
  };
  struct Capture {
    render::SonarWater water;
    std::vector<std::uint8_t> image;
  };

  // A ping's image is large (256 x 512 samples: 128 KB in uint8, 512 KB in float32): writers keep 10, and
  // the monitor leaves it out (sensors/sensor_kind.h); monitors read rt/<vehicle>/<sensor>/preview, the ping
  // drawn as a fan (fan_image, kPreviewHeight rows, mono8), instead.
  struct ImageTopic {
    static constexpr std::string_view kSuffix = "";
    static constexpr int kHistoryDepth = 10;
    static constexpr bool kInMonitor = false;
    static constexpr bool kPreview = true;
    using Message = marine_acoustic_msgs::msg::ProjectedSonarImage;
    using PubSubType = marine_acoustic_msgs::msg::ProjectedSonarImagePubSubType;
    static void fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
    static void fill_preview(const Spec& spec, const State& state, const MessageHeader& header,
                             sensor_msgs::msg::Image& msg);
  };
  static constexpr int kPreviewHeight = 300;

  // A ping's samples (range-major, the spec's encoding) as a fan seen from above, for people (the preview,
  // hadal-validate-sonar): `height` rows of grey levels (SonarImageEncoding::grey), the sonar at
  // (apex_u, apex_v), ahead (x_S) up the image and port (y_S) to its left, px_per_m = (height - 2 margin) /
  // max_range with a margin of 10 px; each pixel takes the sample of the beam and bin its centre falls in,
  // 0 outside the fan or the window. Samples of the wrong size give a black fan.
  struct FanImage {
    int width = 0, height = 0;
    int apex_u = 0, apex_v = 0;
    double px_per_m = 0.0;
    std::vector<std::uint8_t> grey;  // row-major, width x height
  };
  static FanImage fan_image(const Spec& spec, const std::vector<std::uint8_t>& samples, int height);
  using Topics = TopicList<ImageTopic>;

  // Azimuth of beam k about z_S [rad].
  static double beam_azimuth(const Spec& spec, int k);
  // Fills spec.ping from the spec's geometry and acoustics; throws std::invalid_argument as
  // render::SonarPingSpec::validate does.
  static void make_ping(Spec& spec);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static CaptureWork capture(const CaptureContext& context, const Spec& spec, const State& state, Capture& out);
  static void deliver(const SampleContext& context, const Spec& spec, State& state, Capture&& capture);
};

// A product's figures (a preset's, config/preset.h).
struct FlsFigures {
  double frequency_hz = 0.0;
  int beams = 0;
  double fov_deg = 0.0;                // the fan's width
  double beam_width_deg = 0.0;         // a beam's width in the fan
  double vertical_aperture_deg = 0.0;  // a beam's height across the fan
  double max_range = 0.0;  // the preset's receive window [m] (at most the product's maximum)
  int bins = 0;            // samples over the window
  double rate_hz = 0.0;    // pings per second, a working setting within the product's limit

  // Its figures into a spec (the keys the file gives override them).
  void apply(FlsSpec& spec) const;
};
const config::Presets<FlsFigures>& fls_presets();

}  // namespace hadal::sensors
