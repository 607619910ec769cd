#include "message_conversion.h"

#include <limits>

#include "hadal/dds/topic_names.h"


namespace hadal::dds {

void fill_odometry(const std::string& world_frame_id, const std::string& vehicle_name, double time_s,
                   const RigidBodyState& body, nav_msgs::msg::Odometry& msg) {
  msg.header().stamp(to_time_msg(time_s));
  msg.header().frame_id(world_frame_id);
  msg.child_frame_id(base_frame_id(vehicle_name));

  const Eigen::Vector3d& p_WB = body.X_WB.translation();
  const Eigen::Matrix3d R_WB = body.X_WB.rotation();
  const Eigen::Quaterniond q_WB(R_WB);
  auto& pose = msg.pose().pose();
  pose.position().x(p_WB.x());
  pose.position().y(p_WB.y());
  pose.position().z(p_WB.z());
  pose.orientation().x(q_WB.x());
  pose.orientation().y(q_WB.y());
  pose.orientation().z(q_WB.z());
  pose.orientation().w(q_WB.w());

  const Eigen::Vector3d v_WB_B = R_WB.transpose() * body.v_WB;
  const Eigen::Vector3d w_WB_B = R_WB.transpose() * body.w_WB;
  auto& twist = msg.twist().twist();
  twist.linear().x(v_WB_B.x());
  twist.linear().y(v_WB_B.y());
  twist.linear().z(v_WB_B.z());
  twist.angular().x(w_WB_B.x());
  twist.angular().y(w_WB_B.y());
  twist.angular().z(w_WB_B.z());
}

void fill_thruster_state(const VehicleSpec& spec, const VehicleState& state, double time_s,
                         hadal_msgs::msg::ThrusterState& msg) {
  msg.header().stamp(to_time_msg(time_s));
  msg.header().frame_id(base_frame_id(spec.name));
  std::size_t n = 0;
  for (const physics::ActuatorKindState& actuator : state.actuators) {
    n += std::holds_alternative<physics::ThrusterActuator::State>(actuator) ? 1 : 0;
  }
  msg.name().resize(n);
  msg.setpoint().resize(n);
  msg.rotor_speed().resize(n);
  msg.thrust().resize(n);
  msg.torque().resize(n);
  std::size_t i = 0;
  for (std::size_t k = 0; k < state.actuators.size(); ++k) {
    const auto* thruster = std::get_if<physics::ThrusterActuator::State>(&state.actuators[k]);
    if (thruster == nullptr) continue;
    msg.name()[i] = spec.actuators[k].name;
    msg.setpoint()[i] = thruster->setpoint;
    msg.rotor_speed()[i] = thruster->rotor_speed_rev_s;
    msg.thrust()[i] = thruster->thrust_N;
    msg.torque()[i] = thruster->torque_Nm;
    ++i;
  }
  msg.command_source(static_cast<std::uint8_t>(state.command_source));
}

}  // namespace hadal::dds
