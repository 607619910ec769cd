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
  const std::size_t n = spec.thrusters.size();
  msg.name().resize(n);
  msg.setpoint().resize(n);
  msg.rotor_speed().resize(n);
  msg.thrust().resize(n);
  msg.torque().resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    msg.name()[i] = spec.thrusters[i].name;
    msg.setpoint()[i] = state.thrusters[i].setpoint;
    msg.rotor_speed()[i] = state.thrusters[i].rotor_speed;
    msg.thrust()[i] = state.thrusters[i].thrust;
    msg.torque()[i] = state.thrusters[i].torque;
  }
  msg.command_source(static_cast<std::uint8_t>(state.command_source));
}

}  // namespace hadal::dds
