#include "hadal/sensors/pressure_sensor.h"

#include <sensor_msgs.h>
#include <sensor_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/dds/time_msg.h"
#include "hadal/physics/ocean.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::Range;

NoiseChannelParams PressureSensor::channel(const Spec& spec, double period) {
  NoiseChannelParams params = per_sample_white_noise(spec.noise_stddev, period, spec.resolution, 0.0, spec.range_pa);
  params.noise.turn_on_bias = spec.offset;
  return params;
}

SensorReach PressureSensor::reach(const Spec& /*spec*/) { return {}; }

const config::KeyTable<PressureSensor::Spec, SensorReader>& PressureSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].pressure", "absolute pressure at the sensor's origin");
    t.number("noise_stddev", &Spec::noise_stddev).unit("Pa").range(Range::non_negative()).doc("white noise per sample");
    t.number("resolution", &Spec::resolution).unit("Pa").range(Range::non_negative()).doc("quantisation step; 0: none");
    t.number("range_pa", &Spec::range_pa).unit("Pa").range(Range::positive())
        .doc("full scale (absolute); readings clip to [0, range_pa]");
    t.renamed("range_max", "range_pa", "a channel's full scale is range_<unit>, as range_g and range_ut");
    t.number("offset", &Spec::offset).unit("Pa").doc("a zero offset added to every reading (a transducer zeroed in air)");
  });
}

PressureSensor::State PressureSensor::initial_state(const Spec& spec, const SensorSetup& setup) {
  State state;
  state.noise = make_noise_state(channel(spec, setup.period),
                                 channel_key(setup.seed, setup.vehicle, setup.sensor, "pressure"));
  return state;
}

void PressureSensor::sample(const SampleContext& context, const Spec& spec, State& state) {
  const double ideal = context.ocean.pressure_at(context.p_WS(), context.time);  // the waves' dynamic pressure too
  state.pressure = measure(channel(spec, context.period), state.noise, ideal, context.period);
}

void PressureSensor::fill_message(const Spec& spec, const State& state, const MessageHeader& header,
                                  Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.fluid_pressure(state.pressure);
  msg.variance(spec.noise_stddev * spec.noise_stddev + spec.resolution * spec.resolution / 12.0);
}

}  // namespace hadal::sensors
