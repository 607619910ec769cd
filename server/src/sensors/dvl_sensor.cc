#include "hadal/sensors/dvl_sensor.h"

#include <marine_acoustic_msgs.h>
#include <marine_acoustic_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>

#include "hadal/config/yaml_reader.h"
#include "hadal/dds/time_msg.h"
#include "hadal/geometry/scene_rays.h"
#include "hadal/physics/ocean.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::format_number;
using config::join_names;
using config::MapReader;
using config::Need;
using config::quoted;
using config::Range;

double DvlSensor::ray_length(const Spec& spec) {
  const DvlParams& params = spec.params;
  return 1.01 * std::max(params.max_altitude, params.water_track_layer_far) / std::cos(params.beam_tilt);
}

const std::vector<std::string>& DvlSensor::keys() {
  static const std::vector<std::string> keys = {
      "preset", "beam_tilt_deg", "first_beam_azimuth_deg", "min_altitude", "max_altitude", "dropout_probability",
      "assumed_sound_speed", "water_track", "water_track_layer_near", "water_track_layer_far",
      "water_track_layer_samples", "beam_velocity_noise_stddev", "water_track_noise_stddev", "range_noise_stddev",
      "velocity_resolution", "bias"};
  return keys;
}

// A data-sheet preset (it also sets rate_hz unless given) and/or geometry, bottom-lock window, noise per
// ping, the paper's bias drift, water track and sound-speed error. Per-ping sigmas become white-noise
// densities at the sensor's sample period (dvl_params).
DvlSensor::Spec DvlSensor::read(const SensorReader& reader) {
  const MapReader& map = reader.map;
  Spec spec;
  const DvlParams defaults;
  DvlDatasheet sheet;  // generic: the DvlParams defaults with 5 mm/s per beam
  sheet.id = "generic";
  sheet.beam_tilt_deg = defaults.beam_tilt / kDegToRad;
  sheet.min_altitude_m = defaults.min_altitude;
  sheet.max_altitude_m = defaults.max_altitude;
  sheet.beam_velocity_sigma = 0.005;
  if (const auto preset = map.optional("preset")) {
    if (const auto id = preset->string()) {
      if (const DvlDatasheet* found = find_dvl_preset(*id)) {
        sheet = *found;
        if (!reader.rate_given) reader.rate_hz = sheet.update_hz;
      } else {
        std::vector<std::string> ids;
        for (const auto& p : dvl_presets()) ids.push_back(quoted(std::string(p.id)));
        preset->error("unknown DVL preset " + quoted(*id) + " (presets: " + join_names(ids) + ")");
      }
    }
  }
  const double period = 1.0 / reader.rate_hz;
  DvlParams& p = spec.params;
  p = dvl_params(sheet, period);
  double tilt_deg = p.beam_tilt / kDegToRad, azimuth_deg = p.first_beam_azimuth / kDegToRad;
  if (map.read_number("beam_tilt_deg", Need::kOptional, Range::closed(1.0, 60.0), &tilt_deg)) {
    p.beam_tilt = tilt_deg * kDegToRad;
  }
  if (map.read_number("first_beam_azimuth_deg", Need::kOptional, Range::closed(-360.0, 360.0), &azimuth_deg)) {
    p.first_beam_azimuth = azimuth_deg * kDegToRad;
  }
  if (map.read_number("min_altitude", Need::kOptional, Range::non_negative(), &p.min_altitude) &
          map.read_number("max_altitude", Need::kOptional, Range::positive(), &p.max_altitude) &&
      !(p.max_altitude > p.min_altitude)) {
    map.error_at_key(map.has("max_altitude") ? "max_altitude" : "min_altitude",
                     "max_altitude (" + format_number(p.max_altitude) + " m) must exceed min_altitude (" +
                         format_number(p.min_altitude) + " m)");
  }
  map.read_number("dropout_probability", Need::kOptional, Range::closed(0.0, 1.0), &p.dropout_probability);
  map.read_number("assumed_sound_speed", Need::kOptional, Range::non_negative(), &p.assumed_sound_speed);
  if (p.assumed_sound_speed > 0.0 && !(p.assumed_sound_speed >= 1300.0 && p.assumed_sound_speed <= 1700.0)) {
    map.error_at_key("assumed_sound_speed", "assumed_sound_speed must be 0 (measured) or in [1300, 1700] m/s, got " +
                                                format_number(p.assumed_sound_speed));
  }
  map.read_bool("water_track", Need::kOptional, &p.water_track);
  if (map.read_number("water_track_layer_near", Need::kOptional, Range::non_negative(), &p.water_track_layer_near) &
          map.read_number("water_track_layer_far", Need::kOptional, Range::positive(), &p.water_track_layer_far) &&
      !(p.water_track_layer_far > p.water_track_layer_near)) {
    map.error_at_key(map.has("water_track_layer_far") ? "water_track_layer_far" : "water_track_layer_near",
                     "the water-track layer must have near < far (got " + format_number(p.water_track_layer_near) +
                         " m to " + format_number(p.water_track_layer_far) + " m)");
  }
  const auto per_ping = [&](const char* key, NoiseChannelParams* channel) {
    double sigma = 0.0;
    if (map.read_number(key, Need::kOptional, Range::non_negative(), &sigma) && map.has(key)) {
      channel->noise.white_noise_density = sigma * std::sqrt(period);
    }
  };
  per_ping("beam_velocity_noise_stddev", &p.beam_velocity_noise);
  per_ping("water_track_noise_stddev", &p.water_track_velocity_noise);
  per_ping("range_noise_stddev", &p.range_noise);
  double lsb = 0.0;
  if (map.read_number("velocity_resolution", Need::kOptional, Range::non_negative(), &lsb)) {
    p.beam_velocity_noise.lsb = p.water_track_velocity_noise.lsb = lsb;
  }
  if (const auto bias_value = map.optional("bias")) {
    const MapReader bias(*bias_value, {"initial", "initial_stddev", "drift_rate", "drift_rate_stddev", "random_walk"});
    if (bias.ok()) {
      bias.read_vector3("initial", Need::kOptional, Range::finite(), &p.bias.initial);
      bias.read_number("initial_stddev", Need::kOptional, Range::non_negative(), &p.bias.initial_sigma);
      bias.read_vector3("drift_rate", Need::kOptional, Range::finite(), &p.bias.drift_rate);
      bias.read_number("drift_rate_stddev", Need::kOptional, Range::non_negative(), &p.bias.drift_rate_sigma);
      bias.read_number("random_walk", Need::kOptional, Range::non_negative(), &p.bias.random_walk_density);
    }
  }
  double samples = spec.water_track_layer_samples;
  if (map.read_number("water_track_layer_samples", Need::kOptional, Range::closed(1.0, 64.0), &samples)) {
    spec.water_track_layer_samples = static_cast<int>(samples);
  }
  return spec;
}

