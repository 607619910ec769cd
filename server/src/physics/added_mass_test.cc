#include "hadal/physics/added_mass.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/core/units.h"

namespace hadal::physics {
namespace {

constexpr double kRho = 1025.0;

// Carlson (1995), table of test values for R_D (printed to 13-14 digits).
TEST(CarlsonRd, MatchesPublishedValues) {
  EXPECT_NEAR(carlson_rd(0.0, 2.0, 1.0), 1.7972103521034, 1e-12);
  EXPECT_NEAR(carlson_rd(2.0, 3.0, 4.0), 0.16510527294261, 1e-13);
  // R_D(x, x, x) = x^(-3/2).
  EXPECT_NEAR(carlson_rd(4.0, 4.0, 4.0), 0.125, 1e-15);
}

TEST(LambCoefficients, SphereAndSum) {
  const Eigen::Vector3d k = lamb_coefficients(Eigen::Vector3d(0.3, 0.3, 0.3));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(k[i], 2.0 / 3.0, 1e-14);
  const Eigen::Vector3d k2 = lamb_coefficients(Eigen::Vector3d(1.0, 0.4, 0.15));
  EXPECT_NEAR(k2.sum(), 2.0, 1e-13);  // alpha0 + beta0 + gamma0 = 2 for every ellipsoid
}

// Prolate spheroid a > b = c, eccentricity e = sqrt(1 - b^2/a^2) (Lamb sec. 115, Newman 1977 table 4.?):
//   alpha0 = 2 (1 - e^2) / e^3 (1/2 ln((1+e)/(1-e)) - e),  beta0 = 1/e^2 - (1 - e^2)/(2 e^3) ln((1+e)/(1-e)).
TEST(LambCoefficients, ProlateSpheroidClosedForm) {
  for (double ratio : {1.5, 3.0, 8.0}) {
    const double a = 1.0, b = a / ratio;
    const double e = std::sqrt(1.0 - b * b / (a * a));
    const double log_term = std::log((1.0 + e) / (1.0 - e));
    const double alpha0 = 2.0 * (1.0 - e * e) / (e * e * e) * (0.5 * log_term - e);
    const double beta0 = 1.0 / (e * e) - (1.0 - e * e) / (2.0 * e * e * e) * log_term;
    const Eigen::Vector3d k = lamb_coefficients(Eigen::Vector3d(a, b, b));
    EXPECT_NEAR(k.x(), alpha0, 1e-12) << ratio;
    EXPECT_NEAR(k.y(), beta0, 1e-12) << ratio;
    EXPECT_NEAR(k.z(), beta0, 1e-12) << ratio;
  }
}

TEST(EllipsoidAddedMass, SphereIsHalfDisplacedMassAndNoRotation) {
  const double r = 0.5;
  const Matrix6d M = ellipsoid_added_mass(Eigen::Vector3d(r, r, r), kRho);
  const double displaced = kRho * 4.0 / 3.0 * kPi * r * r * r;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(M(i, i), 0.5 * displaced, 1e-10 * displaced);
  for (int i = 3; i < 6; ++i) EXPECT_EQ(M(i, i), 0.0);
  EXPECT_EQ((M - Matrix6d(M.diagonal().asDiagonal())).norm(), 0.0);
}

// Prolate spheroid in closed form (Lamb, Hydrodynamics, sec. 373), independent of the R_D route:
// k1 = alpha0 / (2 - alpha0), k2 = beta0 / (2 - beta0) (fractions of the displaced mass) and
// k' = e^4 (beta0 - alpha0) / ((2 - e^2)(2 e^2 - (2 - e^2)(beta0 - alpha0))) (fraction of the displaced
// fluid's moment of inertia rho V (a^2 + b^2) / 5 about a transverse axis), with alpha0, beta0 from e
// as above. Lamb's table lists 0.210 / 0.704 / 0.240 at a/b = 2 and 0.021 / 0.960 / 0.883 at 10.
TEST(EllipsoidAddedMass, ProlateSpheroidClosedForm) {
  for (double ratio : {2.0, 5.0, 10.0}) {
    const double a = 1.0, b = 1.0 / ratio;
    const double e2 = 1.0 - b * b / (a * a), e = std::sqrt(e2);
    const double log_term = std::log((1.0 + e) / (1.0 - e));
    const double alpha0 = 2.0 * (1.0 - e2) / (e2 * e) * (0.5 * log_term - e);
    const double beta0 = 1.0 / e2 - (1.0 - e2) / (2.0 * e2 * e) * log_term;
    const double k1 = alpha0 / (2.0 - alpha0), k2 = beta0 / (2.0 - beta0);
    const double k_rot =
        e2 * e2 * (beta0 - alpha0) / ((2.0 - e2) * (2.0 * e2 - (2.0 - e2) * (beta0 - alpha0)));
    const double displaced = kRho * 4.0 / 3.0 * kPi * a * b * b;
    const Matrix6d M = ellipsoid_added_mass(Eigen::Vector3d(a, b, b), kRho);
    EXPECT_NEAR(M(0, 0) / displaced, k1, 1e-11) << ratio;
    EXPECT_NEAR(M(1, 1) / displaced, k2, 1e-11) << ratio;
    EXPECT_NEAR(M(2, 2) / displaced, k2, 1e-11) << ratio;
    EXPECT_EQ(M(3, 3), 0.0);  // axis of revolution
    const double fluid_inertia = displaced * (a * a + b * b) / 5.0;
    EXPECT_NEAR(M(4, 4) / fluid_inertia, k_rot, 1e-9) << ratio;
    EXPECT_NEAR(M(5, 5) / fluid_inertia, k_rot, 1e-9) << ratio;
  }
  // Lamb's printed table, three decimals (its entries also carry the table's own rounding of a/b).
  const Matrix6d M2 = ellipsoid_added_mass(Eigen::Vector3d(1.0, 0.5, 0.5), kRho);
  const double displaced2 = kRho * 4.0 / 3.0 * kPi * 0.25;
  EXPECT_NEAR(M2(0, 0) / displaced2, 0.210, 1e-3);
  EXPECT_NEAR(M2(1, 1) / displaced2, 0.704, 1e-3);
  EXPECT_NEAR(M2(5, 5) / (displaced2 * 1.25 / 5.0), 0.240, 1e-3);
}

// Lamb's integral alpha0 = a b c int_0^inf dl / ((a^2 + l) D(l)), D = sqrt((a^2+l)(b^2+l)(c^2+l)) (and beta0,
// gamma0 with b, c in the first factor), by quadrature, independent of Carlson's R_D: l = s^2 (1/u^2 - 1)
// with s the smallest semi-axis maps [0, inf) onto u in (0, 1] with an integrand smooth at both ends (~u^2
// near 0; varying on a scale of order 1 near u = 1), and composite Simpson on 4000 panels agrees with 1000
// panels to 4e-15.
Eigen::Vector3d lamb_by_quadrature(double a, double b, double c) {
  const double s2 = std::min({a, b, c}) * std::min({a, b, c});
  const Eigen::Vector3d squares(a * a, b * b, c * c);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const int n = 4000;
  for (int i = 0; i <= n; ++i) {
    const double u = static_cast<double>(i) / n;
    if (u == 0.0) continue;  // the integrand's limit there is 0
    const double l = s2 * (1.0 / (u * u) - 1.0), dl_du = 2.0 * s2 / (u * u * u);
    const double D = std::sqrt((squares.array() + l).prod());
    const double weight = (i == n ? 1.0 : (i % 2 ? 4.0 : 2.0)) / (3.0 * n);
    sum += weight * dl_du * (a * b * c / D) * (squares.array() + l).inverse().matrix();
  }
  return sum;
}

// A triaxial ellipsoid a > b > c (no two axes alike, so a swapped axis shows): every diagonal term against
// Lamb's closed forms (Hydrodynamics sec. 373), written out per axis with alpha0, beta0, gamma0 from the
// quadrature above. Translation: k_i / (2 - k_i) of the displaced mass; rotation about x:
//   m44 = rho V / 5 (b^2 - c^2)^2 (gamma0 - beta0) / (2 (b^2 - c^2) + (b^2 + c^2)(beta0 - gamma0)),
// about y and z likewise with (c, a, gamma0, alpha0) and (a, b, alpha0, beta0). Tolerance 1e-9 relative:
// the quadrature's 1e-14, amplified by the rotational terms' differences of nearly equal numbers.
TEST(EllipsoidAddedMass, TriaxialEllipsoidMatchesLambOnEveryAxis) {
  const double a = 1.0, b = 0.4, c = 0.15;
  const Eigen::Vector3d k = lamb_by_quadrature(a, b, c);
  const double alpha0 = k.x(), beta0 = k.y(), gamma0 = k.z();
  EXPECT_NEAR(alpha0 + beta0 + gamma0, 2.0, 1e-11);  // the quadrature itself
  EXPECT_NEAR((lamb_coefficients(Eigen::Vector3d(a, b, c)) - k).norm(), 0.0, 1e-11);
  const double rho_V = kRho * 4.0 / 3.0 * kPi * a * b * c;
  const double a2 = a * a, b2 = b * b, c2 = c * c;
  const double m44 = rho_V / 5.0 * (b2 - c2) * (b2 - c2) * (gamma0 - beta0) /
                     (2.0 * (b2 - c2) + (b2 + c2) * (beta0 - gamma0));
  const double m55 = rho_V / 5.0 * (c2 - a2) * (c2 - a2) * (alpha0 - gamma0) /
                     (2.0 * (c2 - a2) + (c2 + a2) * (gamma0 - alpha0));
  const double m66 = rho_V / 5.0 * (a2 - b2) * (a2 - b2) * (beta0 - alpha0) /
                     (2.0 * (a2 - b2) + (a2 + b2) * (alpha0 - beta0));
  const Vector6d expected(alpha0 / (2.0 - alpha0) * rho_V, beta0 / (2.0 - beta0) * rho_V,
                          gamma0 / (2.0 - gamma0) * rho_V, m44, m55, m66);
  // The six are distinct (the closest two, m22 and m55, 6 % apart): an exchange of two cannot pass.
  for (int i = 0; i < 6; ++i) {
    for (int j = i + 1; j < 6; ++j) {
      EXPECT_GT(std::abs(expected[i] - expected[j]), 0.05 * std::max(expected[i], expected[j])) << i << ' ' << j;
    }
  }
  const Matrix6d M = ellipsoid_added_mass(Eigen::Vector3d(a, b, c), kRho);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(M(i, i), expected[i], 1e-9 * expected[i]) << i;
  EXPECT_EQ((M - Matrix6d(M.diagonal().asDiagonal())).norm(), 0.0);
}

// A circular disc of radius R moving broadside carries 8/3 rho R^3 (Lamb sec. 108): the limit c -> 0
// of the oblate ellipsoid. With c = 1e-6 R the ellipsoid result differs by O(c/R).
TEST(EllipsoidAddedMass, ThinDiscLimit) {
  const double R = 0.4;
  const Matrix6d M = ellipsoid_added_mass(Eigen::Vector3d(R, R, 1e-6 * R), kRho);
  const double disc = 8.0 / 3.0 * kRho * R * R * R;
  EXPECT_NEAR(M(2, 2), disc, 1e-5 * disc);
  EXPECT_LT(M(0, 0), 1e-5 * disc);
}

TEST(EquivalentEllipsoid, RecoversAnEllipsoidMesh) {
  // A finely tessellated unit sphere stretched to semi-axes (0.8, 0.2, 0.1), rotated and moved.
  CollisionShape sphere;
  sphere.type = CollisionShapeType::kSphere;
  sphere.radius = 1.0;
  geometry::TriangleMesh mesh = geometry::tessellate(sphere);
  const Eigen::Vector3d axes(0.8, 0.2, 0.1);
  Eigen::Isometry3d X_BE = Eigen::Isometry3d::Identity();
  X_BE.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  X_BE.translation() = Eigen::Vector3d(0.5, -0.2, 0.1);
  for (std::size_t i = 0; i + 2 < mesh.positions.size(); i += 3) {
    const Eigen::Vector3d p(mesh.positions[i], mesh.positions[i + 1], mesh.positions[i + 2]);
    const Eigen::Vector3d q = X_BE * Eigen::Vector3d(p.cwiseProduct(axes));
    for (int k = 0; k < 3; ++k) mesh.positions[i + k] = static_cast<float>(q[k]);
  }
  const geometry::MeshProperties props = geometry::compute_mesh_properties(mesh);
  ASSERT_TRUE(props.closed);
  const Ellipsoid e = equivalent_ellipsoid(props);
  // Tessellation makes the polyhedron's volume and moments differ from the ellipsoid's by O(h^2);
  // the primitive tessellation's faceting error on volume is below 1 %, hence 1 %.
  Eigen::Vector3d sorted = e.semi_axes;
  std::sort(sorted.data(), sorted.data() + 3);
  EXPECT_NEAR(sorted[2], 0.8, 0.008);
  EXPECT_NEAR(sorted[1], 0.2, 0.002);
  EXPECT_NEAR(sorted[0], 0.1, 0.001);
  EXPECT_LT((e.X_BE.translation() - X_BE.translation()).norm(), 1e-6);
  // The long axis is X_BE's x axis (up to sign).
  int longest = 0;
  e.semi_axes.maxCoeff(&longest);
  EXPECT_NEAR(std::abs(e.X_BE.linear().col(longest).dot(X_BE.linear().col(0))), 1.0, 1e-6);
}

TEST(ShiftAddedMass, PreservesKineticEnergy) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  Vector6d d;
  for (int i = 0; i < 6; ++i) d[i] = 1.0 + std::abs(n(rng));
  const Matrix6d M_O = d.asDiagonal();
  const Eigen::Matrix3d R_BE =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, -1.0, 0.4).normalized()).toRotationMatrix();
  const Eigen::Vector3d p_BO(0.3, -0.1, 0.2), p_BC(-0.05, 0.02, -0.01);
  const Matrix6d M_C = shift_added_mass(M_O, R_BE, p_BO, p_BC);
  for (int trial = 0; trial < 5; ++trial) {
    Vector6d nu_C;
    for (int i = 0; i < 6; ++i) nu_C[i] = n(rng);
    const Eigen::Vector3d v_C = nu_C.head<3>(), w = nu_C.tail<3>();
    Vector6d nu_O;
    nu_O.head<3>() = R_BE.transpose() * (v_C + w.cross(p_BO - p_BC));
    nu_O.tail<3>() = R_BE.transpose() * w;
    const double energy_O = nu_O.dot(M_O * nu_O), energy_C = nu_C.dot(M_C * nu_C);
    EXPECT_NEAR(energy_C, energy_O, 1e-12 * energy_O);
  }
}

