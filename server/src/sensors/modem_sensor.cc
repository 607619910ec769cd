#include "hadal/sensors/modem_sensor.h"

#include <hadal_msgs.h>
#include <hadal_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>
#include <variant>

#include "hadal/config/key_table.h"
#include "hadal/core/vehicle_spec.h"
#include "hadal/dds/time_msg.h"
#include "hadal/sensors/acoustic_channel.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::Range;

const config::Presets<ModemFigures>& modem_presets() {
  // Band, bit rate and packet structure as the makers publish them; the source levels are typical of the
  // transducers these modems ship with, and the implementation losses (what a real receiver needs beyond the
  // ideal modulation's Eb/N0, coding included) are assumptions of this simulator, stated as such.
  static const config::Presets<ModemFigures> presets = {
      {.id = "whoi_micromodem_fhfsk",
       .product = "WHOI Micro-Modem, FH-FSK packet (rate 0) in its 25 kHz band",
       .source = "Freitag et al., \"The WHOI Micro-Modem\", OCEANS 2005, and acomms.whoi.edu/micro-modem: FH-FSK "
                 "at 80 bit/s in a 4 kHz band, 32-byte frames, probe and null 0.3 s before a packet (the page's "
                 "PSK table). Source level 185 dB and implementation loss 3 dB assumed",
       .figures = {.frequency_hz = 25000.0, .bandwidth_hz = 4000.0, .bit_rate_bps = 80.0, .source_level_db = 185.0,
                   .modulation = ModemModulation::kFsk, .implementation_loss_db = 3.0, .preamble_s = 0.3,
                   .max_payload_bytes = 32}},
      {.id = "whoi_micromodem_psk_rate5",
       .product = "WHOI Micro-Modem, PSK packet at ~5000 bit/s in its 25 kHz band",
       .source = "acomms.whoi.edu/micro-modem: PSK in a 5 kHz band, rate 5 ~5000 bit/s burst rate, probe and null "
                 "0.3 s; 8 frames of 32 bytes assumed per packet. Source level 185 dB and implementation loss 8 dB "
                 "(coherent reception over a multipath channel) assumed",
       .figures = {.frequency_hz = 25000.0, .bandwidth_hz = 5000.0, .bit_rate_bps = 5000.0, .source_level_db = 185.0,
                   .modulation = ModemModulation::kPsk, .implementation_loss_db = 8.0, .preamble_s = 0.3,
                   .max_payload_bytes = 256}},
      {.id = "evologics_s2cr_18_34",
       .product = "EvoLogics S2CR 18/34 (18-34 kHz, up to 13.9 kbit/s)",
       .source = "EvoLogics S2CR 18/34 product page: band 18-34 kHz, acoustic connection up to 13.9 kbit/s, range "
                 "3500 m; S2C Modem Guide (2011): burst data up to 1 KB. Source level 184 dB, preamble 0.1 s and "
                 "implementation loss 10 dB assumed (its range at that rate: ~3.5 km in the default sea)",
       .figures = {.frequency_hz = 26000.0, .bandwidth_hz = 16000.0, .bit_rate_bps = 13900.0,
                   .source_level_db = 184.0, .modulation = ModemModulation::kPsk, .implementation_loss_db = 10.0,
                   .preamble_s = 0.1, .max_payload_bytes = 1024}},
  };
  return presets;
}

void ModemFigures::apply(ModemSpec& spec) const {
  spec.frequency_hz = frequency_hz;
  spec.bandwidth_hz = bandwidth_hz;
  spec.bit_rate_bps = bit_rate_bps;
  spec.source_level_db = source_level_db;
  spec.modulation = modulation;
  spec.implementation_loss_db = implementation_loss_db;
  spec.preamble_s = preamble_s;
  spec.max_payload_bytes = max_payload_bytes;
}