DvlSensor::State DvlSensor::initial_state(const Spec& spec, const SensorSetup& setup) {
  State state;
  state.dvl = make_dvl_state(spec.params, setup.seed, setup.vehicle, setup.sensor);
  return state;
}

void DvlSensor::sample(const SampleContext& context, const Spec& spec, State& state) {
  const DvlParams& params = spec.params;
  const RigidBodyState& body = context.body();
  const Eigen::Matrix3d R_WS = context.R_WS();
  const Eigen::Matrix3d R_SW = R_WS.transpose();
  const Eigen::Vector3d p_WS = context.p_WS();
  DvlPingInput input;
  // The transducer's velocity over the seabed (lever arm included), in S.
  input.v_WS_S = R_SW * (body.v_WB + body.w_WB.cross(p_WS - body.X_WB.translation()));
  const std::array<Eigen::Vector3d, kDvlBeams> beams_S = dvl_beam_unit_vectors(params);
  std::array<Eigen::Vector3d, kDvlBeams> beams_W;
  for (int b = 0; b < kDvlBeams; ++b) beams_W[b] = R_WS * beams_S[b];
  input.slant_range = context.rays->cast(context.state, p_WS, beams_W, context.vehicle_index, ray_length(spec));
  if (params.water_track) {
    const int n = spec.water_track_layer_samples;
    for (int b = 0; b < kDvlBeams; ++b) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int j = 0; j < n; ++j) {
        const Eigen::Vector3d p_S = water_track_layer_point(params, beams_S[b], j, n);
        sum += context.ocean.current_W(p_WS + R_WS * p_S, context.time);
      }
      input.v_water_S[b] = R_SW * sum / static_cast<double>(n);
    }
  }
  input.sound_speed = context.ocean.sound_speed(std::max(context.ocean.depth(p_WS.z()), 0.0));
  input.dt = context.period;
  state.ping = dvl_ping(params, state.dvl, input);
}

void DvlSensor::fill_message(const Spec&, const State& state, const MessageHeader& header, Message& msg) {
  namespace C = marine_acoustic_msgs::msg::Dvl_Constants;
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  const DvlPing& ping = state.ping;
  switch (ping.mode) {
    case DvlMode::kNone: msg.velocity_mode(0); break;
    case DvlMode::kBottomTrack: msg.velocity_mode(C::DVL_MODE_BOTTOM); break;
    case DvlMode::kWaterTrack: msg.velocity_mode(C::DVL_MODE_WATER); break;
  }
  msg.dvl_type(ping.type == DvlType::kPhasedArray ? C::DVL_TYPE_PHASED_ARRAY : C::DVL_TYPE_PISTON);
  msg.velocity().x(ping.velocity.x());
  msg.velocity().y(ping.velocity.y());
  msg.velocity().z(ping.velocity.z());
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      msg.velocity_covar()[static_cast<std::size_t>(3 * r + c)] = ping.velocity_covariance(r, c);
    }
  }
  msg.altitude(ping.altitude);
  msg.course_gnd(ping.course_gnd);
  msg.speed_gnd(ping.speed_gnd);
  msg.num_good_beams(static_cast<std::uint8_t>(ping.num_good_beams));
  msg.sound_speed(static_cast<float>(ping.sound_speed));
  msg.beam_ranges_valid(ping.beam_ranges_valid);
  msg.beam_velocities_valid(ping.beam_velocities_valid);
  for (std::size_t b = 0; b < static_cast<std::size_t>(kDvlBeams); ++b) {
    msg.beam_unit_vec()[b].x(ping.beam_unit_vec[b].x());
    msg.beam_unit_vec()[b].y(ping.beam_unit_vec[b].y());
    msg.beam_unit_vec()[b].z(ping.beam_unit_vec[b].z());
    msg.range()[b] = ping.range[b];
    msg.range_covar()[b] = static_cast<float>(ping.range_covar[b]);
    msg.beam_quality()[b] = static_cast<float>(ping.beam_quality[b]);
    msg.beam_velocity()[b] = static_cast<float>(ping.beam_velocity[b]);
    msg.beam_velocity_covar()[b] = static_cast<float>(ping.beam_velocity_covar[b]);
  }
}

}  // namespace hadal::sensors