TEST(AddedMassCoriolis, MunkMomentAndNoWork) {
  Vector6d diagonal;
  diagonal << 2.0, 30.0, 30.0, 0.0, 5.0, 5.0;  // slender body along x
  const Matrix6d M_A = diagonal.asDiagonal();
  Vector6d nu = Vector6d::Zero();
  nu[0] = 1.5;  // u
  nu[1] = 0.2;  // v
  const Vector6d c = added_mass_coriolis(M_A, nu);
  // Left-hand side yaw term (m22 - m11) u v; the moment on the body is its negative, turning the
  // nose away from the flow (yaw rate < 0 for v > 0: the velocity is to the left of the nose).
  EXPECT_NEAR(c[5], (30.0 - 2.0) * 1.5 * 0.2, 1e-12);
  EXPECT_NEAR(c.head<5>().norm(), 0.0, 1e-12);
  // C_A is skew-symmetric: it does no work.
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 6; ++i) nu[i] = n(rng);
  EXPECT_NEAR(nu.dot(added_mass_coriolis(M_A, nu)), 0.0, 1e-12);
}

AddedMassInput sinking_input(double kappa) {
  AddedMassInput in;
  in.kappa = kappa;
  in.gravity_B = Eigen::Vector3d(0.0, 0.0, -9.81);
  in.tau[2] = 100.0;  // buoyancy
  return in;
}

