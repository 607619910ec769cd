// A vehicle's fluid model as a scenario describes it (YAML: a vehicle definition's `fluid`): the surface
// model's per-face coefficients (physics/surface_hydrodynamics.h) or the lumped model's damping
// (physics/lumped_fluid.h), and added mass (physics/added_mass.h). The keys are declared once in
// physics::fluid_keys() (server/src/physics/fluid_spec.cc); configs/REFERENCE.md shows them.
#pragma once

#include <Eigen/Geometry>

#include <optional>
#include <vector>

#include "hadal/config/key_table_fwd.h"

namespace hadal {
struct LinkSpec;
namespace config {
struct VehicleContext;
}
}  // namespace hadal

namespace hadal::physics {

// Per-body coefficients (scenario keys: the vehicle definition's fluid.hydrodynamics.{drag, skin_friction,
// lift, magnus}). Defaults:
//   drag 1.0: per-face Newtonian drag; a sphere then has C_D = 0.5 on its frontal area (the cos^3
//     integral over the front hemisphere is pi R^2 / 2), the subcritical sphere value (~0.47).
//   skin_friction 0.004: turbulent flat plate, 0.074 Re^-1/5 for Re ~ 1e6 .. 1e7.
//   lift 1.0: plate lift slope 2 C_L = 2 per radian, slender low-aspect-ratio wing (pi/2 AR, AR ~ 1.3).
//   magnus 0 [s]: to be calibrated (see above).
struct HydrodynamicCoefficients {
  double drag = 1.0;            // C_D [-]
  double skin_friction = 0.004; // C_f [-]
  double lift = 1.0;            // C_L [-]
  double magnus = 0.0;          // C_M [s]
  bool buoyancy = true;
};

}  // namespace hadal::physics

namespace hadal {

using Vector6d = Eigen::Matrix<double, 6, 1>;

enum class FluidModelType { kLumped, kSurface };

// kSurface (default): per-face forces on the links' hydrodynamic meshes
// (physics/surface_hydrodynamics.h) in the scenario's Ocean; buoyancy comes from pressure integration, so links' buoyancy volumes are not
// used. Coefficients in `hydrodynamics` (its `buoyancy` flag is always true from YAML).
// kLumped: Fossen-style lumped fluid model: buoyancy rho g V at the centre of buoyancy, and
// damping in the body frame, tau = -(D_l + D_q |nu|) nu with nu = [u v w p q r] relative to the water.
// Coefficients are magnitudes (>= 0): linear [N s/m x3, N m s/rad x3], quadratic [N s^2/m^2 x3,
// N m s^2/rad^2 x3].

// Added mass and inertia (physics/added_mass.h). The fluid accelerated with the body adds the 6x6
// matrix M_A to its inertia; at depth d it is scaled by kappa(d) = 1 - p(d)/K (paper; K from
// world.water.bulk_modulus), and its Coriolis-centripetal terms C_A(nu_r) nu_r (Fossen 2011, eq.
// 6.43; they contain the Munk moment) act with it.
//   kNone       no added mass.
//   kEllipsoid  Lamb's ellipsoid coefficients (rho0 V k-factors, rho0 from world.water) of
//               - the given semi-axes, ellipsoid frame E at X_BE (semi_axes_E set), or
//               - the hydrodynamic mesh's inertia-equivalent ellipsoid (same volume, same principal
//                 second moments, centred at the enclosed volume's centroid) otherwise.
//   kMatrix     a given 6x6 M_A0 [kg, kg m, kg m^2] at the surface, about the point p_BR, in B axes.
enum class AddedMassModel { kNone, kEllipsoid, kMatrix };

using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct AddedMassSpec {
  AddedMassModel model = AddedMassModel::kEllipsoid;
  std::optional<Eigen::Vector3d> semi_axes_E;              // [m]; empty: fit to the hull
  Eigen::Isometry3d X_BE = Eigen::Isometry3d::Identity();  // ellipsoid centre and axes in B
  Matrix6d M_A0 = Matrix6d::Zero();                        // kMatrix, symmetric positive semidefinite
  Eigen::Vector3d p_BR = Eigen::Vector3d::Zero();          // kMatrix reference point in B [m]
  bool coriolis = true;                                    // C_A(nu_r) nu_r on/off
};

struct FluidSpec {
  FluidModelType model = FluidModelType::kSurface;
  AddedMassSpec added_mass;
  Vector6d linear_damping = Vector6d::Zero();
  Vector6d quadratic_damping = Vector6d::Zero();
  physics::HydrodynamicCoefficients hydrodynamics;
};

namespace physics {
// A vehicle's fluid spec before its `fluid` keys: the surface model with added mass fitted to the hull
// when some link has faces (a mesh or collision shapes), else the lumped model without added mass.
FluidSpec default_fluid(const std::vector<LinkSpec>& links);
// The keys of `fluid` (context: the links, whose geometry decides the defaults).
const config::KeyTable<FluidSpec, config::VehicleContext>& fluid_keys();
}  // namespace physics

}  // namespace hadal
