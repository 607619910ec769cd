#include "inbound.h"

#include <Eigen/Geometry>

#include <cmath>
#include <set>

#include "hadal/dds/time_msg.h"

namespace hadal::dds {

std::string echoed(const std::string& name) {
  constexpr std::size_t kMax = 64;
  return name.size() <= kMax ? name : name.substr(0, kMax) + "... (" + std::to_string(name.size()) + " characters)";
}

InboundCommand command_from_array(int vehicle_index, const std_msgs::msg::Float64MultiArray& msg,
                                  const SourceId& source, std::int64_t stamp_ns) {
  InboundCommand command;
  command.vehicle_index = vehicle_index;
  command.source = source;
  command.source_stamp_ns = stamp_ns;
  const std::size_t offset = msg.layout().data_offset();
  if (offset > msg.data().size()) {
    command.error = "layout.data_offset " + std::to_string(offset) + " exceeds data length " +
                    std::to_string(msg.data().size());
    return command;
  }
  command.setpoints.assign(msg.data().begin() + static_cast<std::ptrdiff_t>(offset), msg.data().end());
  return command;
}

InboundCommand command_from_trajectory(int vehicle_index, const std::string& controller,
                                       const trajectory_msgs::msg::JointTrajectory& msg, const SourceId& source,
                                       std::int64_t stamp_ns) {
  InboundCommand command;
  command.vehicle_index = vehicle_index;
  command.joint_controller = controller;
  command.source = source;
  command.source_stamp_ns = stamp_ns;
  physics::JointTrajectoryCommand& trajectory = command.trajectory.emplace();
  const builtin_interfaces::msg::Time& stamp = msg.header().stamp();
  if (stamp.sec() != 0 || stamp.nanosec() != 0) trajectory.start_time = from_time_msg(stamp);
  trajectory.joint_names = msg.joint_names();
  for (std::size_t k = 0; k < msg.points().size(); ++k) {
    const trajectory_msgs::msg::JointTrajectoryPoint& in = msg.points()[k];
    if (!in.effort().empty()) {
      command.error = "joint trajectory for '" + echoed(controller) + "': points[" + std::to_string(k) +
                      "].effort: efforts are not followed (a position group takes positions, velocities and "
                      "accelerations); leave it empty";
      return command;
    }
    physics::JointTrajectoryPoint& point = trajectory.points.emplace_back();
    point.time_from_start = in.time_from_start().sec() + 1e-9 * in.time_from_start().nanosec();
    point.positions = in.positions();
    point.velocities = in.velocities();
    point.accelerations = in.accelerations();
  }
  return command;
}

namespace {

// The index of the vehicle a request names, or -1 with the request's error (returned) and its unknown vehicle
// set.
int named_vehicle(const Model& model, const std::string& name, InboundStepRequest& request, std::string* error) {
  const int index = model.vehicle_index(name);
  if (index < 0) {
    request.unknown_vehicle = echoed(name);
    *error = "unknown vehicle '" + echoed(name) + "'";
  }
  return index;
}

// The reset part of a step request: its seed and its poses (7 numbers per named vehicle: a position
// and a unit quaternion, normalised when its norm is within 1e-3 of 1; finiteness is Simulation::reset's
// check). Returns the error.
std::string parse_reset(const Model& model, const hadal_msgs::msg::StepRequest& msg, InboundStepRequest& request) {
  request.reset = true;
  if (msg.reset_seed_given()) request.reset_seed = msg.reset_seed();
  const auto& names = msg.reset_vehicle_names();
  const auto& poses = msg.reset_poses();
  if (poses.size() != 7 * names.size()) {
    return "reset_poses has " + std::to_string(poses.size()) + " numbers for " + std::to_string(names.size()) +
           " reset_vehicle_names (7 each: x y z qx qy qz qw)";
  }
  request.reset_X_WB.assign(model.vehicles.size(), std::nullopt);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const int index = model.vehicle_index(names[i]);
    if (index < 0) {
      request.unknown_vehicle = echoed(names[i]);
      return "reset: unknown vehicle '" + echoed(names[i]) + "'";
    }
    if (request.reset_X_WB[static_cast<std::size_t>(index)]) {
      return "reset: vehicle '" + names[i] + "' has two poses";
    }
    const double* p = poses.data() + 7 * i;  // a NaN passes here; Simulation::reset refuses the pose
    Eigen::Quaterniond q(p[6], p[3], p[4], p[5]);
    if (std::abs(q.norm() - 1.0) > 1e-3) {
      return "reset: vehicle '" + names[i] + "': quaternion norm " + std::to_string(q.norm()) + ", expected 1";
    }
    Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
    X_WB.translate(Eigen::Vector3d(p[0], p[1], p[2]));
    X_WB.rotate(q.normalized());
    request.reset_X_WB[static_cast<std::size_t>(index)] = X_WB;
  }
  return "";
}

}  // namespace

