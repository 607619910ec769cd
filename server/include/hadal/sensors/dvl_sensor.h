// Doppler velocity log (YAML `type: dvl`, marine_acoustic_msgs/Dvl): four Janus beams in the sensor
// frame S (z along the DVL's axis, the way the transducers look: mount a downward DVL with S's z down),
// ray-cast each ping from the sensor's origin into the world (seabed and other vehicles; its own vehicle
// is transparent), then sensors/dvl.h: bottom lock within the altitude window, dropouts, 3- or 4-beam
// least squares, the paper's bias drift, water track over the current averaged in a layer along each
// beam, sound-speed scale error. The velocity is that of the sensor's origin over the ground (lever arm
// included), in S.
// YAML keys: DvlSensor::keys() (server/src/sensors/dvl_sensor.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/sensors/dvl.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/dvl_spec.h"

namespace marine_acoustic_msgs::msg {
class Dvl;
class DvlPubSubType;
}  // namespace marine_acoustic_msgs::msg

namespace hadal::sensors {

struct DvlSensor {
  static constexpr std::string_view kType = "dvl";
  static constexpr bool kCastsRays = true;
  static constexpr bool kCaptures = false;
  static constexpr bool kOnMovingLink = false;  // its beams' velocities are the body's
  using Message = marine_acoustic_msgs::msg::Dvl;
  using PubSubType = marine_acoustic_msgs::msg::DvlPubSubType;

  using Spec = DvlSpec;
  struct State {
    DvlState dvl;  // bias, dropout and per-beam noise
    DvlPing ping;  // the last ping
  };

  // Rays stop where a return could no longer change the ping: past the bottom-lock window and the
  // water-track layer's far edge, along a tilted beam [m].
  static double ray_length(const Spec& spec);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

}  // namespace hadal::sensors
