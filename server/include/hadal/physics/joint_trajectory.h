// A joint trajectory for a position group (issue 40's trajectory follower; docs/ARCHITECTURE.md, "Joint
// trajectories"): trajectory_msgs/JointTrajectory's waypoints, each at a time from the trajectory's start,
// followed the way ros2_control's joint_trajectory_controller follows them with its "splines"
// interpolation. Between two waypoints each joint moves on
//   - a line, when the waypoints give positions alone;
//   - a cubic through both positions and rates (Hermite), when they give velocities;
//   - a quintic through positions, rates and accelerations, when they give accelerations too.
// The first segment starts where the joints are when the trajectory starts (their positions and rates,
// acceleration zero) and ends at the first waypoint. After the last waypoint its positions are held at
// rate zero. The controller's position law takes the sampled position and feeds the sampled rate forward
// (physics/joint_servo.h).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace hadal::physics {

// One waypoint, in the group's joint order.
struct JointTrajectoryPoint {
  double time_from_start = 0.0;       // [s] after the trajectory's start, increasing from point to point
  std::vector<double> positions;      // one per joint [rad or m]
  std::vector<double> velocities;     // empty, or one per joint [rad/s or m/s]
  std::vector<double> accelerations;  // empty, or (with velocities) one per joint [rad/s^2 or m/s^2]
};

// "" when `points` is a trajectory for `joints` joints, else what is wrong, naming the point and the
// field: no points, a size that is not `joints`, a value that is not finite, times that are negative or
// do not increase, velocities or accelerations given for some points and not others, accelerations
// without velocities.
std::string check_joint_trajectory(const std::vector<JointTrajectoryPoint>& points, std::size_t joints);

struct JointTrajectory {
  double start_time = 0.0;                  // sim time [s] from which time_from_start counts
  std::vector<JointTrajectoryPoint> points;  // check_joint_trajectory holds
  // Set when the trajectory starts (JointTrajectory::started): the sim time it started [s] and the joints'
  // positions and rates then, the first segment's start.
  double started_at = 0.0;
  std::vector<double> start_positions, start_velocities;

  bool started() const { return !start_positions.empty(); }
  // The sim time [s] of the last waypoint.
  double end_time() const { return start_time + points.back().time_from_start; }
};

// A trajectory as a client sends it (trajectory_msgs/JointTrajectory): for a position group, naming its
// joints in any order; the simulation checks it and puts it in the group's order
// (Simulation::set_joint_trajectory).
struct JointTrajectoryCommand {
  // Sim time [s] at which time_from_start counts (the header's stamp); none (a zero stamp): the sim time
  // at which the command is applied.
  std::optional<double> start_time;
  std::vector<std::string> joint_names;      // the group's joints, each once, in any order
  std::vector<JointTrajectoryPoint> points;  // values in joint_names' order
};

struct JointSetpoint {
  double position = 0.0;  // [rad or m]
  double rate = 0.0;      // [rad/s or m/s]
};

// Joint j's setpoint at sim time t, of a started trajectory (t before started_at: the start).
JointSetpoint sample_joint_trajectory(const JointTrajectory& trajectory, std::size_t j, double t);

}  // namespace hadal::physics
