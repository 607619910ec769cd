#include "hadal/physics/terramechanics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hadal/core/units.h"
#include "hadal/geometry/seabed_height.h"
#include "hadal/geometry/triangle_mesh.h"

namespace hadal::physics {
namespace {

// A flat rectangular plate in B: its bottom face (normal -z) at z = 0, length_x by width_y, cut into
// nx by ny cells of two triangles each, and its top face (normal +z) at z = thickness as two triangles.
// Open at the sides: the soil only presses on faces that face it.
geometry::TriangleMesh plate(double length_x, double width_y, int nx, int ny, double thickness = 0.02) {
  geometry::TriangleMesh mesh;
  const auto vertex = [&](double x, double y, double z) {
    mesh.positions.insert(mesh.positions.end(), {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)});
    return static_cast<std::uint32_t>(mesh.num_vertices() - 1);
  };
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) vertex(-0.5 * length_x + length_x * i / nx, -0.5 * width_y + width_y * j / ny, 0.0);
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const auto a = static_cast<std::uint32_t>(j * (nx + 1) + i), b = a + 1;
      const auto c = static_cast<std::uint32_t>(a + nx + 1), d = c + 1;
      // Clockwise seen from above: normal -z.
      mesh.indices.insert(mesh.indices.end(), {a, d, b, a, c, d});
    }
  }
  const auto t0 = vertex(-0.5 * length_x, -0.5 * width_y, thickness), t1 = vertex(0.5 * length_x, -0.5 * width_y, thickness);
  const auto t2 = vertex(-0.5 * length_x, 0.5 * width_y, thickness), t3 = vertex(0.5 * length_x, 0.5 * width_y, thickness);
  mesh.indices.insert(mesh.indices.end(), {t0, t1, t3, t0, t3, t2});
  return mesh;
}

SoilParameters clay() {
  SoilParameters s;
  s.sinkage_exponent = 0.5;
  s.k_c = 13.19e3;
  s.k_phi = 692.15e3;
  s.cohesion = 4.14e3;
  s.friction_angle = 13.0 * kDegToRad;
  s.shear_deformation_modulus = 0.006;
  return s;
}

// The plate's bottom `sinkage` below the plane z = 0, at rest, with its centre of mass 0.1 m above.
BodyMotion pressed(double sinkage) {
  BodyMotion m;
  m.X_WB.translation() = Eigen::Vector3d(3.0, -2.0, -sinkage);
  m.p_WBcm = m.X_WB.translation() + Eigen::Vector3d(0.0, 0.0, 0.1);
  return m;
}

TEST(SoilParameters, PressureSinkageAndItsInverse) {
  const SoilParameters s = clay();
  // p = (k_c / b + k_phi) z^n, algebra: 1e-12 relative.
  EXPECT_NEAR(s.pressure(0.04, 0.5), (13.19e3 / 0.5 + 692.15e3) * std::sqrt(0.04), 1e-12 * 1e5);
  EXPECT_EQ(s.pressure(0.0, 0.5), 0.0);
  EXPECT_EQ(s.pressure(-0.01, 0.5), 0.0);
  const double z = s.static_sinkage(2000.0, 0.25, 0.5);
  EXPECT_NEAR(s.pressure(z, 0.5) * 0.25, 2000.0, 1e-9);
  EXPECT_NEAR(s.shear_strength(1e4), 4.14e3 + 1e4 * std::tan(13.0 * kDegToRad), 1e-9);
}

