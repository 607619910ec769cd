#include "hadal/physics/track.h"

#include <algorithm>
#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/core/units.h"

namespace hadal::physics {

using config::Range;

const config::KeyTable<TrackActuator::Spec>& TrackActuator::keys() {
  return config::declare_keys<Spec>([](config::KeyTable<Spec>& t) {
    t.describe("track", "a driven track or wheel: it moves its link's surface over the soil");
    t.direction("direction", &Spec::direction_L)
        .doc("forward in L (the belt's ground run moves along -direction when driving forward); normalised on load");
    t.number("sprocket_radius", &Spec::sprocket_radius).required().unit("m").range(Range::left_open(0.0, 10.0))
        .doc("r; a wheel's radius");
    t.number("max_rpm", &Spec::max_speed_rad_s).required()
        .convert([](double rpm) { return rpm * 2.0 * kPi / 60.0; }, [](double rad_s) { return rad_s * 60.0 / (2.0 * kPi); },
                 "rev/min")
        .range(Range::left_open(0.0, 1e5)).doc("the sprocket's no-load speed omega_0");
    t.number("stall_torque", &Spec::stall_torque).required().unit("N m").range(Range::left_open(0.0, 1e7))
        .doc("at the sprocket");
    t.number("torque_constant", &Spec::torque_constant).unit("N m/A").range(Range::left_open(0.0, 1e6))
        .doc("at the sprocket, gearing included: current = torque / this");
    t.number("drive_inertia", &Spec::drive_inertia).unit("kg m²").range(Range::left_open(0.0, 1e6))
        .doc("motor, gears, sprocket and belt at the sprocket");
    t.number("speed_time_constant_s", &Spec::speed_time_constant_s).unit("s").range(Range::left_open(0.0, 100.0))
        .doc("of the speed loop");
  });
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
