#include "hadal/sensors/lbl_sensor.h"

#include <hadal_msgs.h>
#include <hadal_msgsPubSubTypes.h>

#include "hadal/config/key_table.h"
#include "hadal/dds/time_msg.h"
#include "hadal/geometry/ray_batch.h"
#include "hadal/sensors/acoustic_channel.h"
#include "hadal/sensors/interrogator_keys.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

const config::KeyTable<LblSensor::Spec, SensorReader>& LblSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].lbl",
               "a long-baseline transceiver: interrogates every beacon of world.acoustics.beacons at rate_hz and "
               "measures its range to each");
    declare_interrogator_keys(t);
  });
}

SensorReach LblSensor::reach(const Spec&) { return {}; }

LblSensor::State LblSensor::initial_state(const Spec&, const SensorSetup& setup) {
  State state;
  state.range_noise = RandomStream(channel_key(setup.seed, setup.vehicle, setup.sensor, "range"));
  return state;
}

namespace {

std::vector<Responder> beacons(const SampleContext& context) {
  std::vector<Responder> out;
  out.reserve(context.world.acoustics.beacons.size());
  for (const BeaconSpec& beacon : context.world.acoustics.beacons) {
    Responder& r = out.emplace_back();
    r.present = true;
    r.p_W = beacon.p_W;
    r.ray_body = geometry::kNoHit;
    r.source_level_db = beacon.source_level_db;
    r.detection_threshold_db = beacon.detection_threshold_db;
    r.turnaround_s = beacon.turnaround_s;
  }
  return out;
}

}  // namespace

void LblSensor::sample(const SampleContext& context, const Spec&, State& state) {
  interrogate(state.interrogation, context.time, context.p_WS(), beacons(context));
}

std::optional<double> LblSensor::advance(const SampleContext& context, const Spec& spec, State& state) {
  const AcousticChannel& channel = context.environment.acoustic_channel(context.ocean, context.world.acoustics);
  const std::vector<ReceivedReply> replies =
      advance_interrogations(state.interrogation, channel, interrogator_acoustics(spec), context.time, context.p_WS(),
                             beacons(context), occlusion_of(context));
  bool any = false;
  for (const ReceivedReply& reply : replies) {
    if (!any) state.ranges.clear();
    any = true;
    const BeaconSpec& beacon = context.world.acoustics.beacons[static_cast<std::size_t>(reply.responder)];
    LblRange& range = state.ranges.emplace_back();
    range.stamp = reply.reception_time;
    range.interrogation_time = reply.interrogation_time;
    range.interrogation = reply.interrogation;
    range.beacon = reply.responder;
    range.beacon_name = beacon.name;
    range.p_Wbeacon = beacon.p_W;
    range.travel_time = reply.travel_time;
    range.snr_db = reply.snr_db;
    const double sigma = spec.range_stddev * error_scale(spec, reply.snr_db);
    range.range = reply.range + sigma * state.range_noise.normal();
    range.range_variance = sigma * sigma;
  }
  if (!any) return std::nullopt;
  return state.ranges.back().stamp;
}

void LblSensor::acoustic_links(const SampleContext& context, const Spec&, const State& state,
                              std::vector<AcousticLink>& out) {
  if (context.sensor == nullptr) return;
  std::vector<std::string> names;
  for (const BeaconSpec& beacon : context.world.acoustics.beacons) names.push_back(beacon.name);
  const std::string self = (context.vehicles ? (*context.vehicles)[static_cast<std::size_t>(context.vehicle_index)].name
                                             : std::string("vehicle")) + "/" + context.sensor->name;
  interrogation_links(state.interrogation, context.p_WS(), self, beacons(context), names, out);
}

void LblSensor::fill_message(const Spec&, const State& state, const MessageHeader& header, Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.ranges().clear();
  for (const LblRange& range : state.ranges) {
    hadal_msgs::msg::LblRange& out = msg.ranges().emplace_back();
    out.stamp(dds::to_time_msg(range.stamp));
    out.interrogation_stamp(dds::to_time_msg(range.interrogation_time));
    out.beacon(range.beacon_name);
    out.interrogation(range.interrogation);
    out.travel_time(range.travel_time);
    out.range(range.range);
    out.range_variance(range.range_variance);
    out.beacon_position().x(range.p_Wbeacon.x());
    out.beacon_position().y(range.p_Wbeacon.y());
    out.beacon_position().z(range.p_Wbeacon.z());
    out.snr_db(range.snr_db);
  }
}

}  // namespace hadal::sensors
