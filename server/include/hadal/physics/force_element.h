// A force element (docs/ARCHITECTURE.md, "Force elements"): one source of force on a vehicle -- its
// actuators, the fluid model, the Earth's rotation, the soil -- that adds a wrench at the vehicle's
// centre of mass into the step's StepWrench (physics/actuator_kind.h). Gravity is Bullet's; added mass
// is not a force element: it converts the summed wrench afterwards (physics/added_mass.h). Elements know
// nothing of DDS; they hold constants and scratch of their own, so one vehicle's elements run on one
// thread at a time while other vehicles' run on others.
#pragma once

#include <Eigen/Geometry>

#include <limits>
#include <vector>

#include "hadal/core/state.h"
#include "hadal/physics/actuator_kind.h"

namespace hadal::physics {

// Per face of a vehicle's surface, its shear displacement j in the soil, in W [m] (zero out of contact;
// physics/terramechanics.h). Part of the vehicle's state (core/state.h), so a restored state continues
// the shear.
using SoilShearState = std::vector<Eigen::Vector3d>;

// What an element reads at the start of the step.
struct ForceInput {
  double time = 0.0;  // [s]
  const RigidBodyState& body;
  const Eigen::Vector3d& p_WBcm;  // composite centre of mass in W [m]
  const Eigen::Vector3d& v_WBcm;  // its velocity in W [m/s]
  // The vehicle's actuator states; the actuator element records the forces it applies (a thruster's
  // thrust and torque) in them.
  std::vector<ActuatorKindState>& actuators;
  // The vehicle's soil shear state (physics/terramechanics.h); null for a vehicle without soil contact.
  SoilShearState* soil_shear = nullptr;
  // Per link, the velocity of its surface relative to the body in B (a track's belt) [m/s]; null: none.
  const std::vector<Eigen::Vector3d>* belt_velocity_B = nullptr;
  // Height in W of the seabed under B's origin [m], for actuators that read it
  // (VehicleActuators::needs_seabed); -infinity where there is none or no actuator asked.
  double seabed_z_below = -std::numeric_limits<double>::infinity();
};

class ForceElement {
 public:
  virtual ~ForceElement() = default;
  // Adds this element's force and its moment about in.p_WBcm (both in W) into out.
  virtual void add(const ForceInput& in, StepWrench& out) = 0;
};

}  // namespace hadal::physics
