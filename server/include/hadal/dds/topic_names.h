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
inline std::string odometry_topic(const std::string& vehicle) { return "rt/" + vehicle + "/odometry"; }
// A sensor's samples (sensor_msgs/..., marine_acoustic_msgs/Dvl).
inline std::string sensor_topic(const std::string& vehicle, const std::string& sensor) {
  return "rt/" + vehicle + "/" + sensor;
}
inline std::string thruster_setpoints_topic(const std::string& vehicle) {
  return "rt/" + vehicle + "/thrusters/setpoints";
}
inline std::string thruster_state_topic(const std::string& vehicle) {
  return "rt/" + vehicle + "/thrusters/state";
}
// The state of a vehicle's actuators of one kind besides thrusters, by the kind's YAML list key:
// rt/<vehicle>/tracks/state, fins/state, buoyancy_engines/state, drop_weights/state.
inline std::string actuator_state_topic(const std::string& vehicle, std::string_view list_key) {
  return "rt/" + vehicle + "/" + std::string(list_key) + "/state";
}
// Frame id of a vehicle's body frame B in message headers (REP-105 style).
inline std::string base_frame_id(const std::string& vehicle) { return vehicle + "/base_link"; }

}  // namespace hadal::dds
