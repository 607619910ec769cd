// Profiler (YAML `type: profiler`, sensor_msgs/LaserScan): a fan of range beams in the sensor frame's
// x-y plane, as a profiling sonar or a laser line scanner measures a cross-section of the seabed and
// of what stands on it. Mount it with the fan where it should look (x_S the fan's centre; for a
// downward profile across the track, x_S down and y_S to port).
//   beam k (0 .. beams-1) points at phi_k = -fov/2 + (k + 1/2) fov / beams about z_S from x_S;
//   it is sampled by rays_per_beam rays at phi_k + beam_width ((j + 1/2) / rays_per_beam - 1/2) in the
//   same plane (j = 0 .. rays_per_beam-1), cast from S's origin into the world (its own vehicle is
//   transparent); the beam's range is the nearest of its rays' hits (the echo's leading edge),
//   plus white noise (channel "range", one draw per beam every scan, hit or not), quantised, reported
//   within [min_range, max_range]: -inf closer, +inf when no ray hits within max_range (REP 117).
// Asynchronous capture (sensors/sensor_kind.h): the rays are cast on the ray-cast workers from the
// snapshot at the scan's time, the scan is published latency_s later, stamped with the scan's time.
// The defaults describe a generic 120-degree, 256-beam profiler, not a data sheet.
// YAML keys: ProfilerSensor::keys() (server/src/sensors/profiler_sensor.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/profiler_spec.h"

namespace sensor_msgs::msg {
class LaserScan;
class LaserScanPubSubType;
}  // namespace sensor_msgs::msg

namespace hadal::geometry {
struct RayBatch;
struct RayHits;
}  // namespace hadal::geometry

namespace hadal::sensors {

struct ProfilerSensor {
  static constexpr std::string_view kType = "profiler";
  static constexpr bool kCastsRays = false;  // its rays go to the workers, not the stepping thread
  static constexpr bool kCaptures = true;
  using Message = sensor_msgs::msg::LaserScan;
  using PubSubType = sensor_msgs::msg::LaserScanPubSubType;

  using Spec = ProfilerSpec;
  struct State {
    NoiseChannelState noise;
    std::vector<double> ranges;  // the last scan, one per beam [m]
  };

  // Centre of beam k about z_S [rad], and the angle between neighbouring beams.
  static double beam_angle(const Spec& spec, int k);
  static double beam_spacing(const Spec& spec) { return spec.fov / spec.beams; }
  // The range channel at scan period `period` [s].
  static NoiseChannelParams channel(const Spec& spec, double period);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static geometry::RayBatch capture_rays(const CaptureContext& context, const Spec& spec);
  static void deliver(const SampleContext& context, const Spec& spec, State& state, const geometry::RayHits& hits);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

}  // namespace hadal::sensors
