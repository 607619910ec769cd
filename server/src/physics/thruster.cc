#include "hadal/physics/thruster.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "hadal/config/key_table.h"

namespace hadal::physics {

using config::Range;

const config::KeyTable<ThrusterActuator::Spec>& ThrusterActuator::keys() {
  return config::declare_keys<Spec>([](config::KeyTable<Spec>& t) {
    t.describe("thruster",
               "a propeller thruster: T = K_T rho D^4 n|n| along direction, Q = "
               "-handedness K_Q rho D^5 n|n| about it");
    t.vector("position", &Spec::p_LT).required().unit("m").doc("p_LT, the propeller's position in L");
    t.direction("direction", &Spec::axis_L).required().doc("thrust direction for n > 0, in L; normalised on load");
    t.number("propeller_diameter", &Spec::propeller_diameter).required().unit("m").range(Range::positive()).doc("D");
    t.number("thrust_coefficient", &Spec::thrust_coefficient).required().range(Range::positive()).doc("K_T");
    t.number("torque_coefficient", &Spec::torque_coefficient).range(Range::non_negative()).doc("K_Q");
    t.number("rotor_time_constant_s", &Spec::rotor_time_constant_s).unit("s").range(Range::non_negative())
        .doc("tau of the rotor's first-order lag; 0: the rotor follows the command at once");
    t.number("max_rpm", &Spec::max_rotor_speed_rev_s).required()
        .convert([](double rpm) { return rpm / 60.0; }, [](double rev_s) { return rev_s * 60.0; }, "rev/min")
        .range(Range::positive()).doc("setpoint +-1 commands +-max_rpm");
    t.choice("handedness", &Spec::handedness, {{"right", 1}, {"left", -1}}).doc("of the propeller");
  });
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
