// The acoustic modem kind alone (no Bullet): several modems on several vehicles sharing the water, stepped as
// the simulation steps them (advance() every step, in vehicle order), against closed forms: a packet arrives at
// the start of its transmission plus the travel time plus its duration; queueing and refusals; the capture rule
// at a receiver between two senders and at one beside a sender; half-duplex; the packet success rate against
// range, inverted through the error curve, within 1 dB of the SNR worked out by hand from the preset; seeds.
#include "hadal/sensors/modem_sensor.h"

#include <gtest/gtest.h>
#include <hadal_msgs.h>

#include <cmath>
#include <string>
#include <vector>

#include "hadal/physics/ocean.h"
#include "hadal/sensors/acoustic_channel.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::SensorTestWorld;

// A vehicle (without geometry) at p_W carrying one modem "modem" 0.5 m above its B origin.
VehicleSpec carrier(const std::string& name, const Eigen::Vector3d& p_W, const ModemSpec& spec) {
  VehicleSpec vehicle = testing::one_vehicle_world(p_W).vehicles[0];
  vehicle.name = name;
  SensorSpec modem;
  modem.name = "modem";
  modem.X_LS = pose(Eigen::Vector3d(0.0, 0.0, 0.5));
  modem.kind = spec;
  vehicle.sensors = {modem};
  return vehicle;
}

// Every vehicle's modems stepped together, as Simulation::sample_sensors steps them.
class Net {
 public:
  explicit Net(Model model, double dt = 0.005) : world(std::move(model)) {
    world.step_size = dt;
    for (std::size_t v = 0; v < world.model.vehicles.size(); ++v) {
      for (const SensorSpec& sensor : world.model.vehicles[v].sensors) {
        SensorState& s = world.state.vehicles[v].sensors.emplace_back();
        s.kind = world.initial_state<ModemSensor>(std::get<ModemSpec>(sensor.kind), 1.0, sensor.name,
                                                  static_cast<int>(v));
      }
    }
    received.resize(world.model.vehicles.size());
    step();  // the first advance only remembers where each modem is
  }

  ModemSensor::State& state(int v) { return std::get<ModemSensor::State>(world.state.vehicles[v].sensors[0].kind); }
  const ModemSpec& spec(int v) { return std::get<ModemSpec>(world.model.vehicles[v].sensors[0].kind); }

  std::string send(int v, const std::string& destination, std::vector<std::uint8_t> payload) {
    return ModemSensor::send(world.model.vehicles, v, 0, spec(v), state(v), world.state.time, destination,
                             std::move(payload));
  }

  void step() {
    world.state.time = static_cast<double>(world.state.step_count) * world.step_size;
    for (std::size_t v = 0; v < world.model.vehicles.size(); ++v) {
      const SensorSpec& sensor = world.model.vehicles[v].sensors[0];
      world.sensor_spec = &sensor;
      const SampleContext context = world.context(sensor.X_LS, 1.0, static_cast<int>(v));
      if (ModemSensor::advance(context, spec(static_cast<int>(v)), state(static_cast<int>(v)))) {
        const auto& delivered = state(static_cast<int>(v)).delivered;
        received[v].insert(received[v].end(), delivered.begin(), delivered.end());
      }
    }
    ++world.state.step_count;
  }
  void run_until(double t) {
    while (world.state.time < t) step();
  }
  Eigen::Vector3d p_W(int v) { return world.body(v).X_WB * world.model.vehicles[v].sensors[0].X_LS.translation(); }

  SensorTestWorld world;
  std::vector<std::vector<ModemPacket>> received;  // per vehicle
};

Model fleet(const std::vector<std::pair<std::string, Eigen::Vector3d>>& where, const ModemSpec& spec = {}) {
  Model model = testing::one_vehicle_world(Eigen::Vector3d::Zero(), -4000.0);
  model.vehicles.clear();
  for (const auto& [name, p_W] : where) model.vehicles.push_back(carrier(name, p_W, spec));
  return model;
}

