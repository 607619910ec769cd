#include "hadal/physics/track.h"

#include <algorithm>
#include <cmath>

#include "hadal/config/yaml_reader.h"
#include "hadal/core/units.h"

namespace hadal::physics {

using config::MapReader;
using config::Need;
using config::Range;

const std::vector<std::string>& TrackActuator::keys() {
  static const std::vector<std::string> keys = {"direction",       "sprocket_radius", "max_rpm",
                                                "stall_torque",    "torque_constant", "drive_inertia",
                                                "speed_time_constant_s"};
  return keys;
}

TrackActuator::Spec TrackActuator::read(const ActuatorReader& reader) {
  const MapReader& map = reader.map;
  Spec spec;
  map.read_direction("direction", Need::kOptional, &spec.direction_L);
  map.read_number("sprocket_radius", Need::kRequired, Range::left_open(0.0, 10.0), &spec.sprocket_radius);
  double max_rpm = 0.0;
  if (map.read_number("max_rpm", Need::kRequired, Range::left_open(0.0, 1e5), &max_rpm)) {
    spec.max_speed_rad_s = max_rpm * 2.0 * kPi / 60.0;
  }
  map.read_number("stall_torque", Need::kRequired, Range::left_open(0.0, 1e7), &spec.stall_torque);
  map.read_number("torque_constant", Need::kOptional, Range::left_open(0.0, 1e6), &spec.torque_constant);
  map.read_number("drive_inertia", Need::kOptional, Range::left_open(0.0, 1e6), &spec.drive_inertia);
  map.read_number("speed_time_constant_s", Need::kOptional, Range::left_open(0.0, 100.0),
                  &spec.speed_time_constant_s);
  return spec;
}

TrackDrive TrackActuator::prepare(const Spec& spec, const ActuatorSetup& setup) {
  TrackDrive drive;
  drive.link = setup.link_index;
  drive.direction_B = (setup.X_BL.linear() * spec.direction_L).normalized();
  drive.radius = spec.sprocket_radius;
  drive.no_load_speed = spec.max_speed_rad_s;
  drive.stall_torque = spec.stall_torque;
  drive.torque_constant = spec.torque_constant;
  drive.inertia = spec.drive_inertia;
  drive.speed_time_constant = spec.speed_time_constant_s;
  drive.dt = setup.step_size;
  return drive;
}

std::string TrackActuator::check(const Spec&, const double* controls, std::size_t first) {
  return check_normalised_setpoint(controls[0], first);
}

void TrackActuator::command(State& state, const double* controls) { state.setpoint = held_setpoint(controls[0]); }

void TrackActuator::actuate(const Runtime& d, State& state) {
  const double r = d.radius;
  const double V = state.belt_speed;
  const double omega = V / r;
  const double V_cmd = state.setpoint * d.no_load_speed * r;
  const double load_torque = state.load_N * r;
  double torque = d.inertia * (V_cmd - V) / (d.speed_time_constant * r) + load_torque;
  // The motor's envelope: the torque-speed line while driving, the stall torque while braking.
  const bool driving = torque * omega > 0.0;
  const double limit = driving ? d.stall_torque * std::max(0.0, 1.0 - std::abs(omega) / d.no_load_speed) : d.stall_torque;
  torque = std::clamp(torque, -limit, limit);
  state.belt_speed = V + (torque - load_torque) * r / d.inertia * d.dt;
  state.sprocket_speed = state.belt_speed / r;
  state.motor_torque_Nm = torque;
  state.current_A = torque / d.torque_constant;
  state.power_W = torque * omega;
}

void TrackActuator::stop(State& state) {
  const double setpoint = state.setpoint;
  state = State{};
  state.setpoint = setpoint;
}

}  // namespace hadal::physics