TEST(AddedMassDynamics, SinkingBodyAcceleratesAtReducedRate) {
  const RigidBodyInertia body{50.0, Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal()};
  Vector6d diagonal;
  diagonal << 5.0, 10.0, 20.0, 0.5, 0.5, 0.5;
  const AddedMassDynamics dynamics(body, diagonal.asDiagonal(), true, true);
  for (double kappa : {1.0, 0.97}) {
    const AddedMassInput in = sinking_input(kappa);
    const Vector6d a = dynamics.acceleration(in);
    EXPECT_NEAR(a[2], (100.0 - 50.0 * 9.81) / (50.0 + kappa * 20.0), 1e-12);
    // Bullet, given tau_bullet plus gravity, accelerates the rigid body by the same amount.
    const Vector6d tau_bullet = dynamics.bullet_wrench(in);
    EXPECT_NEAR((tau_bullet[2] + 50.0 * -9.81) / 50.0, a[2], 1e-12);
  }
}

TEST(AddedMassDynamics, NoAddedMassPassesTheWrenchThrough) {
  const RigidBodyInertia body{50.0, Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal()};
  const AddedMassDynamics dynamics(body, Matrix6d::Zero(), true, true);
  AddedMassInput in = sinking_input(1.0);
  in.nu << 1.0, 0.2, -0.1, 0.3, -0.2, 0.5;
  in.tau << 3.0, -2.0, 100.0, 0.4, 0.1, -0.3;
  const Vector6d tau_bullet = dynamics.bullet_wrench(in);
  EXPECT_LT((tau_bullet - in.tau).norm(), 1e-12);
}

