// Buoyancy engine (actuator kind "buoyancy_engine", YAML list `buoyancy_engines`): a glider's variable
// displacement -- oil pumped from an internal reservoir into an external bladder, or let back through a
// valve -- that makes the vehicle heavier or lighter than the water. Its control is one normalised
// setpoint in [-1, 1], the displaced volume it drives to: Delta V_cmd = setpoint Delta V_max.
//
//   volume    Delta V moves towards Delta V_cmd at the pump's rate q [m^3/s]:
//             Delta V_{k+1} = Delta V_k + clamp(Delta V_cmd - Delta V_k, -q dt, q dt)
//   force     f_W = rho(d) g Delta V z_W at the bladder p_WE = X_WB X_BL p_LE (nothing above the surface)
//   power     pumping out (Delta V rising) works against the sea: P = (p(d) - p_atm) q_k / eta, with
//             q_k the step's volume rate and eta the pump's efficiency; letting oil back in through the
//             valve is free (P = 0). energy = sum P dt [J].
// Delta V is displacement beyond the vehicle's own surface (its neutral state is setpoint 0): the
// vehicle's geometry is not changed, only its buoyancy.
//
// YAML keys: BuoyancyEngineActuator::keys() (server/src/physics/buoyancy_engine.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/config/key_table_fwd.h"
#include "hadal/physics/actuator_kind.h"
#include "hadal/physics/buoyancy_engine_spec.h"

namespace hadal::physics {

struct BuoyancyEngineActuator {
  static constexpr std::string_view kType = "buoyancy_engine";
  static constexpr std::string_view kListKey = "buoyancy_engines";
  static constexpr std::size_t kControls = 1;  // the normalised volume setpoint

  using Spec = BuoyancyEngineSpec;
  struct State {
    using Kind = BuoyancyEngineActuator;
    double setpoint = 0.0;       // normalised command in [-1, 1] currently applied
    double volume_change = 0.0;  // Delta V [m^3]
    double volume_rate = 0.0;    // over the last step [m^3/s]
    double force_N = 0.0;        // buoyancy of Delta V, up
    double power_W = 0.0;        // pump power drawn
    double energy_J = 0.0;       // pump energy drawn since the start
  };
  struct Runtime {
    Eigen::Vector3d p_BE = Eigen::Vector3d::Zero();
    double max_volume_change = 0.0, pump_rate = 0.0, efficiency = 0.5, dt = 0.002;
  };

  // Its YAML keys besides name and link, declared once (configs/REFERENCE.md shows them).
  static const config::KeyTable<Spec>& keys();
  static Runtime prepare(const Spec& spec, const ActuatorSetup& setup);
  static std::string check(const Spec& spec, const double* controls, std::size_t first);
  static void command(State& state, const double* controls);
  static void actuate(const Runtime& runtime, State& state);
  static void add_wrench(const Runtime& runtime, State& state, const ActuatorForceInput& in, StepWrench& out);
  // The non-finite policy: the pump stops where the bladder is.
  static void stop(State& state);
  static bool is_finite(const State& state) { return std::isfinite(state.volume_change) && std::isfinite(state.energy_J); }
};

}  // namespace hadal::physics