const config::KeyTable<ModemSensor::Spec, SensorReader>& ModemSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].modem",
               "an acoustic modem: sends the packets clients give it (rt/<vehicle>/<modem>/tx) through the water to "
               "every other modem, and publishes those it decodes (rt/<vehicle>/<modem>/rx); rate_hz is not used");
    t.preset("modem", modem_presets(), [](Spec& spec, const config::Preset<ModemFigures>& preset, SensorReader&) {
       preset.figures.apply(spec);
     }).doc("a product (table below): sets the keys the file does not give");
    t.number("frequency_hz", &Spec::frequency_hz).unit("Hz").range(Range::closed(1000.0, 1e6))
        .doc("centre of the band (absorption, noise)");
    t.number("bandwidth_hz", &Spec::bandwidth_hz).unit("Hz").range(Range::positive())
        .doc("the band, below twice the centre frequency (noise, processing gain, interference)");
    t.number("bit_rate_bps", &Spec::bit_rate_bps).unit("bit/s").range(Range::positive())
        .doc("the data rate of a packet (its duration; Eb/N0)");
    t.number("source_level_db", &Spec::source_level_db).unit("dB re 1 uPa at 1 m").range(Range::closed(100.0, 240.0))
        .doc("the transmit level");
    t.choice("modulation", &Spec::modulation,
             {{"fsk", ModemModulation::kFsk, "non-coherent binary FSK: BER = exp(-Eb/N0 / 2) / 2"},
              {"psk", ModemModulation::kPsk, "coherent BPSK: BER = erfc(sqrt(Eb/N0)) / 2"}})
        .doc("the modulation of the error curve");
    t.number("implementation_loss_db", &Spec::implementation_loss_db).unit("dB").range(Range::closed(-20.0, 40.0))
        .doc("Eb/N0 the receiver needs beyond the ideal modulation's (negative: coding gain)");
    t.number("preamble_s", &Spec::preamble_s).unit("s").range(Range::closed(0.0, 10.0))
        .doc("synchronisation before a packet's data");
    t.number("max_payload_bytes", &Spec::max_payload_bytes).range(Range::closed(1.0, 65536.0))
        .doc("the longest payload a client may send; longer ones are refused");
    t.number("queue_length", &Spec::queue_length).range(Range::closed(0.0, 1024.0))
        .doc("packets that may wait while the modem transmits; more are refused");
    t.number("capture_threshold_db", &Spec::capture_threshold_db).unit("dB").range(Range::closed(0.0, 40.0))
        .doc("a packet survives packets overlapping it at a receiver when it arrives this much stronger than "
             "them together");
    t.number("max_range", &Spec::max_range).unit("m").range(Range::positive())
        .doc("nothing is heard from farther");
    t.check([](const config::KeyReads& reads, Spec& spec, SensorReader&) {
      if (spec.bandwidth_hz < 2.0 * spec.frequency_hz) return true;
      reads.error_at_key("bandwidth_hz", "must be below twice frequency_hz (" +
                                             config::format_number(2.0 * spec.frequency_hz) + " Hz)");
      return false;
    });
  });
}

SensorReach ModemSensor::reach(const Spec&) { return {}; }

ModemSensor::State ModemSensor::initial_state(const Spec&, const SensorSetup& setup) {
  State state;
  state.packet_draws = RandomStream(channel_key(setup.seed, setup.vehicle, setup.sensor, "packets"));
  return state;
}

double ModemSensor::duration(const Spec& spec, std::size_t payload_bytes) {
  return spec.preamble_s + 8.0 * static_cast<double>(payload_bytes) / spec.bit_rate_bps;
}

double ModemSensor::packet_success(const Spec& spec, double sinr_db, std::size_t payload_bytes) {
  const double ebn0_db = sinr_db + 10.0 * std::log10(spec.bandwidth_hz / spec.bit_rate_bps) - spec.implementation_loss_db;
  const double ebn0 = std::pow(10.0, ebn0_db / 10.0);
  const double ber =
      spec.modulation == ModemModulation::kFsk ? 0.5 * std::exp(-0.5 * ebn0) : 0.5 * std::erfc(std::sqrt(ebn0));
  return std::exp(8.0 * static_cast<double>(payload_bytes) * std::log1p(-ber));
}

bool ModemSensor::same_scheme(const Spec& a, const Spec& b) {
  return a.frequency_hz == b.frequency_hz && a.bandwidth_hz == b.bandwidth_hz && a.bit_rate_bps == b.bit_rate_bps &&
         a.modulation == b.modulation;
}

bool ModemSensor::bands_overlap(const Spec& a, const Spec& b) {
  return std::abs(a.frequency_hz - b.frequency_hz) < 0.5 * (a.bandwidth_hz + b.bandwidth_hz);
}