std::vector<std::uint8_t> bytes(const std::string& text) { return {text.begin(), text.end()}; }

// A vessel's modem sends to an AUV 1.5 km away and 1 km deeper; a lander between them hears it but it is not
// addressed to it. The AUV decodes it at the start of transmission + travel time + duration (1e-9 s), with the
// travel time of the channel, its source, destination, sequence and payload; a broadcast reaches both.
TEST(ModemSensorTest, APacketArrivesAfterTheTravelTimeAndItsDuration) {
  Net net(fleet({{"vessel", {0.0, 0.0, -5.0}}, {"auv", {1500.0, 200.0, -1005.0}}, {"lander", {700.0, 0.0, -2000.0}}}));
  net.run_until(0.1);
  const double t_send = net.world.state.time;
  ASSERT_EQ(net.send(0, "auv", bytes("goto 100 200")), "");
  net.run_until(4.0);
  ASSERT_EQ(net.received[1].size(), 1u);
  EXPECT_TRUE(net.received[2].empty());  // heard, not addressed to it
  const ModemPacket& packet = net.received[1][0];
  const AcousticChannel channel(net.world.ocean, net.world.model.world.acoustics);
  const double travel = channel.travel_time(net.p_W(0), net.p_W(1));
  const double duration = 0.3 + 8.0 * 12.0 / 80.0;
  EXPECT_NEAR(ModemSensor::duration(net.spec(0), 12), duration, 1e-12);
  EXPECT_NEAR(packet.transmit_time, t_send, 1e-12);
  EXPECT_NEAR(packet.travel_time, travel, 1e-9);
  EXPECT_NEAR(packet.stamp, t_send + travel + duration, 1e-9);
  EXPECT_GE(packet.stamp, t_send + travel + duration - 1e-9);
  EXPECT_EQ(packet.source, "vessel/modem");
  EXPECT_EQ(packet.destination, "auv");
  EXPECT_EQ(packet.sequence, 0u);
  EXPECT_EQ(packet.payload, bytes("goto 100 200"));
  EXPECT_GT(packet.snr_db, 10.0);

  ASSERT_EQ(net.send(0, "", bytes("all")), "");
  net.run_until(7.0);
  ASSERT_EQ(net.send(1, "vessel/modem", bytes("ack")), "");  // after "all" has passed everyone
  net.run_until(10.0);
  ASSERT_EQ(net.received[1].size(), 2u);
  ASSERT_EQ(net.received[2].size(), 1u);
  EXPECT_EQ(net.received[2][0].payload, bytes("all"));
  EXPECT_EQ(net.received[1][1].sequence, 1u);
  ASSERT_EQ(net.received[0].size(), 1u);
  EXPECT_EQ(net.received[0][0].source, "auv/modem");
  EXPECT_EQ(net.received[0][0].payload, bytes("ack"));
}

// A moving sender emits from where it is when its packet starts: the vessel at 2 m/s (1 cm per 5 ms step), the
// packet sent between two steps; the reception matches the travel time from that point to 1e-9 s (from the step's
// end it would be ~7e-6 s off).
TEST(ModemSensorTest, AMovingSenderEmitsFromWhereItIsWhenThePacketStarts) {
  Net net(fleet({{"vessel", {0.0, 0.0, -5.0}}, {"auv", {1200.0, 300.0, -805.0}}}));
  // The vessel placed for the time of the step about to be taken (Net::step's time is step_count x dt).
  const auto step = [&] {
    net.world.body(0).X_WB.translation().x() = 2.0 * static_cast<double>(net.world.state.step_count) * net.world.step_size;
    net.step();
  };
  while (net.world.state.time < 0.3) step();
  const double t_send = net.world.state.time;
  const Eigen::Vector3d p_emit(2.0 * t_send, 0.0, -4.5);  // the modem 0.5 m above B
  ASSERT_EQ(net.send(0, "auv", bytes("moving")), "");
  while (net.world.state.time < 4.0) step();
  ASSERT_EQ(net.received[1].size(), 1u);
  const AcousticChannel channel(net.world.ocean, net.world.model.world.acoustics);
  EXPECT_NEAR(net.received[1][0].travel_time, channel.travel_time(p_emit, net.p_W(1)), 1e-9);
}

