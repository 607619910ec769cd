// DDS topic names, following ROS 2's conventions: DDS topic = "rt/" + ROS topic without the leading
// slash, so ROS 2 nodes subscribe to /clock, /<vehicle>/odometry ... with no bridge.
#pragma once

#include <string>
#include <string_view>

namespace hadal::dds {

inline std::string clock_topic() { return "rt/clock"; }
inline std::string status_topic() { return "rt/hadal/status"; }
inline std::string step_request_topic() { return "rt/hadal/step_request"; }
inline std::string step_reply_topic() { return "rt/hadal/step_reply"; }
inline std::string scene_topic() { return "rt/hadal/scene"; }
// The latest sample of each light topic in one message, at most 20 per wall second while read (Monitor).
inline std::string monitor_topic() { return "rt/hadal/monitor"; }
// Every acoustic signal in flight (AcousticLinks), at most 20 per wall second while it or the monitor is read.
inline std::string acoustic_links_topic() { return "rt/hadal/acoustic_links"; }
inline std::string odometry_topic(const std::string& vehicle) { return "rt/" + vehicle + "/odometry"; }
// An articulated vehicle's joints (sensor_msgs/JointState), at the odometry rate.
inline std::string joint_states_topic(const std::string& vehicle) { return "rt/" + vehicle + "/joint_states"; }
// A sensor's samples (sensor_msgs/..., marine_acoustic_msgs/Dvl).
inline std::string sensor_topic(const std::string& vehicle, const std::string& sensor) {
  return "rt/" + vehicle + "/" + sensor;
}
// A joint controller's commands (std_msgs/Float64MultiArray, one value per joint of the group).
inline std::string joint_commands_topic(const std::string& vehicle, const std::string& controller) {
  return "rt/" + vehicle + "/" + controller + "/commands";
}
// A position group's trajectories (trajectory_msgs/JointTrajectory), as ros2_control's
// joint_trajectory_controller reads them.
inline std::string joint_trajectory_topic(const std::string& vehicle, const std::string& controller) {
  return "rt/" + vehicle + "/" + controller + "/joint_trajectory";
}
// What a client gives an acoustic modem to send (hadal_msgs/AcousticPacket); it publishes what it decodes on
// sensor_topic(vehicle, modem) + "/rx".
inline std::string modem_tx_topic(const std::string& vehicle, const std::string& modem) {
  return "rt/" + vehicle + "/" + modem + "/tx";
}
// A cable's topics (physics/cable.h): the force it puts on what holds each end (geometry_msgs/WrenchStamped,
// `end` "from" or "to") and its shape (nav_msgs/Path, its nodes from `from` to `to`), in W.
inline std::string cable_tension_topic(const std::string& cable, const std::string& end) {
  return "rt/hadal/cables/" + cable + "/" + end;
}
inline std::string cable_shape_topic(const std::string& cable) { return "rt/hadal/cables/" + cable + "/shape"; }
// A cable's winch: its commands (hadal_msgs/WinchCommand, read) and its state (hadal_msgs/WinchState).
inline std::string winch_command_topic(const std::string& cable) {
  return "rt/hadal/cables/" + cable + "/winch/command";
}
inline std::string winch_state_topic(const std::string& cable) { return "rt/hadal/cables/" + cable + "/winch/state"; }
// The sea at a vehicle (hadal_msgs/SeaState), when the scenario has waves.
inline std::string sea_state_topic(const std::string& vehicle) { return "rt/" + vehicle + "/sea_state"; }
inline std::string actuator_commands_topic(const std::string& vehicle) {
  return "rt/" + vehicle + "/actuators/commands";
}
// The state of a vehicle's actuators of one kind, by the kind's YAML list key: rt/<vehicle>/thrusters/state,
// tracks/state, fins/state, buoyancy_engines/state, drop_weights/state.
inline std::string actuator_state_topic(const std::string& vehicle, std::string_view list_key) {
  return "rt/" + vehicle + "/" + std::string(list_key) + "/state";
}
// Frame id of a vehicle's body frame B in message headers (REP-105 style).
inline std::string base_frame_id(const std::string& vehicle) { return vehicle + "/base_link"; }

// DDS names to ROS 2's: "rt/auv/odometry" -> "/auv/odometry", "nav_msgs::msg::dds_::Odometry_" ->
// "nav_msgs/msg/Odometry". Return false (and leave the outputs alone) for names that do not follow
// ROS 2's DDS conventions.
inline bool ros_topic_name(const std::string& dds_topic, std::string* ros_topic) {
  if (dds_topic.size() < 4 || dds_topic.compare(0, 3, "rt/") != 0) return false;
  *ros_topic = dds_topic.substr(2);
  return true;
}
inline bool ros_type_name(const std::string& dds_type, std::string* ros_type) {
  // pkg::msg::dds_::Type_ (also srv, action)
  const auto first = dds_type.find("::");
  if (first == std::string::npos || first == 0) return false;
  const auto second = dds_type.find("::", first + 2);
  if (second == std::string::npos) return false;
  const std::string kind = dds_type.substr(first + 2, second - first - 2);
  const std::string rest = dds_type.substr(second + 2);
  if (rest.compare(0, 6, "dds_::") != 0 || rest.size() < 8 || rest.back() != '_') return false;
  const std::string type = rest.substr(6, rest.size() - 7);
  if (type.find("::") != std::string::npos) return false;
  *ros_type = dds_type.substr(0, first) + "/" + kind + "/" + type;
  return true;
}

}  // namespace hadal::dds
