#include "hadal/sensors/dvl_sensor.h"

#include <marine_acoustic_msgs.h>
#include <marine_acoustic_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/dds/time_msg.h"
#include "hadal/geometry/scene_rays.h"
#include "hadal/physics/ocean.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::format_number;
using config::join_names;
using namespace config::keys;
using config::Need;
using config::quoted;

double DvlSensor::ray_length(const Spec& spec) {
  const DvlParams& params = spec.params;
  return 1.01 * std::max(params.max_altitude, params.water_track_layer_far) / std::cos(params.beam_tilt);
}

namespace {

// The generic DVL: the DvlParams defaults with 5 mm/s per beam per ping.
DvlDatasheet generic_dvl() {
  const DvlParams defaults;
  DvlDatasheet sheet;
  sheet.beam_tilt_deg = to_degrees(defaults.beam_tilt);
  sheet.min_altitude_m = defaults.min_altitude;
  sheet.max_altitude_m = defaults.max_altitude;
  sheet.beam_velocity_sigma = 0.005;
  return sheet;
}

const config::KeyTable<DvlBiasParams>& dvl_bias_keys() {
  return config::declare_keys<DvlBiasParams>([](config::KeyTable<DvlBiasParams>& t) {
    t.describe("sensors[].dvl.bias", "the paper's slowly varying bias b(t + dt) = b(t) + xi dt");
    t.vector("initial", &DvlBiasParams::initial).unit("m/s").doc("b(0), S axes");
    t.number("initial_stddev", &DvlBiasParams::initial_sigma).unit("m/s").range(Range::non_negative())
        .doc("plus a draw per axis at turn-on");
    t.vector("drift_rate", &DvlBiasParams::drift_rate).unit("m/s²").doc("xi");
    t.number("drift_rate_stddev", &DvlBiasParams::drift_rate_sigma).unit("m/s²").range(Range::non_negative())
        .doc("plus a draw per axis at turn-on");
    t.number("random_walk", &DvlBiasParams::random_walk_density).unit("m/s/√s").range(Range::non_negative())
        .doc("K of the bias's random walk");
  });
}

// A per-ping sigma [m/s or m] as a white-noise density at the sensor's sample period (dvl_params).
std::function<void(DvlSensor::Spec&, double, SensorReader&)> per_ping(NoiseChannelParams DvlParams::*channel) {
  return [channel](DvlSensor::Spec& spec, double sigma, SensorReader& reader) {
    (spec.params.*channel).noise.white_noise_density = sigma * std::sqrt(1.0 / reader.rate_hz);
  };
}

}  // namespace

// A data-sheet preset (it also sets rate_hz unless given) and/or geometry, bottom-lock window, noise per
// ping, the paper's bias drift, water track and sound-speed error. Per-ping sigmas become white-noise
// densities at the sensor's sample period (dvl_params).
SensorReach DvlSensor::reach(const Spec& spec) { return {spec.params.max_altitude / std::cos(spec.params.beam_tilt), spec.params.beam_tilt}; }

