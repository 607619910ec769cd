#include "hadal/physics/buoyancy_engine.h"

#include <algorithm>
#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/physics/ocean.h"

namespace hadal::physics {

using config::Range;

const config::KeyTable<BuoyancyEngineActuator::Spec>& BuoyancyEngineActuator::keys() {
  return config::declare_keys<Spec>([](config::KeyTable<Spec>& t) {
    t.describe("buoyancy_engine",
               "oil pumped between a reservoir and an external bladder: the "
               "displaced volume changes by dV about neutral");
    t.vector("position", &Spec::p_LE).required().unit("m").doc("p_LE, the bladder's centre in L");
    t.number("max_volume_change", &Spec::max_volume_change).required().unit("m³").range(Range::left_open(0.0, 100.0))
        .doc("dV ranges over +- this");
    t.number("pump_rate", &Spec::pump_rate).required().unit("m³/s").range(Range::left_open(0.0, 100.0)).doc("q");
    t.number("efficiency", &Spec::efficiency).range(Range::left_open(0.0, 1.0))
        .doc("hydraulic over electrical power");
  });
}
BuoyancyEngineActuator::Runtime BuoyancyEngineActuator::prepare(const Spec& spec, const ActuatorSetup& setup) {
  Runtime runtime;
  runtime.p_BE = setup.X_BL * spec.p_LE;
  runtime.max_volume_change = spec.max_volume_change;
  runtime.pump_rate = spec.pump_rate;
  runtime.efficiency = spec.efficiency;
  runtime.dt = setup.step_size;
  return runtime;
}

std::string BuoyancyEngineActuator::check(const Spec&, const double* controls, std::size_t first) {
  return check_normalised_setpoint(controls[0], first);
}

void BuoyancyEngineActuator::command(State& state, const double* controls) {
  state.setpoint = held_setpoint(controls[0]);
}

void BuoyancyEngineActuator::actuate(const Runtime& r, State& state) {
  const double target = state.setpoint * r.max_volume_change;
  const double max_step = r.pump_rate * r.dt;
  const double step = std::clamp(target - state.volume_change, -max_step, max_step);
  state.volume_change += step;
  state.volume_rate = step / r.dt;
}

void BuoyancyEngineActuator::add_wrench(const Runtime& r, State& state, const ActuatorForceInput& in,
                                        StepWrench& out) {
  const Eigen::Vector3d p_WE = in.X_WB * r.p_BE;
  const bool submerged = in.ocean && p_WE.z() < in.surface_z;
  const double depth = in.ocean ? std::max(in.ocean->depth(p_WE.z()), 0.0) : 0.0;
  // Pumping out against the sea's gauge pressure; the valve lets oil back for free.
  const double gauge = in.ocean ? in.ocean->pressure(depth) - in.ocean->atmospheric_pressure() : 0.0;
  state.power_W = state.volume_rate > 0.0 ? gauge * state.volume_rate / r.efficiency : 0.0;
  state.energy_J += state.power_W * r.dt;
  state.force_N = submerged ? in.ocean->density(depth) * in.ocean->gravity() * state.volume_change : 0.0;
  const Eigen::Vector3d f_W(0.0, 0.0, state.force_N);
  out.f_W += f_W;
  out.tau_W += (p_WE - in.p_WBcm).cross(f_W);
}

void BuoyancyEngineActuator::stop(State& state) {
  if (!std::isfinite(state.volume_change)) state.volume_change = 0.0;
  if (!std::isfinite(state.energy_J)) state.energy_J = 0.0;
  state.volume_rate = 0.0;
  state.power_W = 0.0;
  state.force_N = 0.0;
}

}  // namespace hadal::physics
