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
// YAML keys (configs/REFERENCE.md): preset (a product; sets what the file does not give, and rate_hz unless
// given), beams (256), swath_deg (130), across_beam_width_deg (1), along_beam_width_deg (1), rays_across (32),
// rays_along (4), min_snr_db (10) and the common sonar keys (sensors/sonar.h; bins default 4000 here:
// 1.25 cm over the default 50 m window); latency_s (common to captured sensors).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/sonar.h"

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

  struct Spec {
    using Kind = MultibeamSensor;
    int beams = 256;
    double swath = 130.0 * kDegToRad;            // [rad]
    double across_beam_width = 1.0 * kDegToRad;  // in the swath [rad]
    double along_beam_width = 1.0 * kDegToRad;   // across it [rad]
    int rays_across = 32;
    int rays_along = 4;
    double min_snr_db = 10.0;
    SonarAcoustics acoustics = default_acoustics();
    std::shared_ptr<const render::SonarPingSpec> ping;  // made by read() / make_ping()
  };
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

  static SonarAcoustics default_acoustics();
  static double beam_angle(const Spec& spec, int k);
  static void make_ping(Spec& spec);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static CaptureWork capture(const CaptureContext& context, const Spec& spec, const State& state, Capture& out);
  static void deliver(const SampleContext& context, const Spec& spec, State& state, Capture&& capture);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

struct MultibeamPreset {
  std::string_view name;
  double frequency_hz;
  int beams;
  double swath_deg, across_beam_width_deg, along_beam_width_deg;
  double max_range_m;
  int bins;
  double rate_hz;
};
const std::vector<MultibeamPreset>& multibeam_presets();

}  // namespace hadal::sensors
