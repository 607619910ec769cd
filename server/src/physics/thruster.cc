#include "hadal/physics/thruster.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "hadal/config/yaml_reader.h"

namespace hadal::physics {

using config::MapReader;
using config::Need;
using config::Range;

const std::vector<std::string>& ThrusterActuator::keys() {
  static const std::vector<std::string> keys = {"position",   "direction", "propeller_diameter", "thrust_coefficient",
                                                "torque_coefficient", "rotor_time_constant_s", "max_rpm",
                                                "handedness"};
  return keys;
}

ThrusterActuator::Spec ThrusterActuator::read(const ActuatorReader& reader) {
  const MapReader& map = reader.map;
  Spec spec;
  map.read_vector3("position", Need::kRequired, Range::finite(), &spec.p_LT);
  map.read_direction("direction", Need::kRequired, &spec.axis_L);
  map.read_number("propeller_diameter", Need::kRequired, Range::positive(), &spec.propeller_diameter);
  map.read_number("thrust_coefficient", Need::kRequired, Range::positive(), &spec.thrust_coefficient);
  map.read_number("torque_coefficient", Need::kOptional, Range::non_negative(), &spec.torque_coefficient);
  map.read_number("rotor_time_constant_s", Need::kOptional, Range::non_negative(), &spec.rotor_time_constant_s);
  double max_rpm = 0.0;
  if (map.read_number("max_rpm", Need::kRequired, Range::positive(), &max_rpm)) {
    spec.max_rotor_speed_rev_s = max_rpm / 60.0;
  }
  map.read_choice<int>("handedness", Need::kOptional, {{"right", 1}, {"left", -1}}, &spec.handedness);
  return spec;
}

Thruster ThrusterActuator::prepare(const Spec& spec, const ActuatorSetup& setup) {
  return Thruster(spec, setup.X_BL, setup.water_density, setup.step_size);
}

std::string ThrusterActuator::check(const Spec&, const double* controls, std::size_t first) {
  return check_normalised_setpoint(controls[0], first);
}

void ThrusterActuator::command(State& state, const double* controls) { state.setpoint = held_setpoint(controls[0]); }

void ThrusterActuator::actuate(const Runtime& runtime, State& state) {
  state.rotor_speed_rev_s = runtime.next_rotor_speed(state.rotor_speed_rev_s, state.setpoint);
}

void ThrusterActuator::add_wrench(const Runtime& runtime, State& state, const ActuatorForceInput& in,
                                  StepWrench& out) {
  const ThrusterWrench wrench = runtime.wrench(state.rotor_speed_rev_s, in.X_WB, in.surface_z);
  state.thrust_N = wrench.thrust;
  state.torque_Nm = wrench.torque;
  out.f_W += wrench.f_W;
  out.tau_W += wrench.tau_W + (wrench.p_WT - in.p_WBcm).cross(wrench.f_W);
}

void ThrusterActuator::stop(State& state) {
  state.rotor_speed_rev_s = 0.0;
  state.thrust_N = 0.0;
  state.torque_Nm = 0.0;
}

Thruster::Thruster(const ThrusterActuator::Spec& spec, const Eigen::Isometry3d& X_BL, double water_density,
                   double dt)
    : p_BT_(X_BL * spec.p_LT),
      axis_B_((X_BL.linear() * spec.axis_L).normalized()),
      max_rotor_speed_rev_s_(spec.max_rotor_speed_rev_s),
      // -expm1(-x) = 1 - exp(-x) without cancellation when dt << tau.
      response_per_step_(spec.rotor_time_constant_s > 0.0 ? -std::expm1(-dt / spec.rotor_time_constant_s) : 1.0),
      thrust_gain_(spec.thrust_coefficient * water_density * std::pow(spec.propeller_diameter, 4)),
      torque_gain_(-spec.handedness * spec.torque_coefficient * water_density * std::pow(spec.propeller_diameter, 5)) {}

ThrusterWrench Thruster::wrench(double n, const Eigen::Isometry3d& X_WB, double surface_z) const {
  ThrusterWrench out;
  out.p_WT = X_WB * p_BT_;
  if (out.p_WT.z() > surface_z) return out;  // in air
  const Eigen::Vector3d axis_W = X_WB.linear() * axis_B_;
  out.thrust = thrust_in_water(n);
  out.torque = torque_in_water(n);
  out.f_W = out.thrust * axis_W;
  out.tau_W = out.torque * axis_W;
  return out;
}

}  // namespace hadal::physics
