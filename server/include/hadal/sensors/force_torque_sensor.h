// Force/torque sensor (YAML `type: force_torque`, geometry_msgs/WrenchStamped): the wrench across the joint
// of the link it is on (a link on a moving joint of an articulated vehicle), in the sensor frame S about
// S's origin. The simulation finds each such joint's wrench from the step that ends at the sample
// (VehicleState::joint_wrenches_L, physics/articulated_dynamics.h: Newton-Euler over everything beyond the
// joint, with the contacts Bullet applied); the sensor moves it from the joint (L's origin) to S,
//   F_S = R_SL F_L,   N_S = R_SL (N_L - p_LS x F_L),
// turns it round for child_to_parent (the default: what the link and its load put on the parent, so a
// hanging load reads its wet weight along gravity), then adds per axis a zero offset drawn per run and
// white noise per sample, quantises and clips (sensors/noise.h, channels "force" and "torque"). The
// motor's torque about the axis is part of the wrench, as in an ATI sensor between two links.
// YAML keys: ForceTorqueSensor::keys() (server/src/sensors/force_torque_sensor.cc).
#pragma once

#include <Eigen/Core>

#include <string_view>

#include "hadal/sensors/force_torque_spec.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sensor_kind.h"

namespace geometry_msgs::msg {
class WrenchStamped;
class WrenchStampedPubSubType;
}  // namespace geometry_msgs::msg

namespace hadal::sensors {

struct ForceTorqueSensor {
  static constexpr std::string_view kType = "force_torque";
  static constexpr bool kCastsRays = false;
  static constexpr bool kCaptures = false;
  static constexpr bool kOnJoint = true;
  using Message = geometry_msgs::msg::WrenchStamped;
  using PubSubType = geometry_msgs::msg::WrenchStampedPubSubType;

  using Spec = ForceTorqueSpec;
  struct State {
    NoiseTriadState force_noise, torque_noise;
    Eigen::Vector3d force_S = Eigen::Vector3d::Zero();   // last sample [N]
    Eigen::Vector3d torque_S = Eigen::Vector3d::Zero();  // [N m], about S's origin
  };

  static NoiseTriadParams force_channel(const Spec& spec, double period);
  static NoiseTriadParams torque_channel(const Spec& spec, double period);
  // The ideal reading in S from the joint's wrench in L (parent on child, about L's origin).
  static void ideal(const Spec& spec, const Eigen::Isometry3d& X_LS, const Eigen::Matrix<double, 6, 1>& wrench_L,
                    Eigen::Vector3d& force_S, Eigen::Vector3d& torque_S);

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static void sample(const SampleContext& context, const Spec& spec, State& state);
  static void fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
};

}  // namespace hadal::sensors
