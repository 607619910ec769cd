#include "hadal/sensors/gps_sensor.h"

#include "hadal/physics/ocean.h"

#include <sensor_msgs.h>
#include <sensor_msgsPubSubTypes.h>

#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/dds/time_msg.h"
#include "hadal/sensors/geodesy.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::Range;

NoiseTriadParams GpsSensor::position_noise(const Spec& spec, double period) {
  NoiseTriadParams triad;
  triad.axes[0].white_noise_density = spec.horizontal_stddev * std::sqrt(period);
  triad.axes[1].white_noise_density = spec.horizontal_stddev * std::sqrt(period);
  triad.axes[2].white_noise_density = spec.vertical_stddev * std::sqrt(period);
  return triad;
}

SensorReach GpsSensor::reach(const Spec& /*spec*/) { return {}; }

const config::KeyTable<GpsSensor::Spec, SensorReader>& GpsSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].gps", "a fix while the antenna is above the water surface");
    t.number("horizontal_stddev", &Spec::horizontal_stddev).unit("m").range(Range::non_negative())
        .doc("white noise per fix on each horizontal axis");
    t.number("vertical_stddev", &Spec::vertical_stddev).unit("m").range(Range::non_negative()).doc("on the vertical");
  });
}

GpsSensor::State GpsSensor::initial_state(const Spec& spec, const SensorSetup& setup) {
  State state;
  state.noise = make_noise_state(position_noise(spec, setup.period),
                                 channel_key(setup.seed, setup.vehicle, setup.sensor, "position"));
  return state;
}

void GpsSensor::sample(const SampleContext& context, const Spec& spec, State& state) {
  const Eigen::Vector3d p_WS = context.p_WS();
  // The noise streams advance with or without a fix, so dives do not shift later fixes.
  const Eigen::Vector3d p_meas = measure(position_noise(spec, context.period), state.noise, p_WS, context.period);
  state.fix = p_WS.z() > context.ocean.surface_height(p_WS.x(), p_WS.y(), context.time);  // awash: no fix
  if (state.fix) {
    const GeodeticPosition fix = context.environment.frame_W().to_geodetic(p_meas);
    state.latitude_deg = to_degrees(fix.latitude_rad);
    state.longitude_deg = to_degrees(fix.longitude_rad);
    state.height_m = fix.height_m;
  } else {
    state.latitude_deg = state.longitude_deg = state.height_m = std::numeric_limits<double>::quiet_NaN();
  }
}

void GpsSensor::fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.status().status(state.fix ? sensor_msgs::msg::NavSatStatus_Constants::STATUS_FIX
                                : sensor_msgs::msg::NavSatStatus_Constants::STATUS_NO_FIX);
  msg.status().service(sensor_msgs::msg::NavSatStatus_Constants::SERVICE_GPS);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  msg.latitude(state.fix ? state.latitude_deg : nan);
  msg.longitude(state.fix ? state.longitude_deg : nan);
  msg.altitude(state.fix ? state.height_m : nan);
  const double h2 = spec.horizontal_stddev * spec.horizontal_stddev;
  const double v2 = spec.vertical_stddev * spec.vertical_stddev;
  msg.position_covariance({h2, 0, 0, 0, h2, 0, 0, 0, v2});
  msg.position_covariance_type(sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_DIAGONAL_KNOWN);
}

}  // namespace hadal::sensors
