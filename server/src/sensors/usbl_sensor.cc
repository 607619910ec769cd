#include "hadal/sensors/usbl_sensor.h"

#include <hadal_msgs.h>
#include <hadal_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/render/responder_keys.h"
#include "hadal/dds/time_msg.h"
#include "hadal/sensors/acoustic_channel.h"
#include "hadal/sensors/geodesy.h"
#include "hadal/sensors/interrogator_keys.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::Range;

const config::KeyTable<TransponderSpec>& transponder_keys() {
  return config::declare_keys<TransponderSpec>([](config::KeyTable<TransponderSpec>& t) {
    t.describe("transponder", "an acoustic transponder on the vehicle, which USBLs interrogate");
    t.vector("position", &TransponderSpec::p_BT).unit("m").doc("its position in B");
    render::declare_responder_keys(t, "USBL");
  });
}

const config::KeyTable<UsblSensor::Spec, SensorReader>& UsblSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].usbl",
               "an ultra-short baseline transceiver: interrogates every other vehicle's transponder at rate_hz and "
               "fixes each reply's range and direction in S");
    declare_interrogator_keys(t);
    t.number("cone_deg", &Spec::cone_half_angle).degrees().range(Range::left_open(0.0, 180.0))
        .doc("half angle of the coverage about -z_S (90: the hemisphere below a transceiver mounted as B)");
    t.number("bearing_stddev_deg", &Spec::bearing_stddev).degrees().range(Range::closed(0.0, 45.0))
        .doc("direction error per axis across the direction, at and above reference_snr_db");
  });
}

SensorReach UsblSensor::reach(const Spec& spec) { return {spec.max_range, spec.cone_half_angle}; }

UsblSensor::State UsblSensor::initial_state(const Spec&, const SensorSetup& setup) {
  State state;
  state.range_noise = RandomStream(channel_key(setup.seed, setup.vehicle, setup.sensor, "range"));
  state.bearing_noise = RandomStream(channel_key(setup.seed, setup.vehicle, setup.sensor, "bearing"));
  return state;
}

namespace {

// Every vehicle's transponder as a responder (none for the sensor's own vehicle).
std::vector<Responder> transponders(const SampleContext& context) {
  std::vector<Responder> out(context.vehicles->size());
  for (std::size_t v = 0; v < out.size(); ++v) {
    const std::optional<TransponderSpec>& transponder = (*context.vehicles)[v].transponder;
    if (!transponder || static_cast<int>(v) == context.vehicle_index) continue;
    Responder& r = out[v];
    r.present = true;
    r.p_W = context.state.vehicles[v].body.X_WB * transponder->p_BT;
    r.ray_body = static_cast<int>(v);
    r.source_level_db = transponder->source_level_db;
    r.detection_threshold_db = transponder->detection_threshold_db;
    r.turnaround_s = transponder->turnaround_s;
  }
  return out;
}

}  // namespace

void UsblSensor::sample(const SampleContext& context, const Spec&, State& state) {
  if (context.vehicles == nullptr) return;
  interrogate(state.interrogation, context.time, context.p_WS(), transponders(context));
}

