#include "hadal/physics/ocean_fluid.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cfloat>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

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

// The kernel's uniform-water path (FluidSampler::uniform) is taken for constant water without waves or shear, and then
// gives UniformWater's bits; ramp and CTD water, a shear current and waves are sampled face by face.
TEST(OceanFluidTest, OnlyConstantCalmUnshearedWaterIsUniform) {
  const Eigen::Vector3d current_W(0.3, 0.5, -0.1);
  const Ocean constant(constant_water(current_W), kG, 1);
  const std::optional<FluidSampler::Uniform> uniform = OceanFluid(constant, 3.0).uniform();
  ASSERT_TRUE(uniform.has_value());
  EXPECT_EQ(uniform->density, kRho);
  EXPECT_EQ(uniform->current_W, current_W);

  WaterSpec ramp = constant_water(current_W);
  ramp.density_model = DensityModel::kRamp;
  EXPECT_FALSE(OceanFluid(Ocean(ramp, kG, 1), 3.0).uniform().has_value());
  WaterSpec ctd = constant_water(current_W);
  ctd.density_model = DensityModel::kCtd;
  ctd.ctd = {{0.0, 20.0, 35.5}, {1000.0, 4.0, 34.6}};
  EXPECT_FALSE(OceanFluid(Ocean(ctd, kG, 1), 3.0).uniform().has_value());
  WaterSpec sheared = constant_water(current_W);
  sheared.current.shear_surface_W = Eigen::Vector3d(0.2, 0.0, 0.0);
  EXPECT_FALSE(OceanFluid(Ocean(sheared, kG, 1), 3.0).uniform().has_value());
  WorldSpec sea;
  sea.water = constant_water(current_W);
  sea.waves.spectrum = WaveSpectrum::kJonswap;
  sea.waves.significant_height = 1.0;
  sea.waves.peak_period = 6.0;
  EXPECT_FALSE(OceanFluid(Ocean(sea), 3.0).uniform().has_value());

  // Fully submerged: UniformWater's wrench to the bit (both take the constants' path).
  UniformWater water;
  water.density = kRho;
  water.gravity = kG;
  water.surface_z = 2.0;
  water.current_W = current_W;
  SurfaceHydrodynamics a = box_hydro(), b = box_hydro();
  const BodyMotion m = moving_at({10.0, -4.0, -50.0});
  const HydrodynamicWrench expected = a.compute(m, water), got = b.compute(m, OceanFluid(constant, 3.0));
  EXPECT_EQ(got.f_W, expected.f_W);
  EXPECT_EQ(got.tau_W, expected.tau_W);
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

WaterSpec ramp_water() {
  WaterSpec water;
  water.density_model = DensityModel::kRamp;  // defaults: 1025 kg/m^3, +3.075 kg/m^3 over 1000 m
  water.surface_z = 2.0;
  water.current.uniform_W = Eigen::Vector3d(0.1, 0.0, 0.0);
  return water;
}

// CTD rows at 0, 200, 1000 and 6000 m (kinks of T and S, hence of drho/dd); the table ends at 11 km.
WaterSpec ctd_water() {
  WaterSpec water = ramp_water();
  water.density_model = DensityModel::kCtd;
  water.ctd = {{0.0, 20.0, 35.5}, {200.0, 12.0, 35.0}, {1000.0, 4.0, 34.6}, {6000.0, 1.5, 34.7}};
  return water;
}

// OceanFluid::sample for a body whose origin is at depth d_origin against the Ocean's point queries
// (Ocean::density, Ocean::pressure at origin + dz, in double). 300 offsets over +-3.3 m at an irregular
// spacing (two sampling blocks; the points fall anywhere inside the 0.5 m CTD table segments, some on
// nodes), the origin itself first.
// Tolerance: each output is the float rounding of a double that differs from the reference only by
// double roundings. The rounding to float is at most half an ulp, <= FLT_EPSILON / 2 of the value; we
// allow FLT_EPSILON |reference|. The double part: a few roundings of each of the two absolute pressures
// (up to 1.2e8 Pa at 11.5 km) and of the depth (times dp/dd = rho g): 64 DBL_EPSILON of the deepest
// absolute pressure, ~2e-6 Pa, and 64 DBL_EPSILON of rho.
void expect_samples_match(const Ocean& ocean, double d_origin) {
  const double surface_z = ocean.surface_z();
  const Eigen::Vector3d origin_W(-3.0, 7.0, surface_z - d_origin);
  std::vector<float> dx, dy, dz;
  for (int k = 0; k < 300; ++k) {
    dz.push_back(k == 0 ? 0.0f : static_cast<float>(-3.3 + 0.0221 * k + 0.01 * std::sin(7.0 * k)));
    dx.push_back(0.1f * static_cast<float>(k % 7));
    dy.push_back(-0.2f * static_cast<float>(k % 5));
  }
  dz.push_back(static_cast<float>(std::round(d_origin) - d_origin));  // a table node (if |.| is small)
  dx.push_back(0.0f);
  dy.push_back(0.0f);
  const std::size_t n = dz.size();
  std::vector<float> rho(n), dp(n), ux(n), uy(n), uz(n);
  const OceanFluid fluid(ocean, 1.0);
  fluid.sample(origin_W, n, dx.data(), dy.data(), dz.data(),
               FluidSamples{rho.data(), dp.data(), ux.data(), uy.data(), uz.data()});
  const double p_origin = ocean.pressure(ocean.depth(origin_W.z()));
  const double p_deepest = ocean.pressure(d_origin + 3.4);
  for (std::size_t i = 0; i < n; ++i) {
    const double depth = ocean.depth(origin_W.z() + dz[i]);
    const double rho_ref = ocean.density(depth);
    const double dp_ref = ocean.pressure(depth) - p_origin;
    EXPECT_NEAR(rho[i], rho_ref, FLT_EPSILON * rho_ref + 64.0 * DBL_EPSILON * rho_ref)
        << "origin depth " << d_origin << ", point depth " << depth;
    EXPECT_NEAR(dp[i], dp_ref, FLT_EPSILON * std::abs(dp_ref) + 64.0 * DBL_EPSILON * p_deepest)
        << "origin depth " << d_origin << ", point depth " << depth;
    EXPECT_EQ(ux[i], 0.1f);
  }
}

// Origins on and near the surface (points above and below it: rho(0) and gauge pressure 0 above), on
// both sides of the pycnocline kink, and deep; the paper's ramp (kink at 1000 m) and a sharp one whose
// kink at 5 m lies inside the points of a body at the surface.
TEST(OceanFluidTest, RampSamplesMatchPointQueries) {
  const Ocean ocean(ramp_water(), kG, 1);
  for (const double d : {-1.0, 0.0, 1.3, 30.0, 998.7, 1000.0, 1001.1, 6000.0}) {
    expect_samples_match(ocean, d);
  }
  WaterSpec sharp = ramp_water();
  sharp.pycnocline_depth = 5.0;
  sharp.pycnocline_density_increase = 8.0;
  const Ocean sharp_ocean(sharp, kG, 1);
  for (const double d : {-1.0, 0.0, 1.3, 4.0, 5.0, 6.2, 6000.0}) {
    expect_samples_match(sharp_ocean, d);
  }
}

// As above, plus across the CTD rows (200, 1000, 6000 m), on table nodes and between them, and across
// the end of the table at 11 km (linear continuation below it).
TEST(OceanFluidTest, CtdSamplesMatchPointQueries) {
  const Ocean ocean(ctd_water(), kG, 1);
  for (const double d : {-1.0, 0.0, 1.3, 37.37, 199.0, 200.0, 200.25, 999.8, 1000.0, 3000.1, 5998.2, 6000.0,
                         10998.6, 11000.0, 11500.0}) {
    expect_samples_match(ocean, d);
  }
}

// The Ocean's point queries one by one: a reference sampler for the kernel.
class PointwiseOcean final : public FluidSampler {
 public:
  explicit PointwiseOcean(const Ocean& ocean) : ocean_(ocean) {}
  double surface_z_W() const override { return ocean_.surface_z(); }
  double gauge_pressure(double z_W) const override {
    return ocean_.pressure(ocean_.depth(z_W)) - ocean_.atmospheric_pressure();
  }
  double gravity_magnitude() const override { return ocean_.gravity(); }
  void sample(const Eigen::Vector3d& origin_W, std::size_t n, const float* /*dx*/, const float* /*dy*/,
              const float* dz, const FluidSamples& out) const override {
    const double p_origin = gauge_pressure(origin_W.z());
    for (std::size_t i = 0; i < n; ++i) {
      const double z_W = origin_W.z() + dz[i];
      out.rho[i] = static_cast<float>(ocean_.density(ocean_.depth(z_W)));
      out.dp[i] = static_cast<float>(gauge_pressure(z_W) - p_origin);
      const Eigen::Vector3d u_W = ocean_.current_W(Eigen::Vector3d(0.0, 0.0, z_W), 0.0);
      out.u_x[i] = static_cast<float>(u_W.x());
      out.u_y[i] = static_cast<float>(u_W.y());
      out.u_z[i] = static_cast<float>(u_W.z());
    }
  }

 private:
  const Ocean& ocean_;
};

// The whole kernel with OceanFluid against the point-by-point sampler: the samples agree to float
// rounding (tests above), so the wrenches agree to kFloat as in ConstantWaterGivesTheUniformWaterWrench.
TEST(OceanFluidTest, RampAndCtdWrenchesMatchThePointwiseSampler) {
  for (const WaterSpec& water : {ramp_water(), ctd_water()}) {
    const Ocean ocean(water, kG, 1);
    const OceanFluid fluid(ocean, 0.0);
    const PointwiseOcean pointwise(ocean);
    // Crossing the surface, across the 200 m row and the 1000 m pycnocline, deep.
    for (const double z : {2.1, -198.0, -998.0, -5998.0}) {
      SurfaceHydrodynamics a = box_hydro(), b = box_hydro();
      const BodyMotion motion = moving_at({1.0, 2.0, z});
      const HydrodynamicWrench expected = a.compute(motion, pointwise);
      const HydrodynamicWrench got = b.compute(motion, fluid);
      const double f_scale = expected.f_W.norm(), tau_scale = std::max(expected.tau_W.norm(), f_scale);
      EXPECT_GT(f_scale, 100.0);
      EXPECT_LT((got.f_W - expected.f_W).norm(), kFloat * f_scale) << "z " << z;
      EXPECT_LT((got.tau_W - expected.tau_W).norm(), kFloat * tau_scale) << "z " << z;
      EXPECT_EQ(got.clipped_faces, expected.clipped_faces);
    }
  }
}

// A world of kRho water under one regular deep-water wave (amplitude a [m], period [s]) from t = 0 (no build-up).
WorldSpec regular_sea(double a, double period) {
  WorldSpec world;
  world.water.density = kRho;
  world.waves.spectrum = WaveSpectrum::kRegular;
  world.waves.regular = {{a, period, 0.0, 0.0}};
  world.waves.ramp_time = 0.0;
  return world;
}

// A box's faces with the pressure alone (drag, friction and lift off).
SurfaceHydrodynamics pressure_only_box(const Eigen::Vector3d& size) {
  CollisionShape box;
  box.box_size = size;
  HydrodynamicCoefficients pressure_only;
  pressure_only.drag = pressure_only.skin_friction = pressure_only.lift = 0.0;
  return SurfaceHydrodynamics(geometry::tessellate(box), pressure_only);
}

// Waves on a submerged 2 m cube (drag, friction and lift off: the pressure alone, less the calm water's buoyancy),
// regular deep-water waves of 1 m and 8 s (lambda 99.9 m): the dynamic pressure, linear about the cube's centre,
// integrates to the Froude-Krylov force -V grad p_d, whose horizontal and vertical amplitudes are rho g a k V e^(k z')
// (z' = z - eta, Wheeler: between e^(k (z - a)) and e^(k (z + a)) as the surface swings; 1 % for the field's curvature
// across the cube and float); a wavelength down the wave force is under 1 % of that just below the surface
// (e^(-k lambda) = 0.19 %).
TEST(OceanFluidTest, WavesPushASubmergedBodyWithTheirFroudeKrylovForce) {
  const WorldSpec world = regular_sea(1.0, 8.0);
  const Ocean ocean(world);
  SurfaceHydrodynamics hydro = pressure_only_box(Eigen::Vector3d(2.0, 2.0, 2.0));
  WorldSpec calm_world = world;
  calm_world.waves = WaveSpec{};
  const Ocean calm(calm_world);
  const double omega = 2.0 * M_PI / 8.0, k = omega * omega / kG, lambda = 2.0 * M_PI / k;
  const auto amplitude = [&](double z) {
    BodyMotion motion;
    motion.X_WB.translation() = Eigen::Vector3d(0.0, 0.0, z);
    motion.p_WBcm = motion.X_WB.translation();
    const Eigen::Vector3d buoyancy = hydro.compute(motion, OceanFluid(calm, 0.0)).f_W;
    Eigen::Vector3d largest = Eigen::Vector3d::Zero();
    for (int i = 0; i < 80; ++i) {
      const HydrodynamicWrench w = hydro.compute(motion, OceanFluid(ocean, 0.1 * i));
      largest = largest.cwiseMax((w.f_W - buoyancy).cwiseAbs());
    }
    return largest;
  };
  const Eigen::Vector3d near = amplitude(-3.0);
  // The surface over the cube's centre swings by a: z' = z - eta spans e^(k (z - a)) .. e^(k (z + a)); the
  // amplitude (at the crest or trough where the force peaks) is within that range.
  const double fk = kRho * kG * 1.0 * k * 8.0 * std::exp(k * -3.0);
  EXPECT_GT(near.x(), fk * std::exp(-k) * 0.99);
  EXPECT_LT(near.x(), fk * std::exp(k) * 1.01);
  EXPECT_GT(near.z(), fk * std::exp(-k) * 0.99);
  EXPECT_LT(near.z(), fk * std::exp(k) * 1.01);
  const Eigen::Vector3d deep = amplitude(-3.0 - lambda);
  EXPECT_LT(deep.norm(), 0.01 * near.norm());
  EXPECT_GT(deep.norm(), 0.0);
}

// Under a crest, between the mean level and the surface, the gauge pressure a crossing body is referred to is the
// signed hydrostatic rho g (surface_z - z) (negative there) plus the wave's dynamic pressure: positive below the
// moving surface and zero at it (1e-6 of rho g a), as the waves' own pressure_at says.
TEST(OceanFluidTest, UnderACrestThePressureIsZeroAtTheMovingSurface) {
  const Ocean ocean(regular_sea(1.0, 8.0));
  const OceanFluid fluid(ocean, 0.0);  // a crest at x = 0
  EXPECT_NEAR(fluid.surface_plane(Eigen::Vector3d::Zero()).height, 1.0, 1e-12);
  EXPECT_NEAR(fluid.gauge_pressure_at(Eigen::Vector3d(0.0, 0.0, 1.0)), 0.0, 1e-6 * kRho * kG);
  for (double z : {0.9, 0.5, 0.1, -0.5}) {
    const Eigen::Vector3d p(0.0, 0.0, z);
    const double expected = ocean.pressure_at(p, 0.0) - ocean.atmospheric_pressure();
    EXPECT_NEAR(fluid.gauge_pressure_at(p), expected, 1e-9 * kRho * kG) << z;
    EXPECT_GT(fluid.gauge_pressure_at(p), 0.0) << z;
    EXPECT_LT(fluid.gauge_pressure_at(p), kRho * kG * (1.0 - z)) << z;  // less than the still-water column above
  }
}

// A floating 10 x 10 x 2 m box at its 1 m draft, its centre of mass 0.5 m down (at the centre of buoyancy), in regular deep-water
// waves of 0.3 m and 20 s without build-up, at the instant the surface crosses the mean level over it rising toward +x
// (eta = a sin(k x)): linear theory integrated over its wetted faces gives
//   F_x   = -2 L rho g a sin(k L / 2) (1 - e^(-k d)) / k                    (the sides, L = 10 m, d = 1 m)
//   tau_y = -L rho g a e^(-k d) 2 (sin(k L / 2) - (k L / 2) cos(k L / 2)) / k^2  (the bottom's pressure, bow up)
// within 1 %: the dynamic pressure is linear about the centre of mass (e^(k 0.5) = 1.005 at the bottom). The moment
// needs the dynamic pressure's gradient inside each face (the box's bottom is two triangles): without it, it is a third.
// The same force with the centre of mass in the air above the waterline.
TEST(OceanFluidTest, AFloatingBoxFeelsTheWaveSlopeAsLinearTheoryIntegrates) {
  const Ocean ocean(regular_sea(0.3, 20.0));
  SurfaceHydrodynamics hydro = pressure_only_box(Eigen::Vector3d(10.0, 10.0, 2.0));
  const double a = 0.3, omega = 2.0 * M_PI / 20.0, k = omega * omega / kG, L = 10.0, d = 1.0, h = 0.5 * k * L;
  BodyMotion motion;
  motion.p_WBcm = Eigen::Vector3d(0.0, 0.0, -0.5);
  const HydrodynamicWrench w = hydro.compute(motion, OceanFluid(ocean, 5.0));  // eta = a cos(-omega t) = a sin(k x)
  // A centre of mass above the water (a vessel's often is): the waves are expanded about the surface under it, so the
  // force is the same (1e-4: float sums about another point).
  BodyMotion high = motion;
  high.p_WBcm.z() = 0.6;
  const HydrodynamicWrench w_high = hydro.compute(high, OceanFluid(ocean, 5.0));
  EXPECT_LT((w_high.f_W - w.f_W).norm(), 1e-4 * w.f_W.norm()) << w_high.f_W.transpose() << " vs " << w.f_W.transpose();
  const double f_x = -2.0 * L * kRho * kG * a * std::sin(h) * (1.0 - std::exp(-k * d)) / k;
  const double tau_y = -L * kRho * kG * a * std::exp(-k * d) * 2.0 * (std::sin(h) - h * std::cos(h)) / (k * k);
  EXPECT_NEAR(w.f_W.x() / f_x, 1.0, 0.01) << w.f_W.x() << " vs " << f_x;
  EXPECT_NEAR(w.tau_W.y() / tau_y, 1.0, 0.01) << w.tau_W.y() << " vs " << tau_y;
  EXPECT_NEAR(w.f_W.z(), kRho * kG * L * L * d, 1e-4 * kRho * kG * L * L * d);  // the mean waterline's buoyancy
  EXPECT_NEAR(w.f_W.y(), 0.0, 1e-5 * std::abs(f_x));  // float sums
  EXPECT_NEAR(w.tau_W.x(), 0.0, 1e-5 * std::abs(tau_y));
}

}  // namespace
}  // namespace hadal::physics
