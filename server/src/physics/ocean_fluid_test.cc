#include "hadal/physics/ocean_fluid.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "hadal/geometry/primitive_mesh.h"

namespace hadal::physics {
namespace {

constexpr double kRho = 1025.0;
constexpr double kG = 9.80665;
// Same float kernel, same faces: the samplers differ only in how dp is rounded (UniformWater forms
// -rho g dz in float, OceanFluid the difference of double pressures), a few float epsilons per
// face; 1e-5 of the wrench's scale leaves a margin.
constexpr double kFloat = 1e-5;

WaterSpec constant_water(const Eigen::Vector3d& current_W) {
  WaterSpec water;
  water.density = kRho;
  water.surface_z = 2.0;
  water.current.uniform_W = current_W;
  return water;
}

SurfaceHydrodynamics box_hydro() {
  CollisionShape box;
  box.box_size = Eigen::Vector3d(1.2, 0.5, 0.4);
  return SurfaceHydrodynamics(geometry::tessellate(box));
}

void expect_same_wrench(const BodyMotion& motion, const Eigen::Vector3d& current_W) {
  const Ocean ocean(constant_water(current_W), kG, 1);
  UniformWater uniform;
  uniform.density = kRho;
  uniform.gravity = kG;
  uniform.surface_z = 2.0;
  uniform.current_W = current_W;
  const OceanFluid fluid(ocean, 3.0);
  EXPECT_EQ(fluid.surface_z_W(), 2.0);
  EXPECT_EQ(fluid.gravity_magnitude(), kG);
  EXPECT_NEAR(fluid.gauge_pressure(-8.0), kRho * kG * 10.0, 1e-9 * kRho * kG * 10.0);
  EXPECT_EQ(fluid.gauge_pressure(2.5), 0.0);

  SurfaceHydrodynamics a = box_hydro(), b = box_hydro();
  const HydrodynamicWrench expected = a.compute(motion, uniform);
  const HydrodynamicWrench got = b.compute(motion, fluid);
  const double f_scale = expected.f_W.norm(), tau_scale = std::max(expected.tau_W.norm(), f_scale);
  EXPECT_GT(f_scale, 100.0);
  EXPECT_LT((got.f_W - expected.f_W).norm(), kFloat * f_scale) << got.f_W.transpose() << " vs "
                                                               << expected.f_W.transpose();
  EXPECT_LT((got.tau_W - expected.tau_W).norm(), kFloat * tau_scale);
  EXPECT_EQ(got.clipped_faces, expected.clipped_faces);
  EXPECT_EQ(got.fully_submerged, expected.fully_submerged);
  EXPECT_NEAR(got.wetted_area, expected.wetted_area, 1e-9);
}

BodyMotion moving_at(const Eigen::Vector3d& p_W) {
  BodyMotion motion;
  motion.X_WB.linear() = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
                          Eigen::AngleAxisd(0.25, Eigen::Vector3d::UnitX()))
                             .toRotationMatrix();
  motion.X_WB.translation() = p_W;
  motion.p_WBcm = p_W + Eigen::Vector3d(0.05, 0.0, -0.02);
  motion.v_WBcm = Eigen::Vector3d(1.0, -0.3, 0.2);
  motion.w_WB = Eigen::Vector3d(0.1, 0.4, -0.2);
  return motion;
}

TEST(OceanFluidTest, ConstantWaterGivesTheUniformWaterWrench) {
  const Eigen::Vector3d current_W(0.3, 0.5, 0.0);
  expect_same_wrench(moving_at({10.0, -4.0, -50.0}), current_W);   // fully submerged
  expect_same_wrench(moving_at({10.0, -4.0, 2.1}), current_W);     // crossing the surface
  expect_same_wrench(moving_at({0.0, 0.0, -3000.0}), Eigen::Vector3d::Zero());  // deep
}

}  // namespace
}  // namespace hadal::physics
