#include "hadal/physics/added_mass.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hadal/geometry/mesh_properties.h"
#include "hadal/core/units.h"

namespace hadal::physics {

Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

namespace {



// Lamb's rotational coefficient about the axis whose two perpendicular semi-axes are p, q with
// coefficients P, Q (m_44: p = b, q = c, P = beta0, Q = gamma0). rho V / 5 times the ratio, which is
// 0/0 for p = q (a body of revolution about this axis has no added inertia about it): the limit is 0.
double rotational_factor(double p, double q, double P, double Q) {
  const double d2 = p * p - q * q;
  if (std::abs(d2) <= 1e-12 * (p * p + q * q)) return 0.0;
  return d2 * d2 * (Q - P) / (2.0 * d2 + (p * p + q * q) * (P - Q)) / 5.0;
}

}  // namespace

// Carlson (1995), "Numerical computation of real or complex elliptic integrals", algorithm for R_D:
// duplicate x, y, z towards their mean A; each step adds 1/(4^k sqrt(z_k) (z_k + lambda_k)); stop when
// the relative spread is below 1e-3 (truncation error of the 5th-order series ~ spread^6 / (1 - spread)
// < 1e-17), then evaluate the series.
double carlson_rd(double x, double y, double z) {
  if (!(x >= 0.0) || !(y >= 0.0) || !(z > 0.0) || x + y == 0.0) {
    throw std::invalid_argument("carlson_rd: need x, y >= 0 (not both 0) and z > 0");
  }
  double sum = 0.0;
  double factor = 1.0;
  double mean = 0.0, dx = 0.0, dy = 0.0, dz = 0.0;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z);
    const double lambda = sx * (sy + sz) + sy * sz;
    sum += factor / (sz * (z + lambda));
    factor *= 0.25;
    x = 0.25 * (x + lambda);
    y = 0.25 * (y + lambda);
    z = 0.25 * (z + lambda);
    mean = 0.2 * (x + y + 3.0 * z);
    dx = (mean - x) / mean;
    dy = (mean - y) / mean;
    dz = (mean - z) / mean;
    if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) < 1e-3) break;
  }
  const double ea = dx * dy, eb = dz * dz, ec = ea - eb, ed = ea - 6.0 * eb, ee = ed + ec + ec;
  constexpr double c1 = 3.0 / 14.0, c2 = 1.0 / 6.0, c3 = 9.0 / 22.0, c4 = 3.0 / 26.0;
  constexpr double c5 = 0.25 * c3, c6 = 1.5 * c4;
  const double series = 1.0 + ed * (-c1 + c5 * ed - c6 * dz * ee) +
                        dz * (c2 * ee + dz * (-c3 * ec + dz * c4 * ea));
  return 3.0 * sum + factor * series / (mean * std::sqrt(mean));
}

Eigen::Vector3d lamb_coefficients(const Eigen::Vector3d& semi_axes) {
  if (!(semi_axes.minCoeff() > 0.0) || !semi_axes.allFinite()) {
    throw std::invalid_argument("ellipsoid semi-axes must be finite and > 0");
  }
  const double a = semi_axes.x(), b = semi_axes.y(), c = semi_axes.z();
  const double abc = a * b * c;
  return {2.0 / 3.0 * abc * carlson_rd(b * b, c * c, a * a),
          2.0 / 3.0 * abc * carlson_rd(c * c, a * a, b * b),
          2.0 / 3.0 * abc * carlson_rd(a * a, b * b, c * c)};
}

Matrix6d ellipsoid_added_mass(const Eigen::Vector3d& semi_axes, double density) {
  const Eigen::Vector3d k = lamb_coefficients(semi_axes);
  const double a = semi_axes.x(), b = semi_axes.y(), c = semi_axes.z();
  const double rho_V = density * 4.0 / 3.0 * kPi * a * b * c;
  Vector6d diagonal;
  for (int i = 0; i < 3; ++i) diagonal[i] = k[i] / (2.0 - k[i]) * rho_V;
  diagonal[3] = rho_V * rotational_factor(b, c, k.y(), k.z());
  diagonal[4] = rho_V * rotational_factor(c, a, k.z(), k.x());
  diagonal[5] = rho_V * rotational_factor(a, b, k.x(), k.y());
  return diagonal.asDiagonal();
}

