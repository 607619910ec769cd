// Acoustic modem (YAML `type: modem`; received packets on rt/<vehicle>/<modem>/rx, hadal_msgs/AcousticPackets;
// sent by clients on rt/<vehicle>/<modem>/tx, hadal_msgs/AcousticPacket). Every modem of every vehicle shares
// one medium, the water of the acoustic channel (sensors/acoustic_channel.h): what one modem sends, every other
// modem whose band overlaps hears, after the travel time, at the level the channel leaves it, for the packet's
// duration (docs/ARCHITECTURE.md, "Acoustic communications").
//
// Sending. Simulation::send_packet (a client's tx sample, or a packet attached to a lockstep step request)
// queues a packet at the sim time t_q it is applied; it is refused, with the reason, when its payload is empty
// or longer than max_payload_bytes, when its destination is not a modem of the scenario (or is the sender), or
// when queue_length packets already wait. A modem sends one packet at a time: the packet starts at
// max(t_q, the end of the packet before), from where the modem is then, and lasts
//   T = preamble_s + 8 bytes / bit_rate_bps.
// Receiving. The packet's wavefront reaches modem j at t_a, when it meets j's track (linear over each step; the
// emitter is where it was at the start); j receives it over [t_a, t_a + T] at the level
//   RL = SL - TL(p_emit, p_j(t_a), f)          (spreading + Francois–Garrison absorption at j's band centre)
// and decides it at t_a + T:
//   - not for j (another destination; j delivers packets addressed to "", its vehicle or "<vehicle>/<modem>"),
//     or another scheme (frequency, band, bit rate or modulation differ): not decoded, but it interferes;
//   - half-duplex: lost when j transmitted at any time during [t_a, t_a + T];
//   - blocked by the seabed or a body on the straight path at t_a: lost;
//   - capture rule: lost when SIR = RL - 10 log10(sum of the levels of every other sender's packet j receives
//     overlapping it in time, in an overlapping band) < capture_threshold_db (a sender's own packets follow each
//     other; at a receiver closing in, the next one's start overlaps the last one's end by the motion over the
//     turn); so two equal packets overlapping
//     at a receiver between their senders both collide, while a receiver close to one sender keeps that one;
//   - otherwise decoded with the probability packet_success(spec, SINR, bytes) of the preset's error curve,
//     SINR = RL - 10 log10(10^(NL/10) + interference) with NL the Wenz ambient noise in j's band: a uniform draw
//     of j's stream ("packets") per decided packet, in the order the packets end.
// A decoded packet is j's sample, stamped at t_a + T (several in one step: one message).
// Deliberately left out: ray bending, multipath and Doppler, carrier sense and any MAC (the client's job),
// acknowledgements and retries.
// YAML keys: ModemSensor::keys() (server/src/sensors/modem_sensor.cc), shown in configs/REFERENCE.md.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/sensors/modem_spec.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"

namespace hadal_msgs::msg {
class AcousticPackets;
class AcousticPacketsPubSubType;
}  // namespace hadal_msgs::msg

namespace hadal {
struct SimState;
struct VehicleSpec;
}  // namespace hadal

namespace hadal::sensors {

// A packet as a receiver delivers it.
struct ModemPacket {
  double transmit_time = 0.0;  // the start of its transmission [s]
  double stamp = 0.0;          // the end of its reception [s]
  double travel_time = 0.0;    // from the start of transmission to the start of reception [s]
  double snr_db = 0.0;         // SINR over the packet [dB]
  std::string source;          // "<vehicle>/<modem>" of the sender
  std::string destination;     // as sent ("" broadcast)
  std::uint64_t sequence = 0;  // the sender's packet index (0, 1, ...)
  std::vector<std::uint8_t> payload;
};

struct ModemSensor {
  static constexpr std::string_view kType = "modem";
  static constexpr bool kCastsRays = true;  // occlusion
  static constexpr bool kCaptures = false;

  using Spec = ModemSpec;

  struct Rx {
    static constexpr std::string_view kSuffix = "rx";
    using Message = hadal_msgs::msg::AcousticPackets;
    using PubSubType = hadal_msgs::msg::AcousticPacketsPubSubType;
    template <class State>
    static void fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
      ModemSensor::fill_message(spec, state, header, msg);
    }
  };
  using Topics = TopicList<Rx>;

