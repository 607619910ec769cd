// Composite mass properties of a vehicle whose links are rigidly attached to the body frame B, and
// the principal frame P that Bullet needs (a rigid body's origin at its centre of mass, axes along
// its principal axes, so its inertia is diagonal).
//
//   m        = sum_i m_i
//   p_BBcm   = (1/m) sum_i m_i p_BLicm,            p_BLicm = X_BLi * p_LiLicm
//   I_BBcm_B = sum_i [R_BLi I_Licm R_BLi^T + m_i (|r_i|^2 1 - r_i r_i^T)], r_i = p_BLicm - p_BBcm
//   I_BBcm_B = R_BP diag(I_principal) R_BP^T   (eigen-decomposition, det R_BP = +1)
//   X_BP     = [R_BP, p_BBcm]
//
// Units: kg, m, kg m^2. Inertias are about the stated centre of mass and expressed in the stated
// axes.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "hadal/core/model.h"

namespace hadal::physics {

struct MassProperties {
  double mass = 0.0;                                   // [kg]
  Eigen::Vector3d p_BBcm = Eigen::Vector3d::Zero();    // composite centre of mass in B [m]
  Eigen::Matrix3d I_BBcm_B = Eigen::Matrix3d::Zero();  // inertia about Bcm, B axes [kg m^2]
  Eigen::Isometry3d X_BP =
      Eigen::Isometry3d::Identity();  // principal frame: origin Bcm, principal axes
  Eigen::Vector3d I_principal = Eigen::Vector3d::Zero();  // inertia in P (diagonal) [kg m^2]
};

// Composite mass properties of `links` (all attached to B through LinkSpec::X_BL). When I_BBcm_B is
// already diagonal, R_BP is the identity (no axis permutation); otherwise the principal axes are
// sorted by increasing moment. Throws std::invalid_argument if the total mass is not > 0 or not
// finite.
MassProperties composite_mass_properties(const std::vector<LinkSpec>& links);

// Inertia about the centre of mass of homogeneous solids, in the solid's own frame [kg m^2].
// Box with full extents `size`; cylinder with its axis along z and length `length`.
Eigen::Matrix3d solid_box_inertia(double mass, const Eigen::Vector3d& size);
Eigen::Matrix3d solid_sphere_inertia(double mass, double radius);
Eigen::Matrix3d solid_cylinder_inertia(double mass, double radius, double length);

}  // namespace hadal::physics