// The patch width is the plate's short side whatever the tessellation, so the normal force is p A with
// b = 0.3 for a 0.5 m x 0.3 m plate in 2 or in 1200 triangles (the paper's b = sqrt(A_face) would differ
// by k_c (1/sqrt(A/2) - 1/sqrt(A/1200)) ~ 4 %). Float vertices: 1e-6 relative.
TEST(SoilContact, NormalForceIsBekkerPressureOverThePatchWhateverTheTessellation) {
  const auto seabed = geometry::SeabedHeight::plane(0.0);
  const SoilParameters s = clay();
  const double sinkage = 0.03, area = 0.5 * 0.3;
  const double expected = s.pressure(sinkage, 0.3) * area;
  for (const auto& [nx, ny] : {std::pair{1, 1}, std::pair{30, 20}}) {
    SCOPED_TRACE(std::to_string(nx) + " x " + std::to_string(ny));
    SoilContact contact(plate(0.5, 0.3, nx, ny), s, 100.0, 0.002);
    SoilShearState shear;
    const SoilWrench w = contact.compute(pressed(sinkage), seabed, shear);
    EXPECT_GE(w.faces_in_contact, static_cast<std::size_t>(2 * nx * ny));  // large faces are split
    EXPECT_NEAR(contact.patch_widths()[0], 0.3, 1e-6);
    EXPECT_NEAR(w.contact_area, area, 1e-6 * area);
    EXPECT_NEAR(w.f_W.z(), expected, 1e-6 * expected);
    EXPECT_NEAR(w.f_W.x(), 0.0, 1e-9 * expected);
    EXPECT_NEAR(w.f_W.y(), 0.0, 1e-9 * expected);
    // Centred under the centre of mass: no moment.
    EXPECT_LT(w.tau_W.norm(), 1e-6 * expected);
    EXPECT_NEAR(w.max_sinkage, sinkage, 1e-7);
  }
}

// The soil's moment is about the centre of mass, not the body origin. The plate (centred on B's origin)
// pressed in uniformly and sliding along +x: every face carries the same pressure and shear, so the
// resultant F acts at the plate's centre c, and tau = (c - p_cm) x F. With the centre of mass off the
// origin along x, y and z by different amounts (r = c - p_cm = (-0.1, 0.05, -0.1)), the normal force's
// moment is (r_y F_z, -r_x F_z, 0) and the shear's (0, r_z F_x, -r_y F_x): each component has its own
// lever arm and sign. Float vertices: 1e-6 relative.
TEST(SoilContact, MomentIsAboutTheCentreOfMassOffTheOrigin) {
  const auto seabed = geometry::SeabedHeight::plane(0.0);
  SoilParameters s = clay();
  s.shear_damping_time = 0.0;
  const double sinkage = 0.03, v = 0.01;
  SoilContact contact(plate(0.5, 0.3, 3, 3), s, 1e6, 0.002);
  SoilShearState shear;
  BodyMotion m = pressed(sinkage);
  m.p_WBcm = m.X_WB.translation() + Eigen::Vector3d(0.1, -0.05, 0.1);
  m.v_WBcm = Eigen::Vector3d(v, 0.0, 0.0);
  SoilWrench w;
  for (int k = 0; k < 200; ++k) w = contact.compute(m, seabed, shear);  // j = 4 mm: half the soil's strength
  const Eigen::Vector3d r = m.X_WB.translation() - m.p_WBcm;  // (-0.1, 0.05, -0.1)
  const double Fz = w.f_W.z(), Fx = w.f_W.x();
  ASSERT_GT(Fz, 0.0);
  ASSERT_LT(Fx, -0.1 * Fz * std::tan(s.friction_angle));  // sliding +x: the shear pulls back
  const Eigen::Vector3d expected(r.y() * Fz, -r.x() * Fz + r.z() * Fx, -r.y() * Fx);
  EXPECT_NEAR(w.tau_W.x(), expected.x(), 1e-6 * std::abs(expected.x()));
  EXPECT_NEAR(w.tau_W.y(), expected.y(), 1e-6 * std::abs(expected.y()));
  EXPECT_NEAR(w.tau_W.z(), expected.z(), 1e-6 * std::abs(expected.z()));
  EXPECT_NEAR((w.tau_W - r.cross(w.f_W)).norm(), 0.0, 1e-6 * w.tau_W.norm());
}