InboundCommand command_from_packet(int vehicle_index, const std::string& modem,
                                   const hadal_msgs::msg::AcousticPacket& msg, const SourceId& source,
                                   std::int64_t stamp_ns) {
  InboundCommand command;
  command.vehicle_index = vehicle_index;
  command.source = source;
  command.source_stamp_ns = stamp_ns;
  command.packet = InboundCommand::Packet{modem, msg.destination(), msg.payload()};
  return command;
}

InboundCommand command_from_winch(int cable_index, const hadal_msgs::msg::WinchCommand& msg, const SourceId& source,
                                  std::int64_t stamp_ns) {
  InboundCommand command;
  command.source = source;
  command.source_stamp_ns = stamp_ns;
  command.winch = InboundCommand::Winch{cable_index, msg.speed_mps(), msg.target_length_m()};
  return command;
}

std::string command_target(const Model& model, const InboundCommand& command) {
  if (command.winch) return "cable '" + model.cables.at(static_cast<std::size_t>(command.winch->cable_index)).name + "'";
  return model.vehicles.at(static_cast<std::size_t>(command.vehicle_index)).name;
}

namespace {

// The joint-controller commands attached to a request: "" when they parse, else the reason.
std::string parse_joint_commands(const Model& model, const hadal_msgs::msg::StepRequest& msg, const SourceId& source,
                                 std::int64_t stamp, InboundStepRequest& request) {
  const std::size_t n = msg.joint_command_vehicles().size();
  if (msg.joint_command_controllers().size() != n || msg.joint_command_counts().size() != n) {
    return "joint_command_vehicles, joint_command_controllers and joint_command_counts differ in length";
  }
  std::size_t cursor = 0;
  std::string error;
  for (std::size_t i = 0; i < n; ++i) {
    const int index = named_vehicle(model, msg.joint_command_vehicles()[i], request, &error);
    if (index < 0) return error;
    const std::size_t count = msg.joint_command_counts()[i];
    if (cursor + count > msg.joint_commands().size()) {
      return "joint_command_counts add up to more than the " + std::to_string(msg.joint_commands().size()) +
             " joint commands attached";
    }
    InboundCommand command;
    command.vehicle_index = index;
    command.joint_controller = msg.joint_command_controllers()[i];
    command.source = source;
    command.source_stamp_ns = stamp;
    command.setpoints.assign(msg.joint_commands().begin() + static_cast<std::ptrdiff_t>(cursor),
                             msg.joint_commands().begin() + static_cast<std::ptrdiff_t>(cursor + count));
    cursor += count;
    request.commands.push_back(std::move(command));
  }
  if (cursor != msg.joint_commands().size()) {
    return "joint_command_counts add up to " + std::to_string(cursor) + " but " +
           std::to_string(msg.joint_commands().size()) + " joint commands are attached";
  }
  const std::size_t trajectories = msg.joint_trajectories().size();
  if (msg.joint_trajectory_vehicles().size() != trajectories ||
      msg.joint_trajectory_controllers().size() != trajectories) {
    return "joint_trajectory_vehicles, joint_trajectory_controllers and joint_trajectories differ in length";
  }
  for (std::size_t i = 0; i < trajectories; ++i) {
    const int index = named_vehicle(model, msg.joint_trajectory_vehicles()[i], request, &error);
    if (index < 0) return error;
    InboundCommand command = command_from_trajectory(index, msg.joint_trajectory_controllers()[i],
                                                     msg.joint_trajectories()[i], source, stamp);
    if (!command.error.empty()) return command.error;
    request.commands.push_back(std::move(command));
  }
  const std::size_t packets = msg.packets().size();
  if (msg.packet_vehicles().size() != packets || msg.packet_modems().size() != packets) {
    return "packet_vehicles, packet_modems and packets differ in length";
  }
  for (std::size_t i = 0; i < packets; ++i) {
    const int index = named_vehicle(model, msg.packet_vehicles()[i], request, &error);
    if (index < 0) return error;
    request.commands.push_back(command_from_packet(index, msg.packet_modems()[i], msg.packets()[i], source, stamp));
  }
  const std::size_t winches = msg.winch_commands().size();
  if (msg.winch_cables().size() != winches) return "winch_cables and winch_commands differ in length";
  for (std::size_t i = 0; i < winches; ++i) {
    const std::string& name = msg.winch_cables()[i];
    const int index = model.cable_index(name);
    if (index < 0) {
      std::string known;
      for (const physics::CableModel& cable : model.cables) {
        if (cable.winch_end() >= 0) known += (known.empty() ? "'" : ", '") + cable.name + "'";
      }
      return "winch_cables[" + std::to_string(i) + "]: unknown cable '" + echoed(name) + "' (cables with a winch: " +
             (known.empty() ? "none" : known) + ")";
    }
    request.commands.push_back(command_from_winch(index, msg.winch_commands()[i], source, stamp));
  }
  return "";
}

}  // namespace