// Refusals, each with its reason, changing nothing; a send while transmitting waits in the queue and starts when
// the packet before ends (back to back at the receiver too); queue_length 0 refuses it.
TEST(ModemSensorTest, RefusalsAndTheQueue) {
  ModemSpec spec;
  spec.queue_length = 1;
  Net net(fleet({{"vessel", {0.0, 0.0, -5.0}}, {"auv", {800.0, 0.0, -505.0}}}, spec));
  EXPECT_NE(net.send(0, "auv", {}).find("empty payload"), std::string::npos);
  EXPECT_NE(net.send(0, "auv", std::vector<std::uint8_t>(33, 1)).find("longer than the modem's max_payload_bytes (32)"),
            std::string::npos);
  EXPECT_NE(net.send(0, "glider", bytes("x")).find("unknown destination 'glider'"), std::string::npos);
  EXPECT_NE(net.send(0, "auv/usbl", bytes("x")).find("unknown destination"), std::string::npos);
  EXPECT_NE(net.send(0, "vessel", bytes("x")).find("is the sending modem itself"), std::string::npos);
  EXPECT_TRUE(net.state(0).queue.empty());
  ASSERT_EQ(net.send(0, "auv", bytes("one")), "");
  ASSERT_EQ(net.send(0, "auv", bytes("two")), "");  // waits while "one" goes
  const std::string full = net.send(0, "auv", bytes("three"));
  EXPECT_NE(full.find("transmitting"), std::string::npos) << full;
  EXPECT_NE(full.find("queue_length 1"), std::string::npos) << full;
  net.run_until(5.0);
  ASSERT_EQ(net.received[1].size(), 2u);
  const double one = ModemSensor::duration(net.spec(0), 3);
  EXPECT_NEAR(net.received[1][1].transmit_time - net.received[1][0].transmit_time, one, 1e-12);
  EXPECT_NEAR(net.received[1][1].stamp - net.received[1][0].stamp, one, 1e-9);
  EXPECT_EQ(net.received[1][1].payload, bytes("two"));

  ModemSpec no_queue;
  no_queue.queue_length = 0;
  Net busy(fleet({{"vessel", {0.0, 0.0, -5.0}}, {"auv", {800.0, 0.0, -505.0}}}, no_queue));
  ASSERT_EQ(busy.send(0, "auv", bytes("one")), "");
  busy.step();
  EXPECT_NE(busy.send(0, "auv", bytes("two")).find("queue_length 0"), std::string::npos);
}

// A sender's packets follow each other back to back: at a receiver closing in at 3 m/s each next one starts to
// arrive ~0.2 ms before the last one has ended, and still none collides with its predecessor.
TEST(ModemSensorTest, BackToBackPacketsReachAReceiverClosingIn) {
  Net net(fleet({{"vessel", {0.0, 0.0, -5.0}}, {"auv", {900.0, 0.0, -505.0}}}));
  for (const char* text : {"first", "second", "third"}) ASSERT_EQ(net.send(0, "auv", bytes(text)), "");
  while (net.world.state.time < 5.0) {
    net.world.body(1).X_WB.translation().x() = 900.0 - 3.0 * net.world.state.time;
    net.step();
  }
  ASSERT_EQ(net.received[1].size(), 3u);
  EXPECT_EQ(net.received[1][2].payload, bytes("third"));
  EXPECT_EQ(net.state(1).tally.lost_collision, 0u);
  EXPECT_LT(net.received[1][1].travel_time, net.received[1][0].travel_time);
}

