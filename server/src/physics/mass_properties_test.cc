#include "hadal/physics/mass_properties.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "hadal/physics/test_models.h"

namespace hadal::physics {
namespace {

// Mass-property algebra is a handful of sums and products of O(1) numbers: its round-off is a few
// ulp, so 1e-12 (absolute, on O(1) values) is a comfortable bound.
constexpr double kAlgebraTol = 1e-12;

Eigen::Isometry3d translation(const Eigen::Vector3d& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = p;
  return X;
}

TEST(MassPropertiesTest, TwoBoxesMatchReducedMassClosedForm) {
  // Two small boxes of masses m1, m2 a distance d apart along B-x, offset in y and z by the same
  // amount. Closed form: com = (m1 p1 + m2 p2) / m, and about it
  // I = I_box1 + I_box2 + mu (|d|^2 1 - d d^T), mu = m1 m2 / (m1 + m2), d = p1 - p2.
  const double m1 = 3.0, m2 = 1.0;
  const Eigen::Vector3d size(0.1, 0.2, 0.3);
  const Eigen::Vector3d p1(1.0, 0.5, -0.25), p2(-1.0, 0.5, -0.25);
  std::vector<LinkSpec> links = {testing::box_link("a", m1, size, 0.0, translation(p1)),
                                 testing::box_link("b", m2, size, 0.0, translation(p2))};
  const MassProperties props = composite_mass_properties(links);

  const double mu = m1 * m2 / (m1 + m2);
  const Eigen::Vector3d d = p1 - p2;
  const Eigen::Matrix3d expected =
      solid_box_inertia(m1, size) + solid_box_inertia(m2, size) +
      mu * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  EXPECT_DOUBLE_EQ(props.mass, 4.0);
  EXPECT_TRUE(props.p_BBcm.isApprox(Eigen::Vector3d(0.5, 0.5, -0.25), kAlgebraTol));
  EXPECT_LT((props.I_BBcm_B - expected).norm(), kAlgebraTol);
  // Hand values: Ixx = (m/12)(0.2^2 + 0.3^2) summed, Iyy and Izz gain mu d^2 = 0.75 * 4 = 3.
  EXPECT_NEAR(props.I_BBcm_B(0, 0), 4.0 / 12.0 * 0.13, kAlgebraTol);
  EXPECT_NEAR(props.I_BBcm_B(1, 1), 4.0 / 12.0 * 0.10 + 3.0, kAlgebraTol);
  EXPECT_NEAR(props.I_BBcm_B(2, 2), 4.0 / 12.0 * 0.05 + 3.0, kAlgebraTol);
  // Already diagonal: P keeps B's axes and sits at the centre of mass.
  EXPECT_TRUE(props.X_BP.linear().isIdentity(0.0));
  EXPECT_TRUE(props.X_BP.translation().isApprox(props.p_BBcm, 0.0));
  EXPECT_TRUE(props.I_principal.isApprox(props.I_BBcm_B.diagonal(), 0.0));
}

TEST(MassPropertiesTest, LinkInertiaIsRotatedIntoB) {
  // A link yawed by 90 deg: its x axis is B's y, so diag(1, 2, 3) in L is diag(2, 1, 3) in B; its
  // centre of mass at p_LLcm = (1, 0, 0) is at X_BL p_LLcm = p_BL + (0, 1, 0).
  LinkSpec link;
  link.mass = 2.0;
  link.I_LLcm_L = Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal();
  link.p_LLcm = Eigen::Vector3d(1.0, 0.0, 0.0);
  link.X_BL = translation(Eigen::Vector3d(0.0, 0.0, 5.0));
  link.X_BL.linear() = Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const MassProperties props = composite_mass_properties({link});
  EXPECT_LT((props.p_BBcm - Eigen::Vector3d(0.0, 1.0, 5.0)).norm(), kAlgebraTol);
  EXPECT_LT((props.I_BBcm_B - Eigen::Matrix3d(Eigen::Vector3d(2.0, 1.0, 3.0).asDiagonal())).norm(),
            kAlgebraTol);
  // Yawed by 30 deg (c = sqrt(3)/2, s = 1/2), the rotation's direction shows: I_B = R I_L R^T has
  // I_xx = c^2 + 2 s^2 = 1.25, I_yy = s^2 + 2 c^2 = 1.75 and I_xy = c s (1 - 2) = -sqrt(3)/4 (R^T I_L R
  // would give +sqrt(3)/4; a 90 deg yaw gives the same matrix either way).
  link.X_BL.linear() = Eigen::AngleAxisd(EIGEN_PI / 6, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  link.p_LLcm.setZero();
  const MassProperties yawed = composite_mass_properties({link});
  Eigen::Matrix3d expected;
  expected << 1.25, -std::sqrt(3.0) / 4.0, 0.0, -std::sqrt(3.0) / 4.0, 1.75, 0.0, 0.0, 0.0, 3.0;
  EXPECT_LT((yawed.I_BBcm_B - expected).norm(), kAlgebraTol) << yawed.I_BBcm_B;
}

TEST(MassPropertiesTest, PrincipalFrameDiagonalisesAndIsRightHanded) {
  // Two equal cubes on the diagonal of the B xy-plane: about the centre of mass
  // I = 2 c 1 + mu (|d|^2 1 - d d^T) with c the cube's isotropic inertia, so the principal moments
  // are 2c (axis along d) and 2c + mu |d|^2 (twice).
  const double m = 1.5, side = 0.2;
  const Eigen::Vector3d p1(0.7, 0.7, 0.0), p2(-0.7, -0.7, 0.0);
  std::vector<LinkSpec> links = {
      testing::box_link("a", m, Eigen::Vector3d::Constant(side), 0.0, translation(p1)),
      testing::box_link("b", m, Eigen::Vector3d::Constant(side), 0.0, translation(p2))};
  const MassProperties props = composite_mass_properties(links);

  const double c = m * side * side / 6.0;
  const double mu = m / 2.0;
  const Eigen::Vector3d d = p1 - p2;
  const Eigen::Matrix3d R_BP = props.X_BP.linear();
  // The eigen-solver is backward stable: errors ~ eps * |I| (|I| ~ 1.5), so kAlgebraTol holds.
  EXPECT_NEAR(R_BP.determinant(), 1.0, kAlgebraTol);
  EXPECT_LT((R_BP.transpose() * R_BP - Eigen::Matrix3d::Identity()).norm(), kAlgebraTol);
  const Eigen::Matrix3d I_P = R_BP.transpose() * props.I_BBcm_B * R_BP;
  EXPECT_LT((I_P - Eigen::Matrix3d(props.I_principal.asDiagonal())).norm(), kAlgebraTol);
  EXPECT_NEAR(props.I_principal(0), 2 * c, kAlgebraTol);
  EXPECT_NEAR(props.I_principal(1), 2 * c + mu * d.squaredNorm(), kAlgebraTol);
  EXPECT_NEAR(props.I_principal(2), 2 * c + mu * d.squaredNorm(), kAlgebraTol);
  EXPECT_NEAR(std::abs(R_BP.col(0).dot(d.normalized())), 1.0, kAlgebraTol);
}

TEST(MassPropertiesTest, RejectsMasslessVehicle) {
  LinkSpec link;
  link.mass = 0.0;
  EXPECT_THROW(composite_mass_properties({link}), std::invalid_argument);
  EXPECT_THROW(composite_mass_properties({}), std::invalid_argument);
}

TEST(MassPropertiesTest, SolidInertiasMatchTextbook) {
  // Textbook formulas evaluated by hand for m = 12 kg.
  EXPECT_TRUE(solid_box_inertia(12.0, Eigen::Vector3d(1, 2, 3))
                  .diagonal()
                  .isApprox(Eigen::Vector3d(13, 10, 5)));
  EXPECT_TRUE(solid_sphere_inertia(12.0, 0.5).diagonal().isApprox(Eigen::Vector3d::Constant(1.2)));
  // Cylinder r = 1, L = 2: transverse m (3 r^2 + L^2) / 12 = 7, axial m r^2 / 2 = 6.
  EXPECT_TRUE(solid_cylinder_inertia(12.0, 1.0, 2.0).diagonal().isApprox(Eigen::Vector3d(7, 7, 6)));
}

}  // namespace
}  // namespace hadal::physics