namespace {

const ModemSpec* modem_spec(const SensorSpec& sensor) { return std::get_if<ModemSpec>(&sensor.kind); }

// A name a client sent, for a refusal: at most 64 characters.
std::string echoed(const std::string& name) {
  return "'" + (name.size() <= 64 ? name : name.substr(0, 61) + "...") + "'";
}

// Whether a packet to `destination` is for modem `sensor` of `vehicle`.
bool addressed_to(const std::string& destination, const VehicleSpec& vehicle, const SensorSpec& sensor) {
  if (destination.empty() || destination == vehicle.name) return true;
  return destination.size() == vehicle.name.size() + 1 + sensor.name.size() &&
         destination.compare(0, vehicle.name.size(), vehicle.name) == 0 && destination[vehicle.name.size()] == '/' &&
         destination.compare(vehicle.name.size() + 1, std::string::npos, sensor.name) == 0;
}

// Drops what can no longer matter: a packet or an own transmission that ended before every reception still to
// be decided (and before now) began.
void prune(ModemSensor::State& state, double t1) {
  double horizon = t1;
  for (const ModemSensor::Incoming& in : state.incoming) {
    if (!in.decided) horizon = std::min(horizon, in.arrived ? in.start : t1);
  }
  std::erase_if(state.incoming, [horizon](const ModemSensor::Incoming& in) { return in.decided && in.end < horizon; });
  std::erase_if(state.sent_intervals, [horizon](const std::pair<double, double>& s) { return s.second < horizon; });
}

}  // namespace

std::string ModemSensor::check_send(const std::vector<VehicleSpec>& vehicles, int vehicle, int sensor,
                                    const Spec& spec, const State& state, double t, const std::string& destination,
                                    std::size_t payload_bytes) {
  if (payload_bytes == 0) return "empty payload: a packet carries at least one byte";
  if (payload_bytes > static_cast<std::size_t>(spec.max_payload_bytes)) {
    return "payload of " + std::to_string(payload_bytes) + " bytes is longer than the modem's max_payload_bytes (" +
           std::to_string(spec.max_payload_bytes) + ")";
  }
  const VehicleSpec& self = vehicles[static_cast<std::size_t>(vehicle)];
  if (!destination.empty()) {
    bool known = false, only_self = true;
    for (const VehicleSpec& v : vehicles) {
      for (const SensorSpec& s : v.sensors) {
        if (!modem_spec(s) || !addressed_to(destination, v, s)) continue;
        known = true;
        if (&s != &self.sensors[static_cast<std::size_t>(sensor)]) only_self = false;
      }
    }
    if (!known) {
      return "unknown destination " + echoed(destination) +
             ": not a vehicle with a modem or a '<vehicle>/<modem>' of the scenario ('' sends to every modem)";
    }
    if (only_self) return "destination " + echoed(destination) + " is the sending modem itself";
  }
  // The packets that would wait behind the one being sent: the queue's head starts at once on a free modem.
  const bool free = state.busy_until <= t;
  const std::size_t waiting = state.queue.size() + 1 - (free ? 1 : 0);
  if (waiting > static_cast<std::size_t>(spec.queue_length)) {
    return "the modem is transmitting until t = " + config::format_number(std::max(state.busy_until, t)) +
           " s or about to, and " + std::to_string(waiting - 1) + " packet(s) wait behind it (queue_length " +
           std::to_string(spec.queue_length) + ")";
  }
  return "";
}

std::string ModemSensor::send(const std::vector<VehicleSpec>& vehicles, int vehicle, int sensor, const Spec& spec,
                              State& state, double t, const std::string& destination,
                              std::vector<std::uint8_t> payload) {
  std::string reason = check_send(vehicles, vehicle, sensor, spec, state, t, destination, payload.size());
  if (reason.empty()) state.queue.push_back({destination, std::move(payload), t});
  return reason;
}

void ModemSensor::sample(const SampleContext&, const Spec&, State&) {}

