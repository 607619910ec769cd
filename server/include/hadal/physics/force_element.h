// A force element (docs/ARCHITECTURE.md, "Force elements"): one source of force on a vehicle -- its
// actuators, the fluid model, the Earth's rotation, next the soil -- that adds a wrench at the vehicle's
// centre of mass into the step's StepWrench (physics/actuator_kind.h). Gravity is Bullet's; added mass
// is not a force element: it converts the summed wrench afterwards (physics/added_mass.h). Elements know
// nothing of DDS; they hold constants and scratch of their own, so one vehicle's elements run on one
// thread at a time while other vehicles' run on others.
#pragma once

#include <Eigen/Geometry>

#include <vector>

#include "hadal/core/state.h"
#include "hadal/physics/actuator_kind.h"

namespace hadal::physics {

// What an element reads at the start of the step.
struct ForceInput {
  double time = 0.0;  // [s]
  const RigidBodyState& body;
  const Eigen::Vector3d& p_WBcm;  // composite centre of mass in W [m]
  const Eigen::Vector3d& v_WBcm;  // its velocity in W [m/s]
  // The vehicle's actuator states; the actuator element records the forces it applies (a thruster's
  // thrust and torque) in them.
  std::vector<ActuatorKindState>& actuators;
};

class ForceElement {
 public:
  virtual ~ForceElement() = default;
  // Adds this element's force and its moment about in.p_WBcm (both in W) into out.
  virtual void add(const ForceInput& in, StepWrench& out) = 0;
};

}  // namespace hadal::physics
