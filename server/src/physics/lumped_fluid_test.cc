#include "hadal/physics/lumped_fluid.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hadal/physics/test_models.h"

namespace hadal::physics {
namespace {

// Every expectation below is a short chain of products of O(1)..O(1e4) numbers evaluated two ways:
// round-off is a few ulp, so 1e-12 relative.
constexpr double kTol = 1e-12;

const Eigen::Vector3d kBoxSize(2.0, 1.0, 0.5);

WorldSpec water_world() {
  WorldSpec world;
  world.water.surface_z = 0.0;
  world.water.density = 1000.0;
  return world;
}

VehicleSpec box_vehicle(double volume) {
  VehicleSpec vehicle;
  vehicle.links.push_back(testing::box_link("hull", 100.0, kBoxSize, volume));
  return vehicle;
}

using testing::at;

TEST(LumpedFluidTest, FullySubmergedBuoyancyIsRhoGVAtCentreOfBuoyancy) {
  VehicleSpec vehicle = box_vehicle(1.0);
  vehicle.links[0].buoyancy.p_LCb = Eigen::Vector3d(0.1, 0.0, 0.05);
  const WorldSpec world = water_world();
  const LumpedFluid fluid(vehicle, world);
  RigidBodyState body;
  body.X_WB = at(Eigen::Vector3d(3.0, 4.0, -50.0),
                 Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  const LumpedFluidWrench w = fluid.wrench(body, Eigen::Vector3d::Zero());
  const Eigen::Vector3d f_expected = -1000.0 * 1.0 * world.gravity_W;
  EXPECT_DOUBLE_EQ(w.submerged_fraction, 1.0);
  EXPECT_TRUE(w.f_buoyancy_W.isApprox(f_expected, kTol));
  const Eigen::Vector3d p_BoCb_W = body.X_WB.linear() * vehicle.links[0].buoyancy.p_LCb;
  EXPECT_TRUE(w.tau_buoyancy_W.isApprox(p_BoCb_W.cross(f_expected), kTol));
  EXPECT_TRUE(w.f_damping_W.isZero(0.0));
}

TEST(LumpedFluidTest, UprightBoxFractionIsItsDraughtOverHeight) {
  // Upright box (height 0.5 m) with Cb at its centre: s = (z_surface - z_bottom) / 0.5, clamped.
  const LumpedFluid fluid(box_vehicle(1.0), water_world());
  struct Case {
    double z_centre, fraction;
  };
  for (const Case c : {Case{-0.25, 1.0}, Case{0.0, 0.5}, Case{0.125, 0.25}, Case{-0.125, 0.75},
                       Case{0.25, 0.0}, Case{3.0, 0.0}, Case{-3.0, 1.0}}) {
    EXPECT_NEAR(fluid.link_submerged_fraction(0, at(Eigen::Vector3d(0, 0, c.z_centre))), c.fraction,
                kTol)
        << "z = " << c.z_centre;
  }
}

TEST(LumpedFluidTest, TiltedBoxUsesItsWorldVerticalExtent) {
  // Rolled 90 deg about x, the box's 1 m side is vertical: the draught over 1 m.
  const LumpedFluid fluid(box_vehicle(1.0), water_world());
  const Eigen::Matrix3d roll =
      Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_NEAR(fluid.link_submerged_fraction(0, at(Eigen::Vector3d(0, 0, 0.3), roll)), 0.2, kTol);
  // Rolled 45 deg: vertical extent (1 + 0.5) / sqrt(2).
  const Eigen::Matrix3d roll45 =
      Eigen::AngleAxisd(EIGEN_PI / 4, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const double h = 1.5 / std::sqrt(2.0);
  EXPECT_NEAR(fluid.link_submerged_fraction(0, at(Eigen::Vector3d(0, 0, 0.1), roll45)),
              (h / 2 - 0.1) / h, kTol);
  // Rolled -45 deg: the same extent (a box's extent takes the absolute value of each axis's height).
  const Eigen::Matrix3d roll_minus45 =
      Eigen::AngleAxisd(-EIGEN_PI / 4, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_NEAR(fluid.link_submerged_fraction(0, at(Eigen::Vector3d(0, 0, 0.1), roll_minus45)),
              (h / 2 - 0.1) / h, kTol);
}

// The centre of buoyancy's height is taken in W: a box pitched 90 deg (x_B pointing down) with Cb 0.4 m
// along x_L has Cb 0.4 m below B's origin, its 2 m side vertical, so at z = 0 the draught is 1.4 m of 2:
// s = 0.7 (Cb's offset taken unrotated would give 0.5). Its buoyancy is s rho V g = 0.7 x 1000 x 9.80665 N
// up, acting at Cb.
TEST(LumpedFluidTest, PartlySubmergedBuoyancyIsTheFractionOfRhoGVAtTheRotatedCentre) {
  VehicleSpec vehicle = box_vehicle(1.0);
  vehicle.links[0].buoyancy.p_LCb = Eigen::Vector3d(0.4, 0.0, 0.0);
  const WorldSpec world = water_world();
  const LumpedFluid fluid(vehicle, world);
  RigidBodyState body;
  body.X_WB = at(Eigen::Vector3d(0.0, 0.0, 0.0),
                 Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix());
  EXPECT_NEAR(fluid.link_submerged_fraction(0, body.X_WB), 0.7, kTol);
  const LumpedFluidWrench w = fluid.wrench(body, Eigen::Vector3d::Zero());
  EXPECT_NEAR(w.submerged_fraction, 0.7, kTol);
  const Eigen::Vector3d f_expected = -0.7 * 1000.0 * 1.0 * world.gravity_W;
  EXPECT_TRUE(w.f_buoyancy_W.isApprox(f_expected, kTol)) << w.f_buoyancy_W.transpose();
  // Upright at z = 0: half in, half the full buoyancy (4903.325 N).
  body.X_WB = at(Eigen::Vector3d(0.0, 0.0, 0.0));
  const LumpedFluidWrench half = fluid.wrench(body, Eigen::Vector3d::Zero());
  EXPECT_NEAR(half.f_buoyancy_W.z(), 0.5 * 1000.0 * 9.80665, kTol * 1e4);
}

TEST(LumpedFluidTest, RoundShapesAndShapelessLinks) {
  VehicleSpec vehicle;
  LinkSpec cylinder;
  cylinder.mass = 1.0;
  cylinder.buoyancy.volume = 0.1;
  CollisionShape shape;
  shape.type = CollisionShapeType::kCylinder;
  shape.radius = 0.2;
  shape.length = 2.0;
  cylinder.collisions.push_back(shape);
  LinkSpec capsule = cylinder;
  capsule.collisions[0].type = CollisionShapeType::kCapsule;
  LinkSpec sphere = cylinder;
  sphere.collisions[0].type = CollisionShapeType::kSphere;
  LinkSpec shapeless = cylinder;
  shapeless.collisions.clear();
  vehicle.links = {cylinder, capsule, sphere, shapeless};
  const LumpedFluid fluid(vehicle, water_world());
  const Eigen::Vector3d p(0, 0, 0.1);  // Cb 0.1 m above the surface
  // Upright cylinder: h = L = 2; capsule: L + 2r = 2.4; sphere: 2r = 0.4.
  EXPECT_NEAR(fluid.link_submerged_fraction(0, at(p)), 0.9 / 2.0, kTol);
  EXPECT_NEAR(fluid.link_submerged_fraction(1, at(p)), 1.1 / 2.4, kTol);
  EXPECT_NEAR(fluid.link_submerged_fraction(2, at(p)), 0.1 / 0.4, kTol);
  // No shapes: the diameter of the sphere of volume V.
  const double d = 2.0 * std::cbrt(3.0 * 0.1 / (4.0 * EIGEN_PI));
  EXPECT_NEAR(fluid.link_submerged_fraction(3, at(p)), (d / 2 - 0.1) / d, kTol);
  // A horizontal cylinder (pitched 90 deg) has vertical extent 2r; tilted by a, L cos a + 2r sin a.
  const Eigen::Matrix3d pitch =
      Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_NEAR(fluid.link_submerged_fraction(0, at(Eigen::Vector3d(0, 0, 0.1), pitch)), 0.1 / 0.4,
              1e-9);
  const double a = 0.3;
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const double h = 2.0 * std::cos(a) + 0.4 * std::sin(a);
  EXPECT_NEAR(fluid.link_submerged_fraction(0, at(Eigen::Vector3d(0, 0, 0.1), tilt)),
              (h / 2 - 0.1) / h, kTol);
}

TEST(LumpedFluidTest, DampingIsDiagonalInBodyFrame) {
  // nu = [R^T v; R^T w]; tau_k = -(D_l + D_q |nu_k|) nu_k; force and moment rotated back into W.
  VehicleSpec vehicle = box_vehicle(1.0);
  vehicle.fluid.linear_damping << 10, 20, 30, 1, 2, 3;
  vehicle.fluid.quadratic_damping << 100, 200, 300, 4, 5, 6;
  const LumpedFluid fluid(vehicle, water_world());
  RigidBodyState body;
  const Eigen::Matrix3d R_WB = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  body.X_WB = at(Eigen::Vector3d(0, 0, -10), R_WB);
  const Eigen::Vector3d nu_v(1.5, -0.5, 0.25), nu_w(0.1, -0.2, 0.3);
  body.v_WB = R_WB * nu_v;
  body.w_WB = R_WB * nu_w;
  const LumpedFluidWrench w = fluid.wrench(body, Eigen::Vector3d::Zero());
  const Eigen::Vector3d f_B(-(10 + 100 * 1.5) * 1.5, -(20 + 200 * 0.5) * -0.5,
                            -(30 + 300 * 0.25) * 0.25);
  const Eigen::Vector3d m_B(-(1 + 4 * 0.1) * 0.1, -(2 + 5 * 0.2) * -0.2, -(3 + 6 * 0.3) * 0.3);
  EXPECT_TRUE(w.f_damping_W.isApprox(R_WB * f_B, kTol));
  EXPECT_TRUE(w.tau_damping_W.isApprox(R_WB * m_B, kTol));

  // Water moving with the body: no relative velocity, no translational damping.
  EXPECT_TRUE(fluid.wrench(body, body.v_WB).f_damping_W.isZero(kTol));

  // Half submerged: half the damping.
  body.X_WB.translation().z() = 0.0;
  body.X_WB.linear().setIdentity();
  body.v_WB = nu_v;
  body.w_WB = nu_w;
  const LumpedFluidWrench half = fluid.wrench(body, Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(half.submerged_fraction, 0.5);
  EXPECT_TRUE(half.f_damping_W.isApprox(0.5 * f_B, kTol));
  EXPECT_TRUE(half.tau_damping_W.isApprox(0.5 * m_B, kTol));
}

TEST(LumpedFluidTest, VehicleFractionIsVolumeWeighted) {
  // Two boxes stacked 2 m apart, only the lower one submerged: s = V_low / (V_low + V_high).
  VehicleSpec vehicle;
  Eigen::Isometry3d up = Eigen::Isometry3d::Identity();
  up.translation().z() = 2.0;
  vehicle.links = {testing::box_link("low", 1.0, kBoxSize, 3.0),
                   testing::box_link("high", 1.0, kBoxSize, 1.0, up)};
  const LumpedFluid fluid(vehicle, water_world());
  RigidBodyState body;
  body.X_WB = at(Eigen::Vector3d(0, 0, -1.0));
  const LumpedFluidWrench w = fluid.wrench(body, Eigen::Vector3d::Zero());
  EXPECT_NEAR(w.submerged_fraction, 0.75, kTol);
  EXPECT_NEAR(w.f_buoyancy_W.z(), 1000.0 * 3.0 * 9.80665, 1e-12 * 3e4);
}

}  // namespace
}  // namespace hadal::physics
