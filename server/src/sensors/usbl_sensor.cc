#include "hadal/sensors/usbl_sensor.h"

#include <hadal_msgs.h>
#include <hadal_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/dds/time_msg.h"
#include "hadal/geometry/scene_rays.h"
#include "hadal/sensors/acoustic_channel.h"
#include "hadal/sensors/geodesy.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::Range;

const config::KeyTable<TransponderSpec>& transponder_keys() {
  return config::declare_keys<TransponderSpec>([](config::KeyTable<TransponderSpec>& t) {
    t.describe("transponder", "an acoustic transponder on the vehicle, which USBLs interrogate");
    t.vector("position", &TransponderSpec::p_BT).unit("m").doc("its position in B");
    t.number("source_level_db", &TransponderSpec::source_level_db).unit("dB re 1 uPa at 1 m")
        .range(Range::closed(100.0, 240.0)).doc("the reply's source level");
    t.number("detection_threshold_db", &TransponderSpec::detection_threshold_db).unit("dB")
        .range(Range::closed(-20.0, 60.0)).doc("the SNR an interrogation needs to be heard");
    t.number("turnaround_s", &TransponderSpec::turnaround_s).unit("s").range(Range::closed(0.0, 10.0))
        .doc("from hearing an interrogation to replying (known to the USBL, which subtracts it)");
  });
}

const config::KeyTable<UsblSensor::Spec, SensorReader>& UsblSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].usbl",
               "an ultra-short baseline transceiver: interrogates every other vehicle's transponder at rate_hz and "
               "fixes each reply's range and direction in S");
    t.number("frequency_hz", &Spec::frequency_hz).unit("Hz").range(Range::closed(1000.0, 1e6))
        .doc("centre of the band (absorption, noise)");
    t.number("bandwidth_hz", &Spec::bandwidth_hz).unit("Hz").range(Range::positive())
        .doc("the band, below twice the centre frequency (noise)");
    t.number("source_level_db", &Spec::source_level_db).unit("dB re 1 uPa at 1 m").range(Range::closed(100.0, 240.0))
        .doc("the interrogation's source level");
    t.number("directivity_index_db", &Spec::directivity_index_db).unit("dB").range(Range::closed(0.0, 40.0))
        .doc("the receive array's gain over one omnidirectional hydrophone");
    t.number("detection_threshold_db", &Spec::detection_threshold_db).unit("dB").range(Range::closed(-20.0, 60.0))
        .doc("the SNR a reply needs to be detected");
    t.number("cone_deg", &Spec::cone_half_angle).degrees().range(Range::left_open(0.0, 180.0))
        .doc("half angle of the coverage about -z_S (90: the hemisphere below a transceiver mounted as B)");
    t.number("max_range", &Spec::max_range).unit("m").range(Range::positive()).doc("the longest slant range fixed");
    t.number("range_stddev", &Spec::range_stddev).unit("m").range(Range::non_negative())
        .doc("range error at and above reference_snr_db");
    t.number("bearing_stddev_deg", &Spec::bearing_stddev).degrees().range(Range::closed(0.0, 45.0))
        .doc("direction error per axis across the direction, at and above reference_snr_db");
    t.number("reference_snr_db", &Spec::reference_snr_db).unit("dB").range(Range::closed(-20.0, 80.0))
        .doc("below it the errors grow as 10^((reference - SNR) / 20)");
    t.check([](const config::KeyReads& reads, Spec& spec, SensorReader&) {
      if (spec.bandwidth_hz < 2.0 * spec.frequency_hz) return true;
      reads.error_at_key("bandwidth_hz", "must be below twice frequency_hz (" +
                                             config::format_number(2.0 * spec.frequency_hz) + " Hz)");
      return false;
    });
  });
}

SensorReach UsblSensor::reach(const Spec& spec) { return {spec.max_range, spec.cone_half_angle}; }

double UsblSensor::error_scale(const Spec& spec, double snr_db) {
  return std::max(1.0, std::pow(10.0, (spec.reference_snr_db - snr_db) / 20.0));
}

UsblSensor::State UsblSensor::initial_state(const Spec&, const SensorSetup& setup) {
  State state;
  state.range_noise = RandomStream(channel_key(setup.seed, setup.vehicle, setup.sensor, "range"));
  state.bearing_noise = RandomStream(channel_key(setup.seed, setup.vehicle, setup.sensor, "bearing"));
  return state;
}

namespace {

const AcousticChannel& channel_of(const SampleContext& context) {
  return context.environment.acoustic_channel(context.ocean, context.world.acoustics);
}

Eigen::Vector3d p_WT(const SampleContext& context, int vehicle) {
  const VehicleSpec& spec = (*context.vehicles)[static_cast<std::size_t>(vehicle)];
  return context.state.vehicles[static_cast<std::size_t>(vehicle)].body.X_WB * spec.transponder->p_BT;
}

bool clear_path(const SampleContext& context, const Eigen::Vector3d& p_WS, const Eigen::Vector3d& p_WT, int target) {
  return context.rays == nullptr ||
         !AcousticChannel::occluded(*context.rays, context.state, p_WS, context.own_ray_body(), p_WT, target);
}

}  // namespace

void UsblSensor::sample(const SampleContext& context, const Spec&, State& state) {
  if (context.vehicles == nullptr) return;
  const std::uint64_t index = state.interrogations++;
  for (std::size_t v = 0; v < context.vehicles->size(); ++v) {
    if (static_cast<int>(v) == context.vehicle_index || !(*context.vehicles)[v].transponder) continue;
    Exchange& exchange = state.exchanges.emplace_back();
    exchange.target = static_cast<int>(v);
    exchange.interrogation = index;
    exchange.t_interrogation = context.time;
    exchange.p_Winterrogation = context.p_WS();
  }
}