// Two senders 2 km apart send equal 20-byte packets (2.3 s) at the same time. At a receiver midway they arrive
// together at equal levels: SIR 0 dB < the capture threshold, both lost. A receiver 20 m from one sender hears
// that one from 0.01 s and the other from 1.3 s, overlapping, ~40 dB weaker: it keeps the near one and loses the
// other. Sent apart in time, the midway receiver decodes both.
TEST(ModemSensorTest, OverlappingPacketsCollideBetweenTheSendersNotBesideOne) {
  const auto net_of = [] {
    return Net(fleet({{"a", {-1000.0, 0.0, -1000.0}},
                      {"b", {1000.0, 0.0, -1000.0}},
                      {"middle", {0.0, 0.0, -1000.0}},
                      {"beside_a", {-980.0, 0.0, -1000.0}}}));
  };
  Net together = net_of();
  together.step();
  ASSERT_EQ(together.send(0, "", bytes("from a .............")), "");
  ASSERT_EQ(together.send(1, "", bytes("from b .............")), "");
  together.run_until(5.0);
  EXPECT_TRUE(together.received[2].empty());
  EXPECT_EQ(together.state(2).tally.lost_collision, 2u);
  ASSERT_EQ(together.received[3].size(), 1u);
  EXPECT_EQ(together.received[3][0].payload, bytes("from a ............."));
  EXPECT_EQ(together.state(3).tally.lost_collision, 1u);

  Net apart = net_of();
  apart.step();
  ASSERT_EQ(apart.send(0, "", bytes("from a .............")), "");
  apart.run_until(3.5);  // "from a" (2.3 s) has passed the middle (0.67 s away) before "from b" starts
  ASSERT_EQ(apart.send(1, "", bytes("from b .............")), "");
  apart.run_until(8.0);
  ASSERT_EQ(apart.received[2].size(), 2u);
  EXPECT_EQ(apart.state(2).tally.lost_collision, 0u);
}

// Half-duplex: a modem that transmits while a packet arrives loses it; the same packet is decoded when it is quiet.
TEST(ModemSensorTest, AModemDoesNotHearWhileItSends) {
  // (packets decoded by the AUV, packets it lost to its own transmission)
  const auto run = [](bool reply_early) -> std::pair<std::size_t, std::uint64_t> {
    Net net(fleet({{"vessel", {0.0, 0.0, -5.0}}, {"auv", {1500.0, 0.0, -5.0}}}));
    net.step();
    EXPECT_EQ(net.send(0, "auv", bytes("0123456789")), "");  // arrives at the AUV after ~1 s, for 1.3 s
    net.run_until(1.5);
    if (reply_early) {
      EXPECT_EQ(net.send(1, "vessel", bytes("status")), "");  // sent while it arrives
    }
    net.run_until(4.0);
    return {net.received[1].size(), net.state(1).tally.lost_half_duplex};
  };
  EXPECT_EQ(run(false), (std::pair<std::size_t, std::uint64_t>(1, 0)));
  EXPECT_EQ(run(true), (std::pair<std::size_t, std::uint64_t>(0, 1)));
}

