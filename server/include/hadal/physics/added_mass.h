// Added mass and inertia of a body in an ideal fluid, and how it enters Bullet's rigid-body step.
//
// Generalised velocity nu = [v; w] of the body at its centre of mass C, in B axes (Fossen's nu at
// the CG); wrenches tau = [f; m] at C in B axes. The fluid adds the symmetric 6x6 matrix M_A to the
// body's inertia (kinetic energy of the fluid T_A = 1/2 nu^T M_A nu).
//
// Ellipsoid estimate (Lamb 1932, sec. 114-115; Imlay 1961, DTMB report 1528). A solid ellipsoid with
// semi-axes a, b, c along its frame E's x, y, z, volume V = 4/3 pi a b c, in fluid of density rho:
//   alpha0 = a b c int_0^inf dl / ((a^2 + l) Delta(l)),  Delta = sqrt((a^2+l)(b^2+l)(c^2+l)),
//   beta0, gamma0 likewise with b^2, c^2 in the first factor; alpha0 + beta0 + gamma0 = 2.
//   In Carlson's form alpha0 = 2/3 a b c R_D(b^2, c^2, a^2) (R_D by the duplication algorithm).
//   translation  m_11 = alpha0 / (2 - alpha0) rho V   (m_22 with beta0, m_33 with gamma0)
//   rotation     m_44 = rho V / 5 (b^2 - c^2)^2 (gamma0 - beta0) / (2 (b^2 - c^2) + (b^2 + c^2)(beta0 - gamma0))
//                (m_55, m_66 by cyclic permutation a -> b -> c); 0 for an axis of revolution.
//   about the ellipsoid's centre, in E axes, diagonal. A sphere: 1/2 rho V in translation, 0 in rotation.
//
// Inertia-equivalent ellipsoid of a closed hull: a solid ellipsoid has second moments
// int x^2 dV = V a^2 / 5 along its axes, so the ellipsoid with the hull's volume centroid, principal
// axes and second moments (C = int (x - c)(x - c)^T dV = R diag(V a_k^2 / 5) R^T) is
// a_k = sqrt(5 lambda_k / V), rescaled by (V / (4/3 pi a b c))^(1/3) to the hull's volume.
//
// Moving a 6x6 added-mass matrix (Fossen 2011, sec. 7.5, system transformation matrix): with M_O
// about point O in axes E, R = R_BE and r = p_BO - p_BC, the velocity at O in E axes is
// nu_O = H nu_C with H = [R^T, -R^T S(r); 0, R^T] (v_O = v_C + w x r), so M_C = H^T M_O H.
//
// Depth scaling (paper): M_A(d) = kappa(d) M_A0 with kappa = 1 - p(d)/K.
//
// Coriolis-centripetal terms (Fossen 2011, eq. 6.43), with p = A11 v + A12 w and h = A21 v + A22 w:
//   C_A(nu) nu = [ w x p ;  v x p + w x h ]     (on the left-hand side, like M_A nu_dot)
// For a slender body (m_22 > m_11) moving with sideslip this contains the Munk moment
// -(m_22 - m_11) u v about z on the right-hand side, which turns the body further across the flow.
//
// Bullet does not know M_A. The equations of motion at C in B axes are
//   M_RB nu_dot + M_A nu_r_dot + C_RB(nu) nu + C_A(nu_r) nu_r = tau + g_RB + tau_c,
// nu_r = nu - [v_water_B; 0] for a current constant in W (irrotational), whose B components turn with
// the body: nu_r_dot = nu_dot + [w x v_water_B; 0] (Fossen 2011, sec. 10.3),
// tau the applied wrench (thrusters, fluid), g_RB = [m R_WB^T g_W; 0] gravity, tau_c contacts,
// C_RB(nu) nu = [m w x v; w x (I w)] the rigid-body terms (Bullet's world-frame integration contains
// them; the gyroscopic part only while it is enabled). Bullet integrates
//   M_RB nu_dot + C_RB nu = tau_bullet + g_RB + tau_c_bullet,
// so the wrench to hand to Bullet is tau_bullet = M_RB nu_dot + C_RB nu - g_RB - tau_c with
//   nu_dot = (M_RB + M_A)^-1 (tau + g_RB + tau_c - C_RB nu - C_A nu_r - M_A [w x v_water_B; 0]).
// Applied forces are thereby exact (a body sinking from rest accelerates at
// (m - rho V) g / (m + m_a)); no added-mass acceleration is differentiated, so the scheme is stable for
// any M_A / M_RB. Bullet's contact impulses see M_RB only; tau_c, the contact wrench Bullet applied in
// the previous step (measured from the velocity change), stands in for this step's, so a body resting
// on the seabed presses on it with its full submerged weight (the one-step lag converges with factor
// M_A (M_RB + M_A)^-1 < 1 after an impact).
//
// Units: SI (kg, kg m, kg m^2, m, s, N, N m).
#pragma once