std::optional<double> UsblSensor::advance(const SampleContext& context, const Spec& spec, State& state) {
  if (context.vehicles == nullptr) return std::nullopt;
  const std::size_t n = context.vehicles->size();
  const Eigen::Vector3d p_WS1 = context.p_WS();
  std::vector<Eigen::Vector3d> p_WT1(n, Eigen::Vector3d::Zero());
  for (std::size_t v = 0; v < n; ++v) {
    if ((*context.vehicles)[v].transponder) p_WT1[v] = p_WT(context, static_cast<int>(v));
  }
  const double t1 = context.time;
  if (!state.has_previous || !(t1 > state.t_previous)) {
    state.has_previous = true;
    state.t_previous = t1;
    state.p_WS_previous = p_WS1;
    state.p_WT_previous = p_WT1;
    return std::nullopt;
  }
  const double t0 = state.t_previous;
  const Eigen::Vector3d p_WS0 = state.p_WS_previous;
  const auto between = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) -> Eigen::Vector3d {
    return a + (t - t0) / (t1 - t0) * (b - a);
  };
  const AcousticChannel& channel = channel_of(context);
  const double noise_db = channel.noise_level_db(spec.frequency_hz, spec.bandwidth_hz);
  // An exchange older than this has lost its reply (the longest two-way time at 1400 m/s, turnaround included).
  const double give_up_s = 2.0 * spec.max_range / 1400.0 + 11.0;
  bool any = false;
  std::vector<Exchange> kept;
  kept.reserve(state.exchanges.size());
  for (Exchange& exchange : state.exchanges) {
    const std::size_t target = static_cast<std::size_t>(exchange.target);
    const TransponderSpec& transponder = *(*context.vehicles)[target].transponder;
    const Eigen::Vector3d& p_WT0 = state.p_WT_previous.size() == n ? state.p_WT_previous[target] : p_WT1[target];
    bool lost = false;
    if (exchange.phase == Exchange::Phase::kOutbound) {
      const std::optional<double> heard =
          channel.arrival(exchange.t_interrogation, exchange.p_Winterrogation, t0, p_WT0, t1, p_WT1[target]);
      if (heard) {
        const Eigen::Vector3d p = between(p_WT0, p_WT1[target], *heard);
        const double snr = spec.source_level_db - channel.transmission_loss_db(exchange.p_Winterrogation, p,
                                                                               spec.frequency_hz) - noise_db;
        if (snr >= transponder.detection_threshold_db &&
            clear_path(context, exchange.p_Winterrogation, p, exchange.target)) {
          exchange.phase = Exchange::Phase::kTurnaround;
          exchange.t_reply = *heard + transponder.turnaround_s;
        } else {
          lost = true;
        }
      }
    }
    if (!lost && exchange.phase == Exchange::Phase::kTurnaround && exchange.t_reply <= t1) {
      exchange.p_Wreply = between(p_WT0, p_WT1[target], std::max(exchange.t_reply, t0));
      exchange.phase = Exchange::Phase::kInbound;
    }
    if (!lost && exchange.phase == Exchange::Phase::kInbound) {
      const std::optional<double> received = channel.arrival(exchange.t_reply, exchange.p_Wreply, t0, p_WS0, t1, p_WS1);
      if (received) {
        lost = true;  // done, fixed or not
        const Eigen::Vector3d p_WSf = between(p_WS0, p_WS1, *received);
        const Eigen::Vector3d d_W = exchange.p_Wreply - p_WSf;
        const double distance = d_W.norm();
        const Eigen::Matrix3d R_WS = context.R_WS();
        const Eigen::Vector3d u_S = R_WS.transpose() * d_W / std::max(distance, 1e-9);
        const double off_axis = std::acos(std::clamp(-u_S.z(), -1.0, 1.0));
        const double snr = transponder.source_level_db -
                           channel.transmission_loss_db(exchange.p_Wreply, p_WSf, spec.frequency_hz) - noise_db +
                           spec.directivity_index_db;
        if (snr >= spec.detection_threshold_db && off_axis <= spec.cone_half_angle && distance <= spec.max_range &&
            clear_path(context, p_WSf, exchange.p_Wreply, exchange.target)) {
          if (!any) state.fixes.clear();
          any = true;
          UsblFix& fix = state.fixes.emplace_back();
          fix.stamp = *received;
          fix.interrogation_time = exchange.t_interrogation;
          fix.interrogation = exchange.interrogation;
          fix.target = exchange.target;
          fix.target_name = (*context.vehicles)[target].name;
          fix.snr_db = snr;
          fix.travel_time = *received - exchange.t_interrogation - transponder.turnaround_s;
          const double scale = error_scale(spec, snr);
          const double sigma_r = spec.range_stddev * scale;
          const double sigma_b = spec.bearing_stddev * scale;
          fix.range = channel.mean_sound_speed(exchange.p_Wreply, p_WSf) * fix.travel_time / 2.0 +
                      sigma_r * state.range_noise.normal();
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
          fix.p_W = p_WSf + R_WS * fix.p_S;
          const GeodeticPosition geo = context.environment.frame_W().to_geodetic(fix.p_W);
          fix.latitude_deg = geo.latitude_rad / kDegToRad;
          fix.longitude_deg = geo.longitude_rad / kDegToRad;
          fix.height = geo.height_m;
        }
      }
    }
    if (!lost && t1 - exchange.t_interrogation > give_up_s) lost = true;
    if (!lost) kept.push_back(exchange);
  }
  state.exchanges = std::move(kept);
  state.t_previous = t1;
  state.p_WS_previous = p_WS1;
  state.p_WT_previous = std::move(p_WT1);
  if (!any) return std::nullopt;
  return state.fixes.back().stamp;
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