// The packet success rate against range follows the preset's error curve at the SNR worked out by hand,
//   SNR = SL - (20 log10 r + alpha r) - NL
// (alpha: Francois–Garrison at the modems' depth and the band centre; NL: the Wenz noise in the band): the rate
// measured over 300 packets at each of three ranges, inverted through packet_success(), lands within 1 dB of it
// (300 packets: the rate's standard error <= 0.03, ~0.15 dB on the curve's slope near one half).
TEST(ModemSensorTest, PacketSuccessAgainstRangeFollowsTheHandSnr) {
  const ModemSpec spec;  // the WHOI Micro-Modem's FH-FSK
  const double depth = 1000.0;
  const std::size_t payload = 10;
  Model model = fleet({{"sender", {0.0, 0.0, -depth - 0.5}}});
  const physics::Ocean ocean(model.world);
  const double alpha = ocean.sound_absorption_db_per_m(depth, spec.frequency_hz);
  const double noise = ambient_noise_level_db(spec.frequency_hz, spec.bandwidth_hz, model.world.acoustics.ambient_noise);
  const auto hand_snr = [&](double r) { return spec.source_level_db - 20.0 * std::log10(r) - alpha * r - noise; };
  const auto range_for = [&](double snr) {  // bisection: the SNR falls with range
    double lo = 10.0, hi = 100000.0;
    for (int i = 0; i < 200; ++i) ((hand_snr(0.5 * (lo + hi)) > snr) ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi);
  };
  const auto snr_for = [&](double success) {  // the curve's inverse: it rises with SNR
    double lo = -40.0, hi = 40.0;
    for (int i = 0; i < 200; ++i) ((ModemSensor::packet_success(spec, 0.5 * (lo + hi), payload) < success) ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi);
  };
  const std::vector<double> snrs = {-5.8, -4.9, -4.0};
  ModemSpec far = spec;
  far.max_range = 30000.0;
  model.vehicles[0].sensors[0].kind = far;
  for (std::size_t i = 0; i < snrs.size(); ++i) {
    const double r = range_for(snrs[i]);
    const double azimuth = 2.0 * static_cast<double>(i);
    model.vehicles.push_back(
        carrier("r" + std::to_string(i), {r * std::cos(azimuth), r * std::sin(azimuth), -depth - 0.5}, far));
  }
  Net net(model, 0.02);
  const int packets = 300;
  for (int k = 0; k < packets; ++k) {
    ASSERT_EQ(net.send(0, "", std::vector<std::uint8_t>(payload, static_cast<std::uint8_t>(k))), "");
    net.run_until(net.world.state.time + 1.5);  // one packet lasts 1.3 s
  }
  net.run_until(net.world.state.time + 15.0);
  for (std::size_t i = 0; i < snrs.size(); ++i) {
    const double rate = static_cast<double>(net.received[i + 1].size()) / packets;
    ASSERT_GT(rate, 0.05) << i;
    ASSERT_LT(rate, 0.95) << i;
    EXPECT_NEAR(snr_for(rate), snrs[i], 1.0) << "range " << range_for(snrs[i]) << " m, success " << rate;
    for (const ModemPacket& p : net.received[i + 1]) EXPECT_NEAR(p.snr_db, snrs[i], 0.05);
  }
}

// The error curve itself: FSK at Eb/N0 = SNR + 10 log10(B / R) - loss, BER = exp(-g/2)/2, 8 bits a byte; PSK's
// erfc; more bytes, lower success.
TEST(ModemSensorTest, TheErrorCurveIsTheModulationsBitErrorRateOverThePacket) {
  ModemSpec spec;
  const double g = std::pow(10.0, (-4.0 + 10.0 * std::log10(4000.0 / 80.0) - 3.0) / 10.0);
  EXPECT_NEAR(ModemSensor::packet_success(spec, -4.0, 10), std::pow(1.0 - 0.5 * std::exp(-0.5 * g), 80.0), 1e-12);
  EXPECT_LT(ModemSensor::packet_success(spec, -4.0, 32), ModemSensor::packet_success(spec, -4.0, 10));
  spec.modulation = ModemModulation::kPsk;
  EXPECT_NEAR(ModemSensor::packet_success(spec, -4.0, 10), std::pow(1.0 - 0.5 * std::erfc(std::sqrt(g)), 80.0), 1e-12);
}

// Same seed, same packets decided the same way; another seed, other draws.
TEST(ModemSensorTest, SameSeedSamePackets) {
  const auto run = [](std::uint64_t seed) {
    Model model = fleet({{"a", {0.0, 0.0, -1000.0}}, {"b", {7600.0, 0.0, -1000.0}}});
    model.world.seed = seed;
    Net net(model, 0.02);
    for (int k = 0; k < 40; ++k) {
      EXPECT_EQ(net.send(0, "b", std::vector<std::uint8_t>(10, static_cast<std::uint8_t>(k))), "");
      net.run_until(net.world.state.time + 1.5);
    }
    net.run_until(net.world.state.time + 10.0);
    std::vector<std::uint64_t> got;
    for (const ModemPacket& p : net.received[1]) got.push_back(p.sequence);
    return got;
  };
  const std::vector<std::uint64_t> first = run(7);
  EXPECT_GT(first.size(), 3u);
  EXPECT_LT(first.size(), 37u);
  EXPECT_EQ(run(7), first);
  EXPECT_NE(run(8), first);
}