std::optional<double> UsblSensor::advance(const SampleContext& context, const Spec& spec, State& state) {
  if (context.vehicles == nullptr) return std::nullopt;
  const AcousticChannel& channel = context.environment.acoustic_channel(context.ocean, context.world.acoustics);
  const std::vector<ReceivedReply> replies =
      advance_interrogations(state.interrogation, channel, interrogator_acoustics(spec), context.time, context.p_WS(),
                             transponders(context), occlusion_of(context));
  bool any = false;
  const Eigen::Matrix3d R_WS = context.R_WS();
  for (const ReceivedReply& reply : replies) {
    const Eigen::Vector3d d_W = reply.p_Wreply - reply.p_Wreceived;
    const Eigen::Vector3d u_S = R_WS.transpose() * d_W / std::max(d_W.norm(), 1e-9);
    const double off_axis = std::acos(std::clamp(-u_S.z(), -1.0, 1.0));
    if (off_axis > spec.cone_half_angle) continue;
    if (!any) state.fixes.clear();
    any = true;
    UsblFix& fix = state.fixes.emplace_back();
    fix.stamp = reply.reception_time;
    fix.interrogation_time = reply.interrogation_time;
    fix.interrogation = reply.interrogation;
    fix.target = reply.responder;
    fix.target_name = (*context.vehicles)[static_cast<std::size_t>(reply.responder)].name;
    fix.snr_db = reply.snr_db;
    fix.travel_time = reply.travel_time;
    const double scale = error_scale(spec, reply.snr_db);
    const double sigma_r = spec.range_stddev * scale;
    const double sigma_b = spec.bearing_stddev * scale;
    fix.range = reply.range + sigma_r * state.range_noise.normal();
    const Eigen::Vector3d axis = std::abs(u_S.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d e1 = u_S.cross(axis).normalized();
    const Eigen::Vector3d e2 = u_S.cross(e1);
    const double a1 = sigma_b * state.bearing_noise.normal();
    const double a2 = sigma_b * state.bearing_noise.normal();
    const Eigen::Vector3d u_measured = (u_S + std::tan(a1) * e1 + std::tan(a2) * e2).normalized();
    fix.p_S = fix.range * u_measured;
    fix.bearing = std::atan2(fix.p_S.y(), fix.p_S.x());
    fix.elevation = std::asin(std::clamp(u_measured.z(), -1.0, 1.0));
    const Eigen::Matrix3d along = u_measured * u_measured.transpose();
    fix.covariance_S = sigma_r * sigma_r * along +
                       (fix.range * sigma_b) * (fix.range * sigma_b) * (Eigen::Matrix3d::Identity() - along);
    fix.p_W = reply.p_Wreceived + R_WS * fix.p_S;
    const GeodeticPosition geo = context.environment.frame_W().to_geodetic(fix.p_W);
    fix.latitude_deg = geo.latitude_rad / kDegToRad;
    fix.longitude_deg = geo.longitude_rad / kDegToRad;
    fix.height = geo.height_m;
  }
  if (!any) return std::nullopt;
  return state.fixes.back().stamp;
}

void UsblSensor::acoustic_links(const SampleContext& context, const Spec&, const State& state,
                              std::vector<AcousticLink>& out) {
  if (context.vehicles == nullptr || context.sensor == nullptr) return;
  std::vector<std::string> names;
  for (const VehicleSpec& vehicle : *context.vehicles) names.push_back(vehicle.name);
  const std::string self = (context.vehicles ? (*context.vehicles)[static_cast<std::size_t>(context.vehicle_index)].name
                                             : std::string("vehicle")) + "/" + context.sensor->name;
  interrogation_links(state.interrogation, context.p_WS(), self, transponders(context), names, out);
}

void UsblSensor::fill_message(const Spec&, const State& state, const MessageHeader& header, Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.fixes().clear();
  for (const UsblFix& fix : state.fixes) {
    hadal_msgs::msg::UsblFix& out = msg.fixes().emplace_back();
    out.stamp(dds::to_time_msg(fix.stamp));
    out.interrogation_stamp(dds::to_time_msg(fix.interrogation_time));
    out.target(fix.target_name);
    out.interrogation(fix.interrogation);
    out.travel_time(fix.travel_time);
    out.range(fix.range);
    out.bearing(fix.bearing);
    out.elevation(fix.elevation);
    out.position().x(fix.p_S.x());
    out.position().y(fix.p_S.y());
    out.position().z(fix.p_S.z());
    for (int i = 0; i < 9; ++i) out.position_covariance()[static_cast<std::size_t>(i)] = fix.covariance_S(i / 3, i % 3);
    out.position_world().x(fix.p_W.x());
    out.position_world().y(fix.p_W.y());
    out.position_world().z(fix.p_W.z());
    out.latitude(fix.latitude_deg);
    out.longitude(fix.longitude_deg);
    out.altitude(fix.height);
    out.snr_db(fix.snr_db);
  }
}

}  // namespace hadal::sensors
