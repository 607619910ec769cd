#include "hadal/sensors/profiler_sensor.h"

#include <sensor_msgs.h>
#include <sensor_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "hadal/config/key_table.h"
#include "hadal/sensors/range_keys.h"
#include "hadal/dds/time_msg.h"
#include "hadal/geometry/ray_batch.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::Range;

double ProfilerSensor::beam_angle(const Spec& spec, int k) {
  return -0.5 * spec.fov + (k + 0.5) * beam_spacing(spec);
}

NoiseChannelParams ProfilerSensor::channel(const Spec& spec, double period) {
  return per_sample_white_noise(spec.noise_stddev, period, spec.resolution, spec.min_range, spec.max_range);
}

SensorReach ProfilerSensor::reach(const Spec& spec) { return {spec.max_range, 0.5 * spec.fov}; }

const config::KeyTable<ProfilerSensor::Spec, SensorReader>& ProfilerSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].profiler", "a fan of beams in S's x-y plane, one range each");
    t.number("beams", &Spec::beams).range(Range::closed(1.0, 4096.0)).doc("beams across the fan");
    t.number("rays_per_beam", &Spec::rays_per_beam).range(Range::closed(1.0, 64.0)).doc("rays across each beam");
    t.number("fov_deg", &Spec::fov).degrees().range(Range::left_open(0.0, 360.0)).doc("the whole fan");
    t.number("beam_width_deg", &Spec::beam_width).degrees().range(Range::left_open(0.0, 30.0)).doc("in the fan's plane");
    declare_range_keys(t);
  });
}

ProfilerSensor::State ProfilerSensor::initial_state(const Spec& spec, const SensorSetup& setup) {
  State state;
  state.noise = make_noise_state(channel(spec, setup.period),
                                 channel_key(setup.seed, setup.vehicle, setup.sensor, "range"));
  state.ranges.assign(static_cast<std::size_t>(spec.beams), std::numeric_limits<double>::infinity());
  return state;
}

geometry::RayBatch ProfilerSensor::capture_rays(const CaptureContext& context, const Spec& spec) {
  const Eigen::Isometry3d X_WS = context.X_WS();
  geometry::RayBatch batch;
  batch.sim_time = context.time;
  batch.step_count = context.step_count;
  batch.X_WB = context.X_WB;
  batch.coherence = geometry::RayCoherence::kCoherent;  // one origin, neighbouring directions
  batch.reserve(static_cast<std::size_t>(spec.beams) * static_cast<std::size_t>(spec.rays_per_beam));
  const Eigen::Vector3f p_WS = X_WS.translation().cast<float>();
  const float t_far = static_cast<float>(1.01 * spec.max_range);
  for (int k = 0; k < spec.beams; ++k) {
    for (int j = 0; j < spec.rays_per_beam; ++j) {
      const double phi = beam_angle(spec, k) + spec.beam_width * ((j + 0.5) / spec.rays_per_beam - 0.5);
      const Eigen::Vector3d d_W = X_WS.linear() * Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0);
      batch.add_ray(p_WS, d_W.normalized().cast<float>(), 0.0f, t_far,
                    static_cast<std::int32_t>(context.own_ray_body()));
    }
  }
  return batch;
}

void ProfilerSensor::deliver(const SampleContext& context, const Spec& spec, State& state,
                             const geometry::RayHits& hits) {
  const NoiseChannelParams range_channel = channel(spec, context.period);
  state.ranges.resize(static_cast<std::size_t>(spec.beams));
  for (int k = 0; k < spec.beams; ++k) {
    float nearest = std::numeric_limits<float>::infinity();
    for (int j = 0; j < spec.rays_per_beam; ++j) {
      nearest = std::min(nearest, hits.distance[static_cast<std::size_t>(k * spec.rays_per_beam + j)]);
    }
    const double range = nearest;
    // The noise stream advances for every beam, hit or not.
    const double measured =
        measure(range_channel, state.noise, std::isfinite(range) ? range : 0.0, context.period);
    double& out = state.ranges[static_cast<std::size_t>(k)];
    if (range < spec.min_range) {
      out = -std::numeric_limits<double>::infinity();
    } else if (!(range <= spec.max_range)) {
      out = std::numeric_limits<double>::infinity();
    } else {
      out = measured;
    }
  }
}

void ProfilerSensor::fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.angle_min(static_cast<float>(beam_angle(spec, 0)));
  msg.angle_max(static_cast<float>(beam_angle(spec, spec.beams - 1)));
  msg.angle_increment(static_cast<float>(beam_spacing(spec)));
  msg.time_increment(0.0f);  // every beam of a scan at once
  msg.scan_time(static_cast<float>(1.0 / header.rate_hz));
  msg.range_min(static_cast<float>(spec.min_range));
  msg.range_max(static_cast<float>(spec.max_range));
  msg.ranges().resize(state.ranges.size());
  for (std::size_t k = 0; k < state.ranges.size(); ++k) msg.ranges()[k] = static_cast<float>(state.ranges[k]);
  msg.intensities().clear();
}

}  // namespace hadal::sensors