TEST(SoilContact, AboveTheSeabedOrFacingAwayNothingTouches) {
  const auto seabed = geometry::SeabedHeight::plane(0.0);
  SoilContact contact(plate(0.5, 0.3, 4, 4), clay(), 100.0, 0.002);
  SoilShearState shear;
  EXPECT_EQ(contact.compute(pressed(-0.001), seabed, shear).faces_in_contact, 0u);
  // Upside down, the top face faces down, 2 cm below the (now upward-facing) bottom: only it touches.
  BodyMotion flipped = pressed(0.05);
  flipped.X_WB.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const SoilWrench w = contact.compute(flipped, seabed, shear);
  EXPECT_GT(w.faces_in_contact, 0u);
  EXPECT_NEAR(w.contact_area, 0.5 * 0.3, 1e-6);
  EXPECT_NEAR(w.max_sinkage, 0.07, 1e-6);
}

// A moving plate's normal damping adds -c_d A v_n; a plate rising faster than p / c_d feels no pull.
TEST(SoilContact, NormalDampingOpposesNormalVelocityAndNeverPulls) {
  const auto seabed = geometry::SeabedHeight::plane(0.0);
  SoilParameters s = clay();
  s.damping = 1e4;
  SoilContact contact(plate(0.5, 0.3, 2, 2), s, 1e6, 0.002);  // heavy: damping not capped
  SoilShearState shear;
  BodyMotion down = pressed(0.03);
  down.v_WBcm = Eigen::Vector3d(0.0, 0.0, -0.2);
  const double p = s.pressure(0.03, 0.3);
  EXPECT_NEAR(contact.compute(down, seabed, shear).f_W.z(), (p + 1e4 * 0.2) * 0.15, 1e-6 * p);
  BodyMotion up = pressed(0.03);
  up.v_WBcm = Eigen::Vector3d(0.0, 0.0, 2.0 * p / 1e4);
  EXPECT_EQ(contact.compute(up, seabed, shear).f_W.z(), 0.0);
}

// The damping of a light body is capped at mass / dt: c_d A dt / m <= 1.
TEST(SoilContact, DampingIsCappedForALightBody) {
  const auto seabed = geometry::SeabedHeight::plane(0.0);
  SoilParameters s = clay();
  s.damping = 1e6;
  const double mass = 10.0, dt = 0.002;
  SoilContact contact(plate(0.5, 0.3, 2, 2), s, mass, dt);
  SoilShearState shear;
  BodyMotion down = pressed(0.03);
  down.v_WBcm = Eigen::Vector3d(0.0, 0.0, -0.1);
  const double p = s.pressure(0.03, 0.3);
  EXPECT_NEAR(contact.compute(down, seabed, shear).f_W.z(), p * 0.15 + mass / dt * 0.1, 1e-6 * p);
}

