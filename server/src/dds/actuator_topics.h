// The state topics of the actuator kinds: a kind with an ActuatorStateTopic below publishes
// rt/<vehicle>/<kListKey>/state (thrusters/state, tracks/state, fins/state, ...) for each vehicle that has
// one of it -- or, with kEveryVehicle, for every vehicle (the thrusters': its command_source says whether
// a client or the schedule commands the vehicle, also one without thrusters) -- one entry per actuator of
// the kind in actuator order, at the vehicle's actuator_state_rate_hz. The message has a header, `name`
// and `command_source`, plus per-actuator sequences that clear() and append() fill. Adding a kind's
// topic: its message in idl/hadal_msgs.idl (and the ROS 2 mirror under idl/ros2/), a specialisation here,
// its client accessors.
#pragma once

#include <hadal_msgs.h>
#include <hadal_msgsPubSubTypes.h>

#include <string>
#include <type_traits>
#include <variant>

#include "hadal/core/model.h"
#include "hadal/core/state.h"
#include "hadal/dds/time_msg.h"
#include "hadal/dds/topic_names.h"
#include "hadal/physics/actuator_kinds.h"

namespace hadal::dds {

// A kind without a state topic of its own.
template <class K>
struct ActuatorStateTopic {
  static constexpr bool kPublished = false;
};

template <>
struct ActuatorStateTopic<physics::ThrusterActuator> {
  static constexpr bool kPublished = true;
  static constexpr bool kEveryVehicle = true;
  using Message = hadal_msgs::msg::ThrusterState;
  using PubSubType = hadal_msgs::msg::ThrusterStatePubSubType;
  static void clear(Message& m) {
    for (auto* f : {&m.setpoint(), &m.rotor_speed(), &m.thrust(), &m.torque()}) f->clear();
  }
  static void append(const physics::ThrusterActuator::State& s, Message& m) {
    m.setpoint().push_back(s.setpoint);
    m.rotor_speed().push_back(s.rotor_speed_rev_s);
    m.thrust().push_back(s.thrust_N);
    m.torque().push_back(s.torque_Nm);
  }
};

template <>
struct ActuatorStateTopic<physics::TrackActuator> {
  static constexpr bool kPublished = true;
  using Message = hadal_msgs::msg::TrackState;
  using PubSubType = hadal_msgs::msg::TrackStatePubSubType;
  static void clear(Message& m) {
    for (auto* f : {&m.setpoint(), &m.belt_speed(), &m.sprocket_speed(), &m.motor_torque(), &m.current(), &m.power(),
                    &m.load()}) {
      f->clear();
    }
  }
  static void append(const physics::TrackActuator::State& s, Message& m) {
    m.setpoint().push_back(s.setpoint);
    m.belt_speed().push_back(s.belt_speed);
    m.sprocket_speed().push_back(s.sprocket_speed);
    m.motor_torque().push_back(s.motor_torque_Nm);
    m.current().push_back(s.current_A);
    m.power().push_back(s.power_W);
    m.load().push_back(s.load_N);
  }
};

template <>
struct ActuatorStateTopic<physics::FinActuator> {
  static constexpr bool kPublished = true;
  using Message = hadal_msgs::msg::FinState;
  using PubSubType = hadal_msgs::msg::FinStatePubSubType;
  static void clear(Message& m) {
    for (auto* f : {&m.setpoint(), &m.angle(), &m.attack_angle(), &m.lift(), &m.drag()}) f->clear();
  }
  static void append(const physics::FinActuator::State& s, Message& m) {
    m.setpoint().push_back(s.setpoint);
    m.angle().push_back(s.angle);
    m.attack_angle().push_back(s.attack_angle);
    m.lift().push_back(s.lift_N);
    m.drag().push_back(s.drag_N);
  }
};

template <>
struct ActuatorStateTopic<physics::BuoyancyEngineActuator> {
  static constexpr bool kPublished = true;
  using Message = hadal_msgs::msg::BuoyancyEngineState;
  using PubSubType = hadal_msgs::msg::BuoyancyEngineStatePubSubType;
  static void clear(Message& m) {
    for (auto* f : {&m.setpoint(), &m.volume_change(), &m.volume_rate(), &m.force(), &m.power(), &m.energy()}) {
      f->clear();
    }
  }
  static void append(const physics::BuoyancyEngineActuator::State& s, Message& m) {
    m.setpoint().push_back(s.setpoint);
    m.volume_change().push_back(s.volume_change);
    m.volume_rate().push_back(s.volume_rate);
    m.force().push_back(s.force_N);
    m.power().push_back(s.power_W);
    m.energy().push_back(s.energy_J);
  }
};

template <>
struct ActuatorStateTopic<physics::DropWeightActuator> {
  static constexpr bool kPublished = true;
  using Message = hadal_msgs::msg::DropWeightState;
  using PubSubType = hadal_msgs::msg::DropWeightStatePubSubType;
  static void clear(Message& m) {
    m.attached().clear();
    m.reason().clear();
    m.release_time().clear();
    m.force().clear();
  }
  static void append(const physics::DropWeightActuator::State& s, Message& m) {
    m.attached().push_back(s.attached());
    m.reason().push_back(static_cast<std::uint8_t>(s.reason));
    m.release_time().push_back(s.release_time);
    m.force().push_back(s.force_N);
  }
};

// Whether kind K's state topic is published for every vehicle (kEveryVehicle), not only those with one.
template <class K, class = void>
struct PublishedForEveryVehicle : std::false_type {};
template <class K>
struct PublishedForEveryVehicle<K, std::void_t<decltype(ActuatorStateTopic<K>::kEveryVehicle)>>
    : std::bool_constant<ActuatorStateTopic<K>::kEveryVehicle> {};

// Whether `vehicle` publishes kind K's state topic: it has an actuator of kind K, or K's is published for
// every vehicle (but an object: it has no actuators and takes no commands).
template <class K>
bool publishes_state_of_kind(const VehicleSpec& vehicle) {
  if (vehicle.type == VehicleType::kObject) return false;
  if (PublishedForEveryVehicle<K>::value) return true;
  for (const ActuatorSpec& actuator : vehicle.actuators) {
    if (std::holds_alternative<typename K::Spec>(actuator.kind)) return true;
  }
  return false;
}

// The vehicle's actuators of kind K, in actuator order.
template <class K>
void fill_actuator_state(const VehicleSpec& spec, const VehicleState& state, double time_s,
                         typename ActuatorStateTopic<K>::Message& msg) {
  msg.header().stamp(to_time_msg(time_s));
  msg.header().frame_id(base_frame_id(spec.name));
  msg.name().clear();
  ActuatorStateTopic<K>::clear(msg);
  for (std::size_t k = 0; k < state.actuators.size(); ++k) {
    const auto* actuator = std::get_if<typename K::State>(&state.actuators[k]);
    if (actuator == nullptr) continue;
    msg.name().push_back(spec.actuators[k].name);
    ActuatorStateTopic<K>::append(*actuator, msg);
  }
  msg.command_source(static_cast<std::uint8_t>(state.command_source));
}

}  // namespace hadal::dds