#include <Eigen/Geometry>

#include "hadal/core/model.h"

namespace hadal::geometry {
struct MeshProperties;
}

namespace hadal::physics {

// Carlson's symmetric elliptic integral of the second kind R_D(x, y, z) = 3/2 int_0^inf dt /
// ((t + z) sqrt((t + x)(t + y)(t + z))), x, y >= 0 (at most one zero), z > 0. Relative error < 1e-14.
double carlson_rd(double x, double y, double z);

// Lamb's alpha0, beta0, gamma0 of an ellipsoid with semi-axes (a, b, c) > 0.
Eigen::Vector3d lamb_coefficients(const Eigen::Vector3d& semi_axes);

// Added mass of the ellipsoid about its centre in E axes (diagonal) [kg, kg m^2].
Matrix6d ellipsoid_added_mass(const Eigen::Vector3d& semi_axes, double density);

struct Ellipsoid {
  Eigen::Vector3d semi_axes = Eigen::Vector3d::Zero();     // along E's x, y, z [m]
  Eigen::Isometry3d X_BE = Eigen::Isometry3d::Identity();  // centre and axes in the mesh's frame
};

// The inertia-equivalent ellipsoid of a closed mesh (positions in B) with properties `props`.
// Throws std::invalid_argument if the mesh is not closed or encloses no volume.
Ellipsoid equivalent_ellipsoid(const geometry::MeshProperties& props);

// M_A about C = p_BC in B axes from M_O about p_BO in E axes (R_BE), see above.
Matrix6d shift_added_mass(const Matrix6d& M_O, const Eigen::Matrix3d& R_BE,
                          const Eigen::Vector3d& p_BO, const Eigen::Vector3d& p_BC);

// The cross-product matrix: skew(a) b = a x b.
Eigen::Matrix3d skew(const Eigen::Vector3d& a);

// C_A(nu) nu for added-mass matrix M_A (about C, B axes).
Vector6d added_mass_coriolis(const Matrix6d& M_A, const Vector6d& nu);

// Rigid-body inertia of the vehicle at C in B axes.
struct RigidBodyInertia {
  double mass = 0.0;                               // [kg]
  Eigen::Matrix3d I_BC_B = Eigen::Matrix3d::Zero();  // B about its centre of mass C, B axes [kg m^2]
};

struct AddedMassInput {
  double kappa = 1.0;                             // compression factor at the vehicle's depth
  Vector6d nu = Vector6d::Zero();                 // [v_WC; w_WB] in B axes
  Vector6d nu_r = Vector6d::Zero();               // nu relative to the water (v - v_water) in B axes
  Vector6d tau = Vector6d::Zero();                // applied wrench at C, B axes (no gravity, no contact)
  Eigen::Vector3d gravity_B = Eigen::Vector3d::Zero();  // g in B axes [m/s^2]
  Vector6d tau_contact = Vector6d::Zero();        // contact wrench of the previous step at C, B axes
};

// Turns applied wrenches into the wrench Bullet must receive so that its rigid-body step follows the
// equations of motion with added mass (see above). Immutable; allocation-free.
class AddedMassDynamics {
 public:
  // M_A0: added mass at the surface about C in B axes. coriolis: include C_A(nu_r) nu_r.
  // gyroscopic: whether Bullet applies w x (I w) (DynamicsSpec::gyroscopic).
  AddedMassDynamics(const RigidBodyInertia& body, const Matrix6d& M_A0, bool coriolis, bool gyroscopic);

  // nu_dot of the equations of motion, B axes.
  Vector6d acceleration(const AddedMassInput& in) const;
  // tau_bullet, at C in B axes.
  Vector6d bullet_wrench(const AddedMassInput& in) const;
  // C_RB(nu) nu as Bullet integrates it.
  Vector6d rigid_body_coriolis(const Vector6d& nu) const;
  // The contact wrench (B axes at the step's start) Bullet applied during a step of dt that took
  // nu0 to nu1_B0 (the new velocity expressed in the *start* B axes, so the difference is the
  // inertial-frame change) while it was given tau_bullet besides gravity g_B:
  //   M_RB (nu1_B0 - nu0) / dt + [0; w0 x (I w0) if gyroscopic] - tau_bullet - g_RB.
  Vector6d contact_wrench(const Vector6d& nu0, const Vector6d& nu1_B0, double dt,
                          const Vector6d& tau_bullet, const Eigen::Vector3d& gravity_B) const;

  const Matrix6d& rigid_body_mass() const { return M_RB_; }
  const Matrix6d& added_mass_surface() const { return M_A0_; }

 private:
  Matrix6d M_RB_;
  Matrix6d M_A0_;
  double mass_;
  Eigen::Matrix3d I_BC_B_;
  bool coriolis_;
  bool gyroscopic_;
};

}  // namespace hadal::physics
