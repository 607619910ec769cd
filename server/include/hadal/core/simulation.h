// Simulation: the fixed-step loop body of hadald, independent of DDS.
//
// One step (DESIGN.md, "data flow of one step"):
//   commands -> actuator setpoints -> rotor dynamics -> forces (thrusters, fluid, gravity)
//   -> Bullet step -> state snapshot -> non-finite check.
// Setpoint source per vehicle: the scenario schedule until a client first commands the vehicle, then
// client setpoints guarded by the watchdog (no fresh command for command_timeout seconds of sim
// time -> setpoints 0, kFaultCommandTimeout set). Non-finite policy (DESIGN.md 7): a vehicle whose
// pose, velocity, rotor speed or client setpoints become NaN/Inf is put back at X_WB_initial at rest,
// rotors stopped, client setpoints zeroed; kFaultNonFiniteState stays set (latched) and fault_resets
// counts the resets. Not thread-safe: the caller serialises access.
// Fluid per vehicle (VehicleSpec::fluid.model): lumped (default; LumpedFluid, water at rest), or
// surface: SurfaceHydrodynamics over the links' meshes (or tessellated collision primitives) in B,
// sampled in the scenario's Ocean (density profile, pressure, currents) at the step's start time,
// applied at the centre of mass; buoyancy then comes from pressure integration (links' buoyancy
// volumes are not used). Both fluid models see the Ocean's current at the vehicle (the lumped model
// at the centre of mass, the surface model per face).
// Added mass (VehicleSpec::fluid.added_mass, physics/added_mass.h): M_A0 about the centre of mass,
// scaled each step by kappa(d) at the centre of mass times the submerged fraction of the vehicle (the
// lumped model's volume fraction, the surface model's wetted-area fraction), with C_A(nu_r) nu_r for
// the velocity relative to the current there; all applied wrenches of a step are collected at the
// centre of mass and turned into the wrench Bullet gets.
// Rigid-body dynamics (world.dynamics): Bullet's gyroscopic moment on/off; Earth-rotation Coriolis
// F = -2 m Omega_W x v_WBcm at the centre of mass when enabled.
// Sensors sample at the end of the step that reaches their sample time (VehicleSpec::sensors); the
// DVL's beams and altimeters cast rays into the world's Embree scene on the stepping thread, so their
// samples are as deterministic as the rest of the step.
// Fluid forces of different vehicles are independent; with two or more surface-model hulls of
// >= 4096 faces they are computed on a persistent worker pool (results are identical either way).
#pragma once

#include "hadal/core/model.h"
#include "hadal/core/state.h"

#include <memory>
#include <string>
#include <vector>

namespace hadal {

class WorkerPool;

namespace sensors {
class SensorEnvironment;
}
namespace geometry {
class SceneRays;
}

namespace physics {
class BulletWorld;
class Ocean;
struct MassProperties;
}

class Simulation {
 public:
  // Throws std::invalid_argument if the model cannot be simulated (physics_rate_hz not > 0, a vehicle
  // without positive mass, a thruster on a missing link, a surface-model vehicle without faces).
  explicit Simulation(Model model);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const Model& model() const { return model_; }
  const SimState& state() const { return state_; }
  double time() const { return state_.time; }

  // Composite mass properties of a vehicle (centre of mass, inertia, principal frame), index < count.
  const physics::MassProperties& mass_properties(int vehicle_index) const;
  // The vehicle's added mass at the surface, M_A0 about its centre of mass in B axes (zero for
  // added_mass.model none) [kg, kg m, kg m^2].
  const Matrix6d& added_mass(int vehicle_index) const;
  // The scenario's water column.
  const physics::Ocean& ocean() const { return *ocean_; }
  // Helper threads computing fluid forces besides the stepping thread (0: serial).
  unsigned fluid_helper_threads() const;

  // Restores a state previously returned by state() (same model; throws std::invalid_argument if the
  // vehicle or thruster counts differ). A vehicle whose restored state is not finite gets the
  // non-finite policy at once (reset, kFaultNonFiniteState, fault_resets + 1), so NaN never enters
  // Bullet. Contact caches are cleared: restoring the same state twice continues bit-identically.
  void set_state(const SimState& state);

  // Validates and applies a client command for a vehicle: one setpoint per thruster, each finite and
  // in [-1, 1]. Returns an empty string when accepted, otherwise the reason (state untouched).
  std::string set_thruster_setpoints(int vehicle_index, const std::vector<double>& setpoints);
  // The validation alone: "" if set_thruster_setpoints would accept the command, else the reason.
  std::string check_thruster_setpoints(int vehicle_index, const std::vector<double>& setpoints) const;

  // Advances by one physics step of model().world.step_size() seconds.
  void step();

 private:
  Model model_;
  SimState state_;
  std::unique_ptr<physics::BulletWorld> world_;
  std::unique_ptr<physics::Ocean> ocean_;  // the water column
  struct VehicleRuntime;                 // per-vehicle thrusters, fluid model, sensors (simulation.cc)
  std::vector<VehicleRuntime> runtime_;  // one per VehicleSpec
  std::unique_ptr<WorkerPool> pool_;     // fluid forces in parallel; null when it does not pay
  std::unique_ptr<sensors::SensorEnvironment> environment_;  // WMM, W's geodetic frame (on first use)
  std::unique_ptr<geometry::SceneRays> rays_;  // the world's Embree scene; null without ray-casting sensors
};

}  // namespace hadal
