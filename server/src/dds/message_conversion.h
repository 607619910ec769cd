// Conversions between Hadal's state and the ROS 2 message types on the wire.
//
// Odometry follows nav_msgs/Odometry's convention: pose of the body frame B in the world frame
// (header.frame_id, ENU), twist expressed in the child frame B (v_WB_B, w_WB_B). Covariances are zero:
// this is ground truth. Sensor messages are their kinds' (sensors/<kind>_sensor.h, fill_message).
#pragma once

#include "hadal/core/model.h"
#include "hadal/core/state.h"
#include "hadal/physics/waves.h"

#include "hadal/dds/time_msg.h"

#include <hadal_msgs.h>
#include <nav_msgs.h>
#include <sensor_msgs.h>

namespace hadal::dds {

// B's pose in W and its twist in B axes, the numbers odometry carries.
struct OdometryValues {
  Eigen::Vector3d p_WB;
  Eigen::Quaterniond q_WB;
  Eigen::Vector3d v_WB_B;  // [m/s]
  Eigen::Vector3d w_WB_B;  // [rad/s]
};
OdometryValues odometry_values(const RigidBodyState& body);

void fill_odometry(const std::string& world_frame_id, const std::string& vehicle_name, double time_s,
                   const RigidBodyState& body, nav_msgs::msg::Odometry& msg);

// hadal_msgs/SeaState at p_W (a vehicle's B origin) at time_s: the waves' surface over it, its depth under that, the
// orbital velocity there, and the sea state's Hs, Tp, mean direction (spec's; listed waves: the longest period and
// the largest component's direction) and build-up.
void fill_sea_state(const std::string& world_frame_id, double time_s, const physics::Waves& waves,
                    const physics::WaveSpec& spec, const Eigen::Vector3d& p_W, hadal_msgs::msg::SeaState& msg);

// A vehicle's joints as JointState reports them: its moving joints in state order (VehicleState::joint_positions),
// then its locked ones (JointSpec::locked_type: fixed at their locks), each `joint.name`, else the child link's
// (configs/REFERENCE.md, `links[].joint`). Empty for a vehicle without either.
struct JointStateLayout {
  std::vector<std::string> names;
  std::vector<double> locked_positions;  // the locked joints' (the last names), at their locks [rad] or [m]
};
JointStateLayout joint_state_layout(const VehicleSpec& vehicle);
// sensor_msgs/JointState of the vehicle's joints: positions, velocities and the efforts their motors hold (a
// locked joint's rate and effort are zero); header.frame_id is the vehicle's base frame.
void fill_joint_state(const JointStateLayout& joints, const std::string& vehicle_name, double time_s,
                      const VehicleState& vehicle, sensor_msgs::msg::JointState& msg);

// A step reply's ground truth: every vehicle's name, pose (7 numbers) and twist (6), as odometry_values.
void fill_reply_states(const Model& model, const SimState& state, hadal_msgs::msg::StepReply& msg);

}  // namespace hadal::dds
