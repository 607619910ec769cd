// The fluid model of a vehicle as a force element (physics/force_element.h), and its added mass.
//
// Surface model (FluidModelType::kSurface): SurfaceHydrodynamics over the vehicle's hydrodynamic mesh in
// B (its links' meshes, or their tessellated collision primitives) in the scenario's Ocean at the step's
// start time; buoyancy comes from pressure integration (links' buoyancy volumes are not used). Parts of a
// hull built from primitives may overlap: faces of one part inside another meet no flow, and the volume
// displaced twice (geometry/shape_overlap.h) is taken back as -rho g E at its centroid, ramped from dry
// to wet over its height. Lumped model (kLumped): LumpedFluid's buoyancy and damping relative to the
// current at the centre of mass. Both report the current at the centre of mass and the submerged fraction
// (the surface model's wetted-area fraction, the lumped model's volume fraction) for the added mass.
// Added mass (AddedMassSpec, physics/added_mass.h): M_A0 about the centre of mass in B axes -- none,
// a given matrix, or Lamb's coefficients of an ellipsoid (given, or the hull's inertia-equivalent one).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <memory>

#include "hadal/core/model.h"
#include "hadal/physics/force_element.h"

namespace hadal::physics {

class Ocean;

struct VehicleFluid {
  std::unique_ptr<ForceElement> force;  // the surface or the lumped model
  Matrix6d M_A0 = Matrix6d::Zero();     // added mass at the surface, about p_BBcm, B axes [kg, kg m, kg m^2]
  std::size_t faces = 0;                // faces the surface model evaluates each step (0: lumped)
};

// Builds the vehicle's fluid model in `ocean` (kept by reference) with its centre of mass at p_BBcm.
// Throws std::invalid_argument naming the vehicle for a surface model without faces, or an added-mass
// ellipsoid that cannot be fitted.
VehicleFluid make_vehicle_fluid(const VehicleSpec& vehicle, const WorldSpec& world, const Ocean& ocean,
                                const Eigen::Vector3d& p_BBcm);

// Earth-rotation Coriolis force F = -2 m Omega_W x v_WBcm at the centre of mass (world.dynamics),
// Omega_W = Omega_E (0, cos(lat), sin(lat)) in ENU at world.origin's latitude; the centrifugal part is
// inside g.
class EarthRotationForce : public ForceElement {
 public:
  EarthRotationForce(const WorldSpec& world, double mass);
  void add(const ForceInput& in, StepWrench& out) override;

 private:
  Eigen::Vector3d Omega_W_;  // [rad/s]
  double mass_;              // [kg]
};

}  // namespace hadal::physics