InboundStepRequest parse_step_request(const Model& model, const hadal_msgs::msg::StepRequest& msg,
                                      const SourceId& source,
                                      std::int64_t stamp) {
  InboundStepRequest request;
  request.request_id = msg.request_id();
  request.steps = msg.steps();
  request.source_stamp_ns = stamp;
  if (msg.steps() == 0 && !msg.reset()) {
    request.error = "steps must be >= 1 (0 only with a reset)";
    return request;
  }
  if (msg.reset()) {
    request.error = parse_reset(model, msg, request);
    if (!request.error.empty()) return request;
  } else if (msg.reset_seed_given() || !msg.reset_vehicle_names().empty() || !msg.reset_poses().empty()) {
    request.error = "reset_seed or reset poses without reset = true";
    return request;
  }
  if (msg.vehicle_names().size() != msg.setpoint_counts().size()) {
    request.error = "vehicle_names and setpoint_counts differ in length";
    return request;
  }
  std::size_t cursor = 0;
  std::set<int> named;
  for (std::size_t i = 0; i < msg.vehicle_names().size(); ++i) {
    const std::string& name = msg.vehicle_names()[i];
    const int index = named_vehicle(model, name, request, &request.error);
    if (index < 0) return request;
    if (!named.insert(index).second) {
      request.error = "vehicle '" + name + "' has setpoints attached twice";
      return request;
    }
    const std::size_t count = msg.setpoint_counts()[i];
    if (cursor + count > msg.setpoints().size()) {
      request.error = "setpoint_counts add up to more than the " +
                      std::to_string(msg.setpoints().size()) + " setpoints attached";
      return request;
    }
    InboundCommand command;
    command.vehicle_index = index;
    command.source = source;
    command.source_stamp_ns = stamp;
    command.setpoints.assign(msg.setpoints().begin() + static_cast<std::ptrdiff_t>(cursor),
                             msg.setpoints().begin() + static_cast<std::ptrdiff_t>(cursor + count));
    cursor += count;
    request.commands.push_back(std::move(command));
  }
  if (cursor != msg.setpoints().size()) {
    request.error = "setpoint_counts add up to " + std::to_string(cursor) + " but " +
                    std::to_string(msg.setpoints().size()) + " setpoints are attached";
    return request;
  }
  request.error = parse_joint_commands(model, msg, source, stamp, request);
  return request;
}

}  // namespace hadal::dds
