// Multibeam echosounder (YAML `type: multibeam`, marine_acoustic_msgs/SonarDetections on
// rt/<vehicle>/<sensor>): a swath of `beams` beams in S's x-y plane, beam k at
//   phi_k = -swath/2 + (k + 1/2) swath / beams   about z_S from x_S,
// each across_beam_width wide in the swath and along_beam_width across it. Mount it like the profiler: x_S
// down, y_S to port (then z_S points forward along track). Each ping (render/sonar.h) casts rays_across x
// rays_along rays per beam, bins the echoes over the receive window and detects the bottom per beam:
// amplitude detection near nadir, phase detection (the seabed crossing the beam's axis) where the echo
// spans kPhaseMinBins bins or more; a beam whose peak is not min_snr_db over the noise has no detection.
// Ranges are the straight-ray distances (refraction is ignored); the two-way travel time is 2 r / c with c
// the sound speed at the sonar.
// Message: per beam flags (DETECT_OK, or DETECT_BAD_SONAR without a detection), two_way_travel_times [s]
// (0 without a detection), tx_delays 0, intensities the echo's peak after TVG [uPa^2], tx_angles 0 and
// rx_angles -phi_k (+ to starboard for the mounting above) [rad]; ping_info the frequency, sound speed at
// the sonar, tx_beamwidths the along-track and rx_beamwidths the across-track width per beam.
// YAML keys: MultibeamSensor::keys() (server/src/sensors/multibeam_sensor.cc), shown in
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
#include "hadal/sensors/multibeam_spec.h"

namespace marine_acoustic_msgs::msg {
class SonarDetections;
class SonarDetectionsPubSubType;
}  // namespace marine_acoustic_msgs::msg

namespace hadal::sensors {

struct MultibeamSensor {
  static constexpr std::string_view kType = "multibeam";
  static constexpr bool kCastsRays = false;
  static constexpr bool kCaptures = true;
  using Message = marine_acoustic_msgs::msg::SonarDetections;
  using PubSubType = marine_acoustic_msgs::msg::SonarDetectionsPubSubType;

  using Spec = MultibeamSpec;
  // Per beam: the detected range [m] (NaN: none) and the echo's peak intensity.
  struct Detections {
    std::vector<double> range_m;
    std::vector<float> intensity;
  };
  struct State {
    std::uint64_t noise_key = 0;
    double sound_speed_m_per_s = 0.0;
    Detections last;
  };
  struct Capture {
    render::SonarWater water;
    Detections detections;
  };

  static double beam_angle(const Spec& spec, int k);
  static void make_ping(Spec& spec);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static CaptureWork capture(const CaptureContext& context, const Spec& spec, const State& state, Capture& out);
  static void deliver(const SampleContext& context, const Spec& spec, State& state, Capture&& capture);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

// A product's figures (a preset's, config/preset.h).
struct MultibeamFigures {
  double frequency_hz = 0.0;
  int beams = 0;
  double swath_deg = 0.0;
  double across_beam_width_deg = 0.0;  // a beam's width in the swath
  double along_beam_width_deg = 0.0;   // a beam's width across it
  double max_range = 0.0;  // the preset's receive window [m] (at most the product's maximum)
  int bins = 0;            // samples over the window
  double rate_hz = 0.0;    // pings per second, a working setting within the product's limit

  // Its figures into a spec (the keys the file gives override them).
  void apply(MultibeamSpec& spec) const;
};
const config::Presets<MultibeamFigures>& multibeam_presets();

}  // namespace hadal::sensors