const config::KeyTable<DvlSensor::Spec, SensorReader>& DvlSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].dvl", "four Janus beams: bottom and water track");
    t.before([](Spec& spec, SensorReader& reader) { spec.params = dvl_params(generic_dvl(), 1.0 / reader.rate_hz); });
    t.preset("DVL", dvl_presets(), [](Spec& spec, const config::Preset<DvlDatasheet>& p, SensorReader& reader) {
       if (!reader.rate_given) reader.rate_hz = p.figures.update_hz;
       spec.params = dvl_params(p.figures, 1.0 / reader.rate_hz);
     }).doc("a product (table below); sets rate_hz unless given");
    t.number("beam_tilt_deg", [](Spec& s) -> double& { return s.params.beam_tilt; }).degrees()
        .range(Range::closed(1.0, 60.0)).doc("theta, the beams' angle from the axis");
    t.number("first_beam_azimuth_deg", [](Spec& s) -> double& { return s.params.first_beam_azimuth; }).degrees()
        .range(Range::closed(-360.0, 360.0)).doc("phi_1 about z_S; beam i at phi_1 + (i - 1) 90°");
    t.number("min_altitude", [](Spec& s) -> double& { return s.params.min_altitude; }).unit("m")
        .range(Range::non_negative()).doc("bottom-lock window along the axis");
    t.number("max_altitude", [](Spec& s) -> double& { return s.params.max_altitude; }).unit("m")
        .range(Range::positive()).rule("> min_altitude").doc("bottom-lock window along the axis");
    t.number("dropout_probability", [](Spec& s) -> double& { return s.params.dropout_probability; })
        .range(Range::closed(0.0, 1.0)).doc("per beam per ping");
    t.number("assumed_sound_speed", [](Spec& s) -> double& { return s.params.assumed_sound_speed; }).unit("m/s")
        .range(Range::non_negative()).rule("0 (measured) or in [1300, 1700]")
        .doc("the sound speed the DVL assumes; velocities scale by it over the true one");
    t.boolean("water_track", [](Spec& s) -> bool& { return s.params.water_track; })
        .doc("water-track mode without bottom lock");
    t.number("water_track_layer_near", [](Spec& s) -> double& { return s.params.water_track_layer_near; }).unit("m")
        .range(Range::non_negative()).doc("the water-track layer along the axis");
    t.number("water_track_layer_far", [](Spec& s) -> double& { return s.params.water_track_layer_far; }).unit("m")
        .range(Range::positive()).rule("> water_track_layer_near").doc("the water-track layer along the axis");
    t.number("water_track_layer_samples", &Spec::water_track_layer_samples).range(Range::closed(1.0, 64.0))
        .doc("current samples per beam across the layer");
    t.number_into("beam_velocity_noise_stddev", per_ping(&DvlParams::beam_velocity_noise), nullptr).unit("m/s")
        .range(Range::non_negative()).default_text("the preset's, else 0.005").doc("per beam per ping, bottom track");
    t.number_into("water_track_noise_stddev", per_ping(&DvlParams::water_track_velocity_noise), nullptr).unit("m/s")
        .range(Range::non_negative()).default_text("the preset's").doc("per beam per ping, water track");
    t.number_into("range_noise_stddev", per_ping(&DvlParams::range_noise), nullptr).unit("m")
        .range(Range::non_negative()).default_text("0").doc("per beam per ping, slant range");
    t.number_into(
         "velocity_resolution",
         [](Spec& s, double lsb, SensorReader&) {
           s.params.beam_velocity_noise.lsb = s.params.water_track_velocity_noise.lsb = lsb;
         },
         [](Spec&) { return 0.0; })
        .unit("m/s").range(Range::non_negative()).doc("quantisation of beam velocities; 0: none");
    t.map("bias", [](Spec& s) -> DvlBiasParams& { return s.params.bias; }, dvl_bias_keys()).doc("the bias drift");
    t.check([](const config::KeyReads& reads, Spec& spec, SensorReader&) {
      const DvlParams& p = spec.params;
      bool ok = true;
      if (reads.ok("min_altitude") && reads.ok("max_altitude") && !(p.max_altitude > p.min_altitude)) {
        reads.error_at_key(reads.has("max_altitude") ? "max_altitude" : "min_altitude",
                           "max_altitude (" + format_number(p.max_altitude) + " m) must exceed min_altitude (" +
                               format_number(p.min_altitude) + " m)");
        ok = false;
      }
      if (p.assumed_sound_speed > 0.0 && !(p.assumed_sound_speed >= 1300.0 && p.assumed_sound_speed <= 1700.0)) {
        reads.error_at_key("assumed_sound_speed", "assumed_sound_speed must be 0 (measured) or in [1300, 1700] m/s, got " +
                                                      format_number(p.assumed_sound_speed));
        ok = false;
      }
      if (reads.ok("water_track_layer_near") && reads.ok("water_track_layer_far") &&
          !(p.water_track_layer_far > p.water_track_layer_near)) {
        reads.error_at_key(reads.has("water_track_layer_far") ? "water_track_layer_far" : "water_track_layer_near",
                           "the water-track layer must have near < far (got " + format_number(p.water_track_layer_near) +
                               " m to " + format_number(p.water_track_layer_far) + " m)");
        ok = false;
      }
      return ok;
    });
  });
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
  input.slant_range = context.rays->cast(context.state, p_WS, beams_W, context.own_ray_body(), ray_length(spec));
  // The sea surface reflects too (its tangent plane over the transducer, tilted by waves): a beam that rises to it
  // before it meets anything else within reach returns from it (an upward-looking DVL tracks the surface).
  for (int b = 0; b < kDvlBeams; ++b) {
    const double to_surface = context.ocean.range_to_surface(p_WS, beams_W[b], context.time);
    if (to_surface <= ray_length(spec) && !(input.slant_range[b] <= to_surface)) input.slant_range[b] = to_surface;
  }
  if (params.water_track) {
    const int n = spec.water_track_layer_samples;
    for (int b = 0; b < kDvlBeams; ++b) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int j = 0; j < n; ++j) {
        const Eigen::Vector3d p_S = water_track_layer_point(params, beams_S[b], j, n);
        // The water's velocity there: the current and, under the surface, the waves' orbital motion.
        const Eigen::Vector3d p_W = p_WS + R_WS * p_S;
        sum += context.ocean.current_W(p_W, context.time);
        if (context.ocean.waves().enabled()) sum += context.ocean.waves().velocity_W(p_W, context.time);
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