// Shear under a steady sideways slip v: j = v t builds the Janosi-Hanamoto stress until the soil yields,
// then stays at A tau_max (the cap).
TEST(SoilContact, ShearBuildsUpWithDisplacementAndSaturatesAtTheShearStrength) {
  const auto seabed = geometry::SeabedHeight::plane(0.0);
  SoilParameters s = clay();
  s.shear_damping_time = 0.0;  // the elastic part alone
  const double dt = 0.002, v = 0.01, sinkage = 0.03, area = 0.15;
  SoilContact contact(plate(0.5, 0.3, 3, 3), s, 1e6, dt);
  SoilShearState shear;
  BodyMotion m = pressed(sinkage);
  m.v_WBcm = Eigen::Vector3d(v, 0.0, 0.0);
  const double tau_max = s.shear_strength(s.pressure(sinkage, 0.3));
  const double K = s.shear_deformation_modulus;
  for (int k = 1; k <= 20; ++k) {
    const SoilWrench w = contact.compute(m, seabed, shear);
    const double j = k * v * dt;
    EXPECT_NEAR(w.shear_force_W.x(), -area * tau_max * (1.0 - std::exp(-j / K)), 1e-6 * area * tau_max) << k;
    EXPECT_NEAR(w.shear_force_W.y(), 0.0, 1e-9);
  }
  for (int k = 0; k < 3000; ++k) contact.compute(m, seabed, shear);
  const SoilWrench w = contact.compute(m, seabed, shear);
  EXPECT_NEAR(w.shear_force_W.x(), -area * tau_max * 0.999, 1e-6 * area * tau_max);
  // Reversed, the shear turns round after travelling back the capped displacement and more.
  m.v_WBcm = -m.v_WBcm;
  const double j_cap = std::log(1000.0) * K;
  for (int k = 0; k < static_cast<int>(std::ceil(2.0 * j_cap / (v * dt))); ++k) contact.compute(m, seabed, shear);
  EXPECT_GT(contact.compute(m, seabed, shear).shear_force_W.x(), 0.99 * area * tau_max);
  // Lifted out of the soil, the shear is forgotten.
  contact.compute(pressed(-0.01), seabed, shear);
  for (const Eigen::Vector3d& j : shear) EXPECT_EQ(j.norm(), 0.0);
}

// Track traction under steady slip (Bekker-Wong): a track of length L and width b pressed in uniformly,
// belt speed V backwards, body speed v = (1 - i) V forwards: F = A tau_max [1 - K / (i L) (1 - e^(-i L / K))],
// growing with slip i and saturating at A c + W tan(phi) (W the normal load). The faces sit at the centres
// of 100 strips along L: the midpoint rule of the integral errs by ~(L/100)^2 / 24 i / K -- below 1e-3 of
// A tau_max for these slips. The steady shear j = i s does not depend on the step (the relaxation is
// implicit), so a long step of 20 ms reaches it in few steps.
TEST(SoilContact, TrackTractionGrowsWithSlipAndSaturatesAtTheSoilsStrength) {
  const auto seabed = geometry::SeabedHeight::plane(0.0);
  SoilParameters s = clay();
  s.shear_damping_time = 0.0;
  const double L = 2.0, b = 0.3, A = L * b, sinkage = 0.04, V = 0.5, dt = 0.02;
  const double K = s.shear_deformation_modulus;
  const double p = s.pressure(sinkage, b);
  const double limit = A * s.cohesion + p * A * std::tan(s.friction_angle);
  double previous = 0.0;
  for (double slip : {0.002, 0.01, 0.05, 0.2, 0.6, 1.0}) {
    SCOPED_TRACE("slip " + std::to_string(slip));
    SoilContact contact(plate(L, b, 100, 8), s, 1e6, dt);  // faces below the 10 cm that would be split
    SoilShearState shear;
    BodyMotion m = pressed(sinkage);
    m.v_WBcm = Eigen::Vector3d((1.0 - slip) * V, 0.0, 0.0);
    const std::vector<Eigen::Vector3d> belt = {Eigen::Vector3d(-V, 0.0, 0.0)};
    SoilWrench w;
    // Steady after the belt has carried an element across the track several times over.
    for (int k = 0; k < static_cast<int>(8.0 * L / V / dt); ++k) w = contact.compute(m, seabed, shear, belt);
    const double iL = slip * L;
    const double expected = A * s.shear_strength(p) * (1.0 - K / iL * (1.0 - std::exp(-iL / K)));
    EXPECT_NEAR(w.shear_force_W.x(), expected, 2e-3 * limit);
    EXPECT_NEAR(w.normal_force_W.z() * std::tan(s.friction_angle) + A * s.cohesion, limit, 1e-6 * limit);
    EXPECT_GT(w.shear_force_W.x(), previous);
    EXPECT_LE(w.shear_force_W.x(), limit);
    previous = w.shear_force_W.x();
  }
  EXPECT_GT(previous, 0.99 * limit);
}

}  // namespace
}  // namespace hadal::physics
