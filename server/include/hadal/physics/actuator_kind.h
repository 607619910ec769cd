// The contract every actuator kind fulfils, the per-step wrench that force elements add into, and the
// contexts handed to them (docs/ARCHITECTURE.md, "Actuator kinds" and "Force elements").
//
// A vehicle's actuators (VehicleSpec::actuators) share one control vector: each actuator takes the next
// kControls entries (a thruster: one normalised setpoint). A command or a schedule keyframe is a whole
// control vector; the simulation checks it with each actuator's check(), holds it over the step with
// command(), advances each actuator's own dynamics with actuate() and lets it add its wrench with
// add_wrench(). An actuator kind is a struct K in physics/<kind>.{h,cc} with
//
//   static constexpr std::string_view kType;      its name ("thruster")
//   static constexpr std::string_view kListKey;   the vehicle definition's YAML list of this kind
//   static constexpr std::size_t kControls;       entries of the control vector it takes
//   struct Spec { using Kind = K; ... };          immutable, from YAML (the model holds it)
//   struct State { using Kind = K; ... };         what evolves (reported on its state topic)
//   using Runtime = ...;                          constants derived once from the spec and the world
//   static const config::KeyTable<Spec>& keys();    its YAML keys besides name and link, each declared
//                                                   once (config/key_table.h): they read the Spec
//   static Runtime prepare(const Spec&, const ActuatorSetup&);
//   static std::string check(const Spec&, const double* controls, std::size_t first);   "" or why not
//   static void command(State&, const double* controls);   the controls held over the next step
//   static void actuate(const Runtime&, State&);            one step of its own dynamics
//   static void add_wrench(const Runtime&, State&, const ActuatorForceInput&, StepWrench&);
//   static void stop(State&);                  the non-finite policy: at rest, no force
//   static bool is_finite(const State&);
//
// Optional: static constexpr bool kDrivesSurface (a track: physics/track.h) and
//   static bool needs_seabed(const Spec&)      true: add_wrench() reads in.seabed_z_below
//
// and one line in physics/actuator_kinds.h. Common to every actuator (ActuatorSpec in core/model.h):
// name and link.
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>

namespace hadal::physics {

class Ocean;

// The wrench a step's force elements add up for one vehicle: force and moment about the vehicle's
// centre of mass p_WBcm at the step's start, in W, plus what the fluid model reports for the added-mass
// conversion (physics/added_mass.h).
struct StepWrench {
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();    // [N]
  Eigen::Vector3d tau_W = Eigen::Vector3d::Zero();  // about p_WBcm [N m]
  double submerged_fraction = 0.0;                  // of the vehicle [-]
  Eigen::Vector3d v_water_W = Eigen::Vector3d::Zero();  // current (and the surface model's waves) at the centre of mass [m/s]
  Eigen::Vector3d a_water_W = Eigen::Vector3d::Zero();  // the waves' orbital acceleration there [m/s^2]
};

// A normalised setpoint, the control of thrusters and tracks: "" when `value` is finite and in [-1, 1],
// else why not, naming it setpoint[first] ("setpoint[1] is NaN", "setpoint[0] = 1.5 is outside [-1, 1]").
std::string check_normalised_setpoint(double value, std::size_t first);
// The setpoint held over a step: a last-line guard clamps it to [-1, 1], NaN to 0.
double held_setpoint(double value);

// What prepare() gets: the pose in B of the link the actuator is mounted on, and the world's constants.
struct ActuatorSetup {
  const Eigen::Isometry3d& X_BL;
  double water_density = 1025.0;  // [kg/m^3], world.water.density
  double step_size = 0.002;       // physics step [s]
  std::size_t link_index = 0;     // the link's index in the vehicle's links
};

// What add_wrench() reads: the vehicle's pose, velocity and centre of mass at the step's start, and the
// water and seabed around it.
struct ActuatorForceInput {
  const Eigen::Isometry3d& X_WB;
  const Eigen::Vector3d& p_WBcm;
  double surface_z = 0.0;  // water surface height in W [m]
  double time = 0.0;       // sim time at the step's start [s]
  Eigen::Vector3d v_WB = Eigen::Vector3d::Zero();  // velocity of B's origin in W [m/s]
  Eigen::Vector3d w_WB = Eigen::Vector3d::Zero();  // angular velocity of B in W [rad/s]
  // The water column (density, pressure, current; physics/ocean.h); null only in unit tests of kinds
  // that do not read it.
  const Ocean* ocean = nullptr;
  // Height in W of the seabed under B's origin [m]; -infinity where there is none or it was not asked
  // for (a kind asks with needs_seabed(), physics/drop_weight.h).
  double seabed_z_below = -std::numeric_limits<double>::infinity();
};

}  // namespace hadal::physics
