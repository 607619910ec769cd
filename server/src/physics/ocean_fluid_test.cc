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

// Both sampling paths against the Ocean's own point queries: the closed-form constant-density path
// and the general path (here the paper's ramp), including a point above the surface and the origin
// itself. Values are rounded to float: 1e-6 relative of the pressure scale (rho g 10 m).
TEST(OceanFluidTest, SamplesMatchTheOceanForConstantAndRampWater) {
  for (const DensityModel model : {DensityModel::kConstant, DensityModel::kRamp}) {
    WaterSpec water = constant_water(Eigen::Vector3d(0.1, 0.0, 0.0));
    water.density_model = model;
    water.rho0 = 1020.0;
    water.pycnocline_depth = 5.0;
    water.pycnocline_density_increase = 8.0;
    const Ocean ocean(water, kG, 1);
    const OceanFluid fluid(ocean, 0.0);
    const Eigen::Vector3d origin_W(3.0, -1.0, -4.0);  // depth 6 m: below the 5 m pycnocline
    const float dx[] = {0.0f, 0.5f, -0.2f, 0.0f};
    const float dy[] = {0.0f, 0.1f, 0.3f, 0.0f};
    const float dz[] = {0.0f, 3.0f, -2.0f, 6.5f};  // the last is 0.5 m above the surface
    float rho[4], dp[4], ux[4], uy[4], uz[4];
    fluid.sample(origin_W, 4, dx, dy, dz, FluidSamples{rho, dp, ux, uy, uz});
    const double p_origin = ocean.pressure(ocean.depth(origin_W.z()));
    for (int k = 0; k < 4; ++k) {
      const double depth = std::max(ocean.depth(origin_W.z() + dz[k]), 0.0);
      EXPECT_NEAR(rho[k], ocean.density(depth), 1e-6 * 1030.0) << "point " << k;
      EXPECT_NEAR(dp[k], ocean.pressure(depth) - p_origin, 1e-6 * kRho * kG * 10.0) << "point " << k;
      EXPECT_FLOAT_EQ(ux[k], 0.1f);
    }
  }
}

}  // namespace
}  // namespace hadal::physics