std::optional<double> ModemSensor::advance(const SampleContext& context, const Spec& spec, State& state) {
  const double t1 = context.time;
  const Eigen::Vector3d p_W1 = context.p_WS();
  if (!state.has_previous || !(t1 > state.t_previous)) {
    state.has_previous = true;
    state.t_previous = t1;
    state.p_W_previous = p_W1;
    return std::nullopt;
  }
  const double t0 = state.t_previous;
  const Eigen::Vector3d p_W0 = state.p_W_previous;
  const auto at = [&](double t) -> Eigen::Vector3d {
    return p_W0 + std::clamp((t - t0) / (t1 - t0), 0.0, 1.0) * (p_W1 - p_W0);
  };

  // 1. Sending: what receivers have picked up (started before the previous step) goes; queued packets start.
  std::erase_if(state.transmissions, [t0](const Transmission& tx) { return tx.created_at < t0; });
  while (!state.queue.empty() && state.busy_until <= t1) {
    State::Queued& queued = state.queue.front();
    const double start = std::max(queued.queued_at, state.busy_until);
    if (start > t1) break;
    Transmission& tx = state.transmissions.emplace_back();
    tx.sequence = state.sequences++;
    tx.start = start;
    tx.end = start + duration(spec, queued.payload.size());
    tx.created_at = t1;
    tx.p_W = at(start);
    tx.destination = std::move(queued.destination);
    tx.payload = std::move(queued.payload);
    state.queue.pop_front();
    state.busy_until = tx.end;
    state.sent_intervals.emplace_back(tx.start, tx.end);
    ++state.tally.sent;
  }

  if (context.vehicles == nullptr) {
    state.t_previous = t1;
    state.p_W_previous = p_W1;
    return std::nullopt;
  }
  const std::vector<VehicleSpec>& vehicles = *context.vehicles;
  const VehicleSpec& self = vehicles[static_cast<std::size_t>(context.vehicle_index)];

  // 2. Picking up what the other modems in an overlapping band started.
  for (std::size_t v = 0; v < vehicles.size(); ++v) {
    for (std::size_t k = 0; k < vehicles[v].sensors.size(); ++k) {
      const SensorSpec& sensor = vehicles[v].sensors[k];
      const ModemSpec* other = modem_spec(sensor);
      if (other == nullptr || &sensor == context.sensor || !bands_overlap(spec, *other)) continue;
      const auto& other_state = std::get<State>(context.state.vehicles[v].sensors[k].kind);
      auto heard = std::find_if(state.heard.begin(), state.heard.end(), [&](const Heard& h) {
        return h.vehicle == static_cast<int>(v) && h.sensor == static_cast<int>(k);
      });
      if (heard == state.heard.end()) {
        heard = state.heard.insert(state.heard.end(), Heard{static_cast<int>(v), static_cast<int>(k), 0});
      }
      for (const Transmission& tx : other_state.transmissions) {
        if (tx.sequence < heard->next) continue;
        heard->next = tx.sequence + 1;
        Incoming& in = state.incoming.emplace_back();
        in.vehicle = static_cast<int>(v);
        in.sensor = static_cast<int>(k);
        in.packet = tx;
        in.source_level_db = other->source_level_db;
        in.decodable = same_scheme(spec, *other) && context.sensor != nullptr &&
                       addressed_to(tx.destination, self, *context.sensor);
      }
    }
  }

  // 3. Wavefronts arriving within the step.
  const AcousticChannel& channel = context.environment.acoustic_channel(context.ocean, context.world.acoustics);
  const double give_up_s = spec.max_range / 1400.0;
  for (Incoming& in : state.incoming) {
    if (in.arrived) continue;
    std::optional<double> arrival;
    if (in.packet.start < t0 && (p_W0 - in.packet.p_W).norm() <= 1400.0 * (t0 - in.packet.start) &&
        in.packet.start + channel.travel_time(in.packet.p_W, p_W0) <= t0) {
      // Picked up a step late (its sender comes later in the step's order) and already here: met at the step start.
      arrival = in.packet.start + channel.travel_time(in.packet.p_W, p_W0);
    } else {
      arrival = channel.arrival(in.packet.start, in.packet.p_W, t0, p_W0, t1, p_W1);
    }
    if (!arrival) {
      if (t1 - in.packet.start > give_up_s) {  // beyond max_range: never heard
        in.decided = in.arrived = true;
        in.start = in.end = in.packet.start;
        in.level_db = -std::numeric_limits<double>::infinity();
      }
      continue;
    }
    const Eigen::Vector3d p = at(*arrival);
    in.arrived = true;
    in.start = *arrival;
    in.end = *arrival + (in.packet.end - in.packet.start);
    if ((p - in.packet.p_W).norm() > spec.max_range) {
      in.decided = true;  // too far to be heard at all
      in.level_db = -std::numeric_limits<double>::infinity();
      continue;
    }
    in.level_db = in.source_level_db - channel.transmission_loss_db(in.packet.p_W, p, spec.frequency_hz);
    if (in.decodable && context.rays != nullptr) {
      in.blocked = AcousticChannel::occluded(*context.rays, context.state, p, context.own_ray_body(), in.packet.p_W,
                                             in.vehicle);
    }
  }

  // 4. Deciding the packets whose reception ended within the step, in the order they end.
  std::vector<std::size_t> ended;
  for (std::size_t i = 0; i < state.incoming.size(); ++i) {
    const Incoming& in = state.incoming[i];
    if (in.arrived && !in.decided && in.end <= t1) ended.push_back(i);
  }
  std::stable_sort(ended.begin(), ended.end(),
                   [&](std::size_t a, std::size_t b) { return state.incoming[a].end < state.incoming[b].end; });
  bool any = false;
  for (const std::size_t i : ended) {
    Incoming& in = state.incoming[i];
    in.decided = true;
    if (!in.decodable) continue;
    const bool sent_meanwhile = std::any_of(state.sent_intervals.begin(), state.sent_intervals.end(),
                                            [&](const std::pair<double, double>& s) {
                                              return s.first < in.end && s.second > in.start;
                                            });
    if (sent_meanwhile) {
      ++state.tally.lost_half_duplex;
      continue;
    }
    if (in.blocked) {
      ++state.tally.lost_blocked;
      continue;
    }
    double interference = 0.0;  // [uPa^2]
    for (std::size_t j = 0; j < state.incoming.size(); ++j) {
      const Incoming& other = state.incoming[j];
      // A sender's own packets follow each other: when the receiver closes in, the next one's start arrives a
      // little before the last one's end, which is motion over the turn, not a collision.
      if (j == i || !other.arrived || (other.vehicle == in.vehicle && other.sensor == in.sensor) ||
          !(other.start < in.end && other.end > in.start)) {
        continue;
      }
      interference += std::pow(10.0, other.level_db / 10.0);
    }
    if (interference > 0.0 && in.level_db - 10.0 * std::log10(interference) < spec.capture_threshold_db) {
      ++state.tally.lost_collision;
      continue;
    }
    if (!state.noise_db) state.noise_db = channel.noise_level_db(spec.frequency_hz, spec.bandwidth_hz);
    const double sinr_db = in.level_db - 10.0 * std::log10(std::pow(10.0, *state.noise_db / 10.0) + interference);
    if (state.packet_draws.uniform() >= packet_success(spec, sinr_db, in.packet.payload.size())) {
      ++state.tally.lost_noise;
      continue;
    }
    if (!any) state.delivered.clear();
    any = true;
    ++state.tally.delivered;
    ModemPacket& packet = state.delivered.emplace_back();
    packet.transmit_time = in.packet.start;
    packet.stamp = in.end;
    packet.travel_time = in.start - in.packet.start;
    packet.snr_db = sinr_db;
    const VehicleSpec& sender = vehicles[static_cast<std::size_t>(in.vehicle)];
    packet.source = sender.name + "/" + sender.sensors[static_cast<std::size_t>(in.sensor)].name;
    packet.destination = in.packet.destination;
    packet.sequence = in.packet.sequence;
    packet.payload = in.packet.payload;
  }
  prune(state, t1);
  state.t_previous = t1;
  state.p_W_previous = p_W1;
  if (!any) return std::nullopt;
  return state.delivered.back().stamp;
}