TEST(AddedMassDynamics, SatisfiesTheEquationsOfMotion) {
  const RigidBodyInertia body{30.0, Eigen::Vector3d(0.1, 6.0, 6.0).asDiagonal()};
  Vector6d diagonal;
  diagonal << 1.5, 29.0, 29.0, 0.0, 4.0, 4.0;
  const Matrix6d M_A = diagonal.asDiagonal();
  for (bool gyroscopic : {true, false}) {
    const AddedMassDynamics dynamics(body, M_A, true, gyroscopic);
    AddedMassInput in = sinking_input(0.98);
    in.nu << 1.2, 0.1, -0.05, 0.02, 0.1, -0.3;
    in.nu_r = in.nu;
    in.nu_r[0] -= 0.2;
    in.tau << 8.0, 0.5, 3.0, 0.01, -0.2, 0.4;
    const Vector6d a = dynamics.acceleration(in);
    Vector6d g_RB = Vector6d::Zero();
    g_RB.head<3>() = 30.0 * in.gravity_B;
    // nu_r_dot = nu_dot + [w x v_water_B; 0] with v_water_B = (nu - nu_r)_v.
    Vector6d nu_r_dot = a;
    nu_r_dot.head<3>() += in.nu.tail<3>().cross(Eigen::Vector3d(in.nu.head<3>() - in.nu_r.head<3>()));
    const Vector6d lhs = dynamics.rigid_body_mass() * a + in.kappa * M_A * nu_r_dot +
                         dynamics.rigid_body_coriolis(in.nu) +
                         in.kappa * added_mass_coriolis(M_A, in.nu_r);
    EXPECT_LT((lhs - (in.tau + g_RB)).norm(), 1e-12);
    // The contact wrench measured from a step that follows exactly nu_dot is zero.
    const Vector6d tau_bullet = dynamics.bullet_wrench(in);
    const double dt = 1e-3;
    // nu1 in the start axes: the inertial-frame change of v is (nu_dot_v + w x v) dt.
    Vector6d nu1_B0 = in.nu + a * dt;
    nu1_B0.head<3>() += in.nu.tail<3>().cross(in.nu.head<3>()) * dt;
    const Vector6d tau_c = dynamics.contact_wrench(in.nu, nu1_B0, dt, tau_bullet, in.gravity_B);
    EXPECT_LT(tau_c.head<3>().norm(), 1e-9);
    EXPECT_LT(tau_c.tail<3>().norm(), 1e-9);
  }
}

}  // namespace
}  // namespace hadal::physics
