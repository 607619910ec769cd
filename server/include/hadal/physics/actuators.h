// A vehicle's actuators as one set (physics/actuator_kind.h): the control vector's layout, command
// checking, the step's actuation, and their forces as the vehicle's first force element. The one place
// the simulation dispatches on actuator kind.
#pragma once

#include <cstddef>
#include <string>
#include <variant>
#include <vector>

#include "hadal/core/model.h"
#include "hadal/core/state.h"
#include "hadal/physics/actuator_kinds.h"
#include "hadal/physics/force_element.h"

namespace hadal::physics {

// Every actuator kind's Runtime, for the per-actuator constants.
template <class List>
struct RuntimesOf;
template <class... Kinds>
struct RuntimesOf<KindList<Kinds...>> {
  using type = std::variant<typename Kinds::Runtime...>;
};
using ActuatorKindRuntime = RuntimesOf<ActuatorKinds>::type;

class VehicleActuators {
 public:
  // Prepares every actuator of `vehicle` (its links must exist). Keeps references to `vehicle` and
  // `ocean` (the water column the kinds read: density, pressure, current; null in tests of kinds that
  // read none of it).
  VehicleActuators(const VehicleSpec& vehicle, const WorldSpec& world, const Ocean* ocean = nullptr);

  // Whether an actuator of `vehicle` reads the seabed's height under it (ForceInput::seabed_z_below).
  static bool needs_seabed(const VehicleSpec& vehicle);

  // The states at the start of a run: every actuator at rest.
  static std::vector<ActuatorKindState> initial_states(const VehicleSpec& vehicle);

  // "" when `controls` is a valid control vector for the vehicle (its length and every actuator's
  // check), else the reason ("expected 3 setpoints (main, heave, sway), got 2", "setpoint[1] is NaN").
  std::string check(const std::vector<double>& controls) const;
  // Holds `controls` over the next step; entries past its end count as 0.
  void command(std::vector<ActuatorKindState>& states, const std::vector<double>& controls) const;
  // One step of every actuator's own dynamics.
  void actuate(std::vector<ActuatorKindState>& states) const;
  // The non-finite policy: every actuator at rest.
  static void stop(std::vector<ActuatorKindState>& states);
  static bool is_finite(const std::vector<ActuatorKindState>& states);

  // Adds every actuator's wrench (in actuator order) at the vehicle's pose.
  void add_wrenches(const ForceInput& in, StepWrench& out) const;

  // Kinds that drive a surface (kDrivesSurface: tracks, wheels) move their link's faces over the body:
  // per link, the velocity of its surface in B (zero for the others), for the soil contact
  // (physics/terramechanics.h). `belts` is resized to the vehicle's link count.
  void belt_velocities(const std::vector<ActuatorKindState>& states, std::vector<Eigen::Vector3d>& belts) const;
  // Hands each such actuator the soil's shear force on its link in the last step (per link, in W) as its
  // load; R_WB the vehicle's orientation then.
  void take_belt_forces(std::vector<ActuatorKindState>& states, const std::vector<Eigen::Vector3d>& link_forces_W,
                        const Eigen::Matrix3d& R_WB) const;
  bool drives_surfaces() const { return drives_surfaces_; }

  std::size_t num_controls() const { return num_controls_; }

 private:
  const VehicleSpec& vehicle_;
  const Ocean* ocean_;
  double surface_z_;
  std::vector<ActuatorKindRuntime> runtimes_;  // one per actuator
  std::vector<std::size_t> first_control_;     // index of each actuator's first control
  std::size_t num_controls_ = 0;
  bool drives_surfaces_ = false;
};

// The actuators as a force element: their wrenches, from the states actuate() left.
class ActuatorForces : public ForceElement {
 public:
  explicit ActuatorForces(const VehicleActuators& actuators) : actuators_(actuators) {}
  void add(const ForceInput& in, StepWrench& out) override { actuators_.add_wrenches(in, out); }

 private:
  const VehicleActuators& actuators_;
};

}  // namespace hadal::physics