void ModemSensor::acoustic_links(const SampleContext& context, const Spec&, const State& state,
                                 std::vector<AcousticLink>& out) {
  if (context.vehicles == nullptr || context.sensor == nullptr) return;
  const std::vector<VehicleSpec>& vehicles = *context.vehicles;
  const std::string self = vehicles[static_cast<std::size_t>(context.vehicle_index)].name + "/" + context.sensor->name;
  for (const Incoming& in : state.incoming) {
    if (in.decided) continue;
    AcousticLink& link = out.emplace_back();
    const VehicleSpec& sender = vehicles[static_cast<std::size_t>(in.vehicle)];
    link.source = sender.name + "/" + sender.sensors[static_cast<std::size_t>(in.sensor)].name;
    link.target = self;
    link.p_Wemit = in.packet.p_W;
    link.p_Wtarget = context.p_WS();
    link.emit_time = in.packet.start;
    link.duration = in.packet.end - in.packet.start;
  }
}

void ModemSensor::fill_message(const Spec&, const State& state, const MessageHeader& header, Rx::Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.packets().clear();
  for (const ModemPacket& packet : state.delivered) {
    hadal_msgs::msg::AcousticPacket& out = msg.packets().emplace_back();
    out.transmit_stamp(dds::to_time_msg(packet.transmit_time));
    out.stamp(dds::to_time_msg(packet.stamp));
    out.source(packet.source);
    out.destination(packet.destination);
    out.sequence_number(packet.sequence);
    out.payload(packet.payload);
    out.travel_time(packet.travel_time);
    out.snr_db(packet.snr_db);
  }
}

}  // namespace hadal::sensors