// The message carries every packet of the step with its fields.
TEST(ModemSensorTest, MessageCarriesThePackets) {
  ModemSensor::State state;
  ModemPacket& p = state.delivered.emplace_back();
  p.transmit_time = 1.25;
  p.stamp = 3.5;
  p.source = "vessel/modem";
  p.destination = "auv";
  p.sequence = 4;
  p.payload = bytes("hi");
  p.travel_time = 1.0;
  p.snr_db = 12.5;
  hadal_msgs::msg::AcousticPackets msg;
  const std::string frame = "auv/modem";
  ModemSensor::fill_message(ModemSpec{}, state, MessageHeader{3.5, frame, 1.0}, msg);
  ASSERT_EQ(msg.packets().size(), 1u);
  EXPECT_EQ(msg.header().frame_id(), frame);
  EXPECT_EQ(msg.packets()[0].source(), "vessel/modem");
  EXPECT_EQ(msg.packets()[0].destination(), "auv");
  EXPECT_EQ(msg.packets()[0].sequence_number(), 4u);
  EXPECT_EQ(msg.packets()[0].payload(), bytes("hi"));
  EXPECT_EQ(msg.packets()[0].transmit_stamp().sec(), 1);
  EXPECT_EQ(msg.packets()[0].transmit_stamp().nanosec(), 250000000u);
  EXPECT_DOUBLE_EQ(msg.packets()[0].snr_db(), 12.5);
}

// What is in flight, for monitors (acoustic_links): each receiver lists the packet from where it left until it has
// all arrived, with its duration; then nothing.
TEST(ModemSensorTest, LinksFollowEachPacketToEachReceiver) {
  Net net(fleet({{"vessel", {0.0, 0.0, -5.0}}, {"auv", {1500.0, 0.0, -1005.0}}, {"lander", {700.0, 0.0, -2000.0}}}));
  net.run_until(0.1);
  const double t_send = net.world.state.time;
  ASSERT_EQ(net.send(0, "auv", bytes("goto")), "");
  const auto links = [&](int v) {
    std::vector<AcousticLink> out;
    const SensorSpec& sensor = net.world.model.vehicles[static_cast<std::size_t>(v)].sensors[0];
    net.world.sensor_spec = &sensor;
    ModemSensor::acoustic_links(net.world.context(sensor.X_LS, 1.0, v), net.spec(v), net.state(v), out);
    return out;
  };
  net.run_until(0.5);
  for (const int v : {1, 2}) {  // the lander hears it too, though it is not for it
    const std::vector<AcousticLink> in_flight = links(v);
    ASSERT_EQ(in_flight.size(), 1u) << v;
    EXPECT_EQ(in_flight[0].kind, AcousticLink::Kind::kPacket);
    EXPECT_EQ(in_flight[0].source, "vessel/modem");
    EXPECT_EQ(in_flight[0].target, v == 1 ? "auv/modem" : "lander/modem");
    EXPECT_NEAR(in_flight[0].emit_time, t_send, 1e-12);
    EXPECT_NEAR(in_flight[0].duration, ModemSensor::duration(net.spec(0), 4), 1e-12);
    EXPECT_TRUE(in_flight[0].p_Wemit.isApprox(net.p_W(0), 1e-12));
    EXPECT_TRUE(in_flight[0].p_Wtarget.isApprox(net.p_W(v), 1e-12));
  }
  EXPECT_TRUE(links(0).empty());
  net.run_until(4.0);
  EXPECT_TRUE(links(1).empty());
  EXPECT_TRUE(links(2).empty());
}

}  // namespace
}  // namespace hadal::sensors