  // A packet a modem has sent or is sending.
  struct Transmission {
    std::uint64_t sequence = 0;
    double start = 0.0, end = 0.0;  // [s]
    double created_at = 0.0;        // the step end at which it was started (receivers pick it up then or next step)
    Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // the emitter at `start`
    std::string destination;
    std::vector<std::uint8_t> payload;
  };
  // A packet travelling towards this modem, or being received.
  struct Incoming {
    int vehicle = -1, sensor = -1;  // the sender
    Transmission packet;
    double source_level_db = 0.0;
    bool decodable = false;  // for this modem, in its scheme
    // Once its wavefront has arrived:
    bool arrived = false;
    double start = 0.0, end = 0.0;  // reception [s]
    double level_db = 0.0;          // received level [dB re 1 uPa^2]
    bool blocked = false;
    bool decided = false;
  };
  // Where this modem has got to in another modem's transmissions.
  struct Heard {
    int vehicle = -1, sensor = -1;
    std::uint64_t next = 0;  // the first sequence not yet picked up
  };
  // Counts for figures and tests.
  struct Tally {
    std::uint64_t sent = 0, delivered = 0, lost_noise = 0, lost_collision = 0, lost_half_duplex = 0, lost_blocked = 0;
  };

  struct State {
    RandomStream packet_draws;
    struct Queued {
      std::string destination;
      std::vector<std::uint8_t> payload;
      double queued_at = 0.0;
    };
    std::deque<Queued> queue;
    double busy_until = -std::numeric_limits<double>::infinity();  // the end of the last transmission [s]
    std::uint64_t sequences = 0;
    std::vector<Transmission> transmissions;  // started at this or the previous step (what receivers pick up)
    std::vector<std::pair<double, double>> sent_intervals;  // own transmissions that may overlap a reception
    std::vector<Heard> heard;
    std::vector<Incoming> incoming;
    std::vector<ModemPacket> delivered;  // those of the last step that had any
    Tally tally;
    bool has_previous = false;
    double t_previous = 0.0;
    Eigen::Vector3d p_W_previous = Eigen::Vector3d::Zero();
    std::optional<double> noise_db;  // the ambient noise in the band, a constant of the run
  };

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  // Nothing on the rate's ticks: a modem's samples are the packets it decodes.
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static std::optional<double> advance(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Rx::Message& msg);
  // A link per packet travelling towards this modem or arriving at it (sensor_kind.h).
  static void acoustic_links(const SampleContext& context, const Spec& spec, const State& state,
                             std::vector<AcousticLink>& out);

  // The packet's duration on the water: preamble_s + 8 bytes / bit_rate_bps [s].
  static double duration(const Spec& spec, std::size_t payload_bytes);
  // The error curve: the probability that a packet of `payload_bytes` arriving with this SINR is decoded,
  //   (1 - BER(Eb/N0))^(8 bytes),  Eb/N0 [dB] = SINR + 10 log10(bandwidth / bit rate) - implementation_loss_db,
  // BER of the spec's modulation (ModemModulation).
  static double packet_success(const Spec& spec, double sinr_db, std::size_t payload_bytes);
  // Whether two modems can decode each other (same frequency, band, bit rate and modulation) and whether
  // their bands overlap (they interfere).
  static bool same_scheme(const Spec& a, const Spec& b);
  static bool bands_overlap(const Spec& a, const Spec& b);

  // Why a packet for `destination` with `payload_bytes` sent at sim time t from the modem (the sensor `sensor`
  // of `vehicles[vehicle]`) is refused, or "" when send() would queue it. `destination`: "" (every modem), a
  // vehicle (its modems) or "<vehicle>/<modem>".
  static std::string check_send(const std::vector<VehicleSpec>& vehicles, int vehicle, int sensor, const Spec& spec,
                                const State& state, double t, const std::string& destination,
                                std::size_t payload_bytes);
  // Queues the packet (check_send() first: a refusal changes nothing and returns the reason).
  static std::string send(const std::vector<VehicleSpec>& vehicles, int vehicle, int sensor, const Spec& spec,
                          State& state, double t, const std::string& destination, std::vector<std::uint8_t> payload);
};

}  // namespace hadal::sensors
