#include "hadal/physics/mass_properties.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hadal::physics {

MassProperties composite_mass_properties(const std::vector<LinkSpec>& links) {
  MassProperties props;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  for (const LinkSpec& link : links) {
    props.mass += link.mass;
    first_moment += link.mass * (link.X_BL * link.p_LLcm);
  }
  if (!(props.mass > 0.0) || !std::isfinite(props.mass)) {
    throw std::invalid_argument("composite mass must be finite and > 0 (got " +
                                std::to_string(props.mass) + " kg)");
  }
  props.p_BBcm = first_moment / props.mass;

  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  for (const LinkSpec& link : links) {
    const Eigen::Matrix3d R_BL = link.X_BL.linear();
    const Eigen::Vector3d r = link.X_BL * link.p_LLcm - props.p_BBcm;
    I += R_BL * link.I_LLcm_L * R_BL.transpose();
    I += link.mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  // Symmetrise so round-off in the rotations cannot make the eigen-solver see an asymmetric matrix.
  props.I_BBcm_B = 0.5 * (I + I.transpose());

  Eigen::Matrix3d R_BP = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d& J = props.I_BBcm_B;
  if (J(0, 1) == 0.0 && J(0, 2) == 0.0 && J(1, 2) == 0.0) {
    props.I_principal = J.diagonal();
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(J);
    R_BP = solver.eigenvectors();
    if (R_BP.determinant() < 0.0) R_BP.col(2) = -R_BP.col(2);  // keep P right-handed
    props.I_principal = solver.eigenvalues();
  }
  props.X_BP = Eigen::Isometry3d::Identity();
  props.X_BP.linear() = R_BP;
  props.X_BP.translation() = props.p_BBcm;
  return props;
}

Eigen::Matrix3d solid_box_inertia(double mass, const Eigen::Vector3d& size) {
  const Eigen::Vector3d s2 = size.cwiseProduct(size);
  return (mass / 12.0) *
         Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y()).asDiagonal();
}

Eigen::Matrix3d solid_sphere_inertia(double mass, double radius) {
  return (0.4 * mass * radius * radius) * Eigen::Matrix3d::Identity();
}

Eigen::Matrix3d solid_cylinder_inertia(double mass, double radius, double length) {
  const double transverse = mass * (3.0 * radius * radius + length * length) / 12.0;
  const double axial = 0.5 * mass * radius * radius;
  return Eigen::Vector3d(transverse, transverse, axial).asDiagonal();
}

}  // namespace hadal::physics