Ellipsoid equivalent_ellipsoid(const geometry::MeshProperties& props) {
  if (!props.closed || !(props.volume > 0.0)) {
    throw std::invalid_argument(
        "added mass from the hull needs a closed, outward-oriented hydrodynamic mesh enclosing a "
        "volume");
  }
  // inertia_unit_density I = tr(C) 1 - C, so C = tr(I)/2 1 - I.
  const Eigen::Matrix3d& I = props.inertia_unit_density;
  const Eigen::Matrix3d C = 0.5 * I.trace() * Eigen::Matrix3d::Identity() - I;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(C);
  Eigen::Matrix3d R = solver.eigenvectors();
  if (R.determinant() < 0.0) R.col(2) = -R.col(2);
  // Keep E's axes as close to B's as the eigen-decomposition allows: if C is (nearly) diagonal, use
  // B's axes directly so that a hull along x gets its long axis as E's x.
  const double off_diagonal = C(0, 1) * C(0, 1) + C(0, 2) * C(0, 2) + C(1, 2) * C(1, 2);
  Eigen::Vector3d moments = solver.eigenvalues();
  if (off_diagonal <= 1e-20 * C.squaredNorm()) {
    R.setIdentity();
    moments = C.diagonal();
  }
  Ellipsoid e;
  for (int k = 0; k < 3; ++k) {
    e.semi_axes[k] = std::sqrt(5.0 * std::max(moments[k], 0.0) / props.volume);
  }
  if (!(e.semi_axes.minCoeff() > 0.0)) {
    throw std::invalid_argument("added mass from the hull: the hull is flat along one axis");
  }
  const double volume_e = 4.0 / 3.0 * kPi * e.semi_axes.prod();
  e.semi_axes *= std::cbrt(props.volume / volume_e);
  e.X_BE.linear() = R;
  e.X_BE.translation() = props.centroid;
  return e;
}

Matrix6d shift_added_mass(const Matrix6d& M_O, const Eigen::Matrix3d& R_BE,
                          const Eigen::Vector3d& p_BO, const Eigen::Vector3d& p_BC) {
  Matrix6d H = Matrix6d::Zero();
  const Eigen::Matrix3d R_EB = R_BE.transpose();
  H.topLeftCorner<3, 3>() = R_EB;
  H.topRightCorner<3, 3>() = -R_EB * skew(p_BO - p_BC);
  H.bottomRightCorner<3, 3>() = R_EB;
  const Matrix6d M_C = H.transpose() * M_O * H;
  return 0.5 * (M_C + M_C.transpose());
}

Vector6d added_mass_coriolis(const Matrix6d& M_A, const Vector6d& nu) {
  const Eigen::Vector3d v = nu.head<3>(), w = nu.tail<3>();
  const Eigen::Vector3d p = M_A.topRows<3>() * nu;
  const Eigen::Vector3d h = M_A.bottomRows<3>() * nu;
  Vector6d out;
  out.head<3>() = w.cross(p);
  out.tail<3>() = v.cross(p) + w.cross(h);
  return out;
}

AddedMassDynamics::AddedMassDynamics(const RigidBodyInertia& body, const Matrix6d& M_A0,
                                     bool coriolis, bool gyroscopic)
    : M_RB_(Matrix6d::Zero()),
      M_A0_(M_A0),
      mass_(body.mass),
      I_BC_B_(body.I_BC_B),
      coriolis_(coriolis),
      gyroscopic_(gyroscopic) {
  M_RB_.topLeftCorner<3, 3>() = body.mass * Eigen::Matrix3d::Identity();
  M_RB_.bottomRightCorner<3, 3>() = body.I_BC_B;
}

Vector6d AddedMassDynamics::rigid_body_coriolis(const Vector6d& nu) const {
  const Eigen::Vector3d v = nu.head<3>(), w = nu.tail<3>();
  Vector6d out;
  out.head<3>() = mass_ * w.cross(v);
  out.tail<3>() = gyroscopic_ ? Eigen::Vector3d(w.cross(I_BC_B_ * w)) : Eigen::Vector3d::Zero();
  return out;
}

Vector6d AddedMassDynamics::acceleration(const AddedMassInput& in) const {
  Vector6d rhs = in.tau + in.tau_contact - rigid_body_coriolis(in.nu);
  rhs.head<3>() += mass_ * in.gravity_B;
  if (coriolis_) rhs -= in.kappa * added_mass_coriolis(M_A0_, in.nu_r);
  // M_A acts on the relative acceleration nu_r_dot = nu_dot + [w x v_water_B; 0] (a current constant
  // in W turns in B as the body rotates; Fossen 2011, sec. 10.3): move the known part to the right.
  Vector6d frame_term = Vector6d::Zero();
  frame_term.head<3>() = in.nu.tail<3>().cross(Eigen::Vector3d(in.nu.head<3>() - in.nu_r.head<3>()));
  rhs -= in.kappa * (M_A0_ * frame_term);
  const Matrix6d M = M_RB_ + in.kappa * M_A0_;
  return M.llt().solve(rhs);
}

Vector6d AddedMassDynamics::bullet_wrench(const AddedMassInput& in) const {
  Vector6d tau = M_RB_ * acceleration(in) + rigid_body_coriolis(in.nu) - in.tau_contact;
  tau.head<3>() -= mass_ * in.gravity_B;
  return tau;
}

Vector6d AddedMassDynamics::contact_wrench(const Vector6d& nu0, const Vector6d& nu1_B0, double dt,
                                           const Vector6d& tau_bullet,
                                           const Eigen::Vector3d& gravity_B) const {
  Vector6d tau_c = M_RB_ * (nu1_B0 - nu0) / dt - tau_bullet;
  tau_c.head<3>() -= mass_ * gravity_B;
  if (gyroscopic_) {
    const Eigen::Vector3d w = nu0.tail<3>();
    tau_c.tail<3>() += w.cross(I_BC_B_ * w);
  }
  return tau_c;
}

}  // namespace hadal::physics
