#include "message_conversion.h"

#include <algorithm>
#include <limits>

#include "hadal/dds/topic_names.h"


namespace hadal::dds {

OdometryValues odometry_values(const RigidBodyState& body) {
  const Eigen::Matrix3d R_WB = body.X_WB.rotation();
  return {body.X_WB.translation(), Eigen::Quaterniond(R_WB), R_WB.transpose() * body.v_WB,
          R_WB.transpose() * body.w_WB};
}

void fill_sea_state(const std::string& world_frame_id, double time_s, const physics::Waves& waves,
                    const physics::WaveSpec& spec, const Eigen::Vector3d& p_W, hadal_msgs::msg::SeaState& msg) {
  msg.header().stamp(to_time_msg(time_s));
  msg.header().frame_id(world_frame_id);
  const physics::WaveKinematics k = waves.kinematics(p_W, time_s);
  msg.surface_z_m(k.surface_height);
  msg.surface_slope_x(k.slope.x());
  msg.surface_slope_y(k.slope.y());
  msg.depth_m(k.surface_height - p_W.z());
  msg.orbital_velocity().x(k.velocity_W.x());
  msg.orbital_velocity().y(k.velocity_W.y());
  msg.orbital_velocity().z(k.velocity_W.z());
  msg.significant_height_m(waves.significant_height());
  double period = spec.peak_period, direction = spec.direction, largest = 0.0;
  if (spec.spectrum == physics::WaveSpectrum::kRegular) {
    period = 0.0;
    for (const physics::WaveComponentSpec& c : spec.regular) {
      if (c.amplitude > 0.0) period = std::max(period, c.period);
      if (c.amplitude > largest) largest = c.amplitude, direction = c.direction;
    }
  }
  msg.peak_period_s(period);
  msg.mean_direction_rad(direction);
  msg.build_up(waves.ramp(time_s));
}

void fill_odometry(const std::string& world_frame_id, const std::string& vehicle_name, double time_s,
                   const RigidBodyState& body, nav_msgs::msg::Odometry& msg) {
  msg.header().stamp(to_time_msg(time_s));
  msg.header().frame_id(world_frame_id);
  msg.child_frame_id(base_frame_id(vehicle_name));
  const OdometryValues o = odometry_values(body);
  auto& pose = msg.pose().pose();
  pose.position().x(o.p_WB.x());
  pose.position().y(o.p_WB.y());
  pose.position().z(o.p_WB.z());
  pose.orientation().x(o.q_WB.x());
  pose.orientation().y(o.q_WB.y());
  pose.orientation().z(o.q_WB.z());
  pose.orientation().w(o.q_WB.w());
  auto& twist = msg.twist().twist();
  twist.linear().x(o.v_WB_B.x());
  twist.linear().y(o.v_WB_B.y());
  twist.linear().z(o.v_WB_B.z());
  twist.angular().x(o.w_WB_B.x());
  twist.angular().y(o.w_WB_B.y());
  twist.angular().z(o.w_WB_B.z());
}

JointStateLayout joint_state_layout(const VehicleSpec& vehicle) {
  JointStateLayout out;
  for (const LinkSpec& link : vehicle.links) {
    if (link.joint.type != JointType::kFixed) out.names.push_back(joint_name(link));
  }
  for (const LinkSpec& link : vehicle.links) {
    if (link.joint.locked_type == JointType::kFixed) continue;
    out.names.push_back(joint_name(link));
    out.locked_positions.push_back(link.joint.lower);
  }
  return out;
}

void fill_joint_state(const JointStateLayout& joints, const std::string& vehicle_name, double time_s,
                      const VehicleState& vehicle, sensor_msgs::msg::JointState& msg) {
  msg.header().stamp(to_time_msg(time_s));
  msg.header().frame_id(base_frame_id(vehicle_name));
  msg.name(joints.names);
  const std::size_t locked = joints.locked_positions.size();
  msg.position().assign(vehicle.joint_positions.begin(), vehicle.joint_positions.end());
  msg.position().insert(msg.position().end(), joints.locked_positions.begin(), joints.locked_positions.end());
  msg.velocity().assign(vehicle.joint_velocities.begin(), vehicle.joint_velocities.end());
  msg.velocity().resize(msg.velocity().size() + locked, 0.0);
  msg.effort().assign(vehicle.joint_efforts.begin(), vehicle.joint_efforts.end());
  msg.effort().resize(msg.effort().size() + locked, 0.0);
}

void fill_reply_states(const Model& model, const SimState& state, hadal_msgs::msg::StepReply& msg) {
  msg.vehicle_names().clear();
  msg.poses().clear();
  msg.twists().clear();
  for (std::size_t i = 0; i < state.vehicles.size(); ++i) {
    const OdometryValues o = odometry_values(state.vehicles[i].body);
    msg.vehicle_names().push_back(model.vehicles[i].name);
    msg.poses().insert(msg.poses().end(), {o.p_WB.x(), o.p_WB.y(), o.p_WB.z(), o.q_WB.x(), o.q_WB.y(),
                                           o.q_WB.z(), o.q_WB.w()});
    msg.twists().insert(msg.twists().end(), {o.v_WB_B.x(), o.v_WB_B.y(), o.v_WB_B.z(), o.w_WB_B.x(),
                                             o.w_WB_B.y(), o.w_WB_B.z()});
  }
}

}  // namespace hadal::dds
