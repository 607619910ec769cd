// What hadald reads from clients, parsed: thruster commands (rt/<vehicle>/actuators/commands), joint commands,
// modem packets (rt/<vehicle>/<modem>/tx), winch commands (rt/hadal/cables/<cable>/winch/command) and step
// requests (rt/hadal/step_request), checked against the model (vehicle names, lengths, a reset's poses)
// before anything reaches the simulation. Pure functions of the model and the message, so the DDS
// listeners (server_endpoints.cc) and the fuzzer (tests/fuzz/command_fuzz.cc) run the same code.
#pragma once

#include "hadal/core/model.h"
#include "hadal/physics/joint_trajectory.h"

#include <hadal_msgs.h>
#include <std_msgs.h>
#include <trajectory_msgs.h>

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hadal::dds {

// The participant a sample came from (its GUID prefix): samples of one participant carry stamps of one
// clock, so only they may be ordered by stamp.
using SourceId = std::array<std::uint8_t, 12>;

// A thruster command from rt/<vehicle>/actuators/commands, or attached to a step request.
struct InboundCommand {
  int vehicle_index = -1;
  // Empty: the vehicle's control vector (rt/<vehicle>/actuators/commands); else the joint controller whose
  // command `setpoints` is (rt/<vehicle>/<controller>/commands, Simulation::set_joint_commands).
  std::string joint_controller;
  std::vector<double> setpoints;
  // A trajectory for the position group `joint_controller` (rt/<vehicle>/<controller>/joint_trajectory,
  // Simulation::set_joint_trajectory) instead of setpoints.
  std::optional<physics::JointTrajectoryCommand> trajectory;
  // A packet for one of the vehicle's acoustic modems (rt/<vehicle>/<modem>/tx, Simulation::send_packet) instead of
  // setpoints.
  struct Packet {
    std::string modem;
    std::string destination;
    std::vector<std::uint8_t> payload;
  };
  std::optional<Packet> packet;
  // A command for a cable's winch (rt/hadal/cables/<cable>/winch/command, Simulation::command_winch) instead:
  // vehicle_index is then -1.
  struct Winch {
    int cable_index = -1;
    double speed = 0.0;          // [m/s]
    double target_length = 0.0;  // [m]; 0: none
  };
  std::optional<Winch> winch;
  SourceId source{};                 // the sending participant
  std::int64_t source_stamp_ns = 0;  // its source timestamp: of one sender, the later command wins
  std::string error;                 // non-empty: malformed before it reached the simulation
};

struct InboundStepRequest {
  std::uint64_t request_id = 0;
  std::uint32_t steps = 0;
  std::vector<InboundCommand> commands;  // setpoints attached to the request
  // A reset request: start over from the initial state first (Simulation::reset), with this seed (the
  // scenario's when none was given) and these poses (one per vehicle, given or not).
  bool reset = false;
  std::optional<std::uint64_t> reset_seed;
  std::vector<std::optional<Eigen::Isometry3d>> reset_X_WB;
  std::int64_t source_stamp_ns = 0;
  std::string error;  // non-empty: the request is malformed and is refused as a whole
  std::string unknown_vehicle;  // the vehicle the scenario does not have when that is the error
};

// A name a client sent, for an error message: at most 64 characters, the rest elided.
std::string echoed(const std::string& name);

// Setpoints carried by a std_msgs/Float64MultiArray: data[layout.data_offset:].
InboundCommand command_from_array(int vehicle_index, const std_msgs::msg::Float64MultiArray& msg,
                                  const SourceId& source, std::int64_t stamp_ns);

// A trajectory_msgs/JointTrajectory for the joint controller `controller` (the simulation checks the rest):
// header.stamp a sim time (zero: none, on receipt), durations in seconds.
InboundCommand command_from_trajectory(int vehicle_index, const std::string& controller,
                                       const trajectory_msgs::msg::JointTrajectory& msg, const SourceId& source,
                                       std::int64_t stamp_ns);

// A packet from rt/<vehicle>/<modem>/tx: its destination and payload (the simulation checks them).
InboundCommand command_from_packet(int vehicle_index, const std::string& modem,
                                   const hadal_msgs::msg::AcousticPacket& msg, const SourceId& source,
                                   std::int64_t stamp_ns);

// A command from rt/hadal/cables/<cable>/winch/command (the simulation checks its numbers).
InboundCommand command_from_winch(int cable_index, const hadal_msgs::msg::WinchCommand& msg, const SourceId& source,
                                  std::int64_t stamp_ns);

// Who a command is for, for a message: its vehicle's name, or "cable '<name>'".
std::string command_target(const Model& model, const InboundCommand& command);

// A step request checked against the model: its commands, its reset, or the error refusing it as a whole.
InboundStepRequest parse_step_request(const Model& model, const hadal_msgs::msg::StepRequest& msg,
                                      const SourceId& source, std::int64_t stamp);

}  // namespace hadal::dds
