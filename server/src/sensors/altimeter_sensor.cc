#include "hadal/sensors/altimeter_sensor.h"

#include <sensor_msgs.h>
#include <sensor_msgsPubSubTypes.h>

#include <cmath>
#include <limits>

#include "hadal/config/key_table.h"
#include "hadal/sensors/range_keys.h"
#include "hadal/dds/time_msg.h"
#include "hadal/geometry/scene_rays.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::Range;

NoiseChannelParams AltimeterSensor::channel(const Spec& spec, double period) {
  return per_sample_white_noise(spec.noise_stddev, period, spec.resolution, spec.min_range, spec.max_range);
}

SensorReach AltimeterSensor::reach(const Spec& spec) { return {spec.max_range, 0.5 * spec.field_of_view}; }

const config::KeyTable<AltimeterSensor::Spec, SensorReader>& AltimeterSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].altimeter", "one beam along x of S: the range to the first hit");
    declare_range_keys(t);
    t.number("field_of_view_deg", &Spec::field_of_view).degrees().range(Range::left_open(0.0, 180.0))
        .doc("full beam width, reported only");
  });
}

AltimeterSensor::State AltimeterSensor::initial_state(const Spec& spec, const SensorSetup& setup) {
  State state;
  state.noise = make_noise_state(channel(spec, setup.period),
                                 channel_key(setup.seed, setup.vehicle, setup.sensor, "range"));
  return state;
}

void AltimeterSensor::sample(const SampleContext& context, const Spec& spec, State& state) {
  const Eigen::Isometry3d& X_WB = context.body().X_WB;
  const Eigen::Vector3d x_W = X_WB.linear() * context.X_BS.linear().col(0);
  const double range = context.rays->cast(context.state, context.p_WS(), std::array<Eigen::Vector3d, 1>{x_W},
                                          context.own_ray_body(), 1.01 * spec.max_range)[0];
  // The noise stream advances every sample, in the window or not.
  const double measured =
      measure(channel(spec, context.period), state.noise, std::isfinite(range) ? range : 0.0, context.period);
  if (range < spec.min_range) {
    state.range = -std::numeric_limits<double>::infinity();
  } else if (!(range <= spec.max_range)) {
    state.range = std::numeric_limits<double>::infinity();
  } else {
    state.range = measured;
  }
}

void AltimeterSensor::fill_message(const Spec& spec, const State& state, const MessageHeader& header,
                                   Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.radiation_type(sensor_msgs::msg::Range_Constants::ULTRASOUND);
  msg.field_of_view(static_cast<float>(spec.field_of_view));
  msg.min_range(static_cast<float>(spec.min_range));
  msg.max_range(static_cast<float>(spec.max_range));
  msg.range(static_cast<float>(state.range));
}

}  // namespace hadal::sensors
