// The image-formation building blocks against closed forms.
#include "hadal/render/optics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include "hadal/core/units.h"

namespace hadal::render {
namespace {

// Integral of p over the sphere and its mean cosine, by the midpoint rule in cos(psi) with 200 000
// intervals: p is smooth in cos(psi), and even at g = 0.924 its forward peak, ~(1-g)^2/g = 0.006 wide in
// cos(psi), spans ~600 intervals, so the rule's error is far below the 1e-6 asked.
// exp3 against std::exp in double: within 2 ulp of float (2 * 2^-23 relative) over 1e6 arguments spread
// over [-87.3, 88], each channel; exact at 0; the clamp below -87.34 gives a tiny positive number.
TEST(OpticsTest, Exp3MatchesExpWithinTwoUlp) {
  std::uint32_t state = 12345u;
  const auto next = [&state] {  // a small LCG: the test needs spread, not quality
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) * 0x1.0p-24f;
  };
  float worst = 0.0f;
  for (int i = 0; i < 1000000; ++i) {
    const Eigen::Array3f x(-87.3f + 175.3f * next(), -20.0f * next(), 0.01f * (next() - 0.5f));
    const Eigen::Array3f y = exp3(x);
    for (int ch = 0; ch < 3; ++ch) {
      const double exact = std::exp(static_cast<double>(x[ch]));
      worst = std::max(worst, static_cast<float>(std::abs(y[ch] - exact) / exact));
    }
  }
  EXPECT_LT(worst, 2.0f * 0x1.0p-23f);
  EXPECT_EQ(exp3(Eigen::Array3f::Zero())[1], 1.0f);
  const Eigen::Array3f deep = exp3(Eigen::Array3f::Constant(-200.0f));
  EXPECT_GT(deep[0], 0.0f);
  EXPECT_LT(deep[0], 2e-38f);
}

TEST(OpticsTest, HenyeyGreensteinIsNormalizedWithMeanCosineG) {
  for (double g : {0.0, 0.5, 0.924, -0.3}) {
    const int n = 200000;
    double total = 0.0, mean_cosine = 0.0;
    for (int i = 0; i < n; ++i) {
      const double mu = -1.0 + 2.0 * (i + 0.5) / n;
      const double p = henyey_greenstein(g, mu) * 2.0 * kPi * (2.0 / n);  // d(omega) = 2 pi d(mu)
      total += p;
      mean_cosine += mu * p;
    }
    EXPECT_NEAR(total, 1.0, 1e-6) << g;
    EXPECT_NEAR(mean_cosine, g, 1e-6) << g;
  }
  EXPECT_DOUBLE_EQ(henyey_greenstein(0.0, 0.3), 1.0 / (4.0 * kPi));
}

TEST(OpticsTest, SpotLightBeamHasASoftEdge) {
  SpotLight light;
  light.inner_half_angle_rad = 0.3;
  light.outer_half_angle_rad = 0.5;
  light.intensity_W_per_sr = Rgb(10.0, 20.0, 30.0);
  const auto at = [&](double angle) {
    return light.intensity_towards(Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0));
  };
  EXPECT_TRUE((at(0.0) == light.intensity_W_per_sr).all());
  EXPECT_TRUE((at(0.29) == light.intensity_W_per_sr).all());
  EXPECT_TRUE((at(0.51) == 0.0).all());
  EXPECT_NEAR(at(0.4)[1], 10.0, 1e-9);  // half way: smoothstep(0.5) = 0.5
  double previous = 21.0;
  for (double angle = 0.3; angle <= 0.5; angle += 0.01) {
    EXPECT_LE(at(angle)[1], previous);
    previous = at(angle)[1];
  }
}

// A white Lambertian wall facing a light and camera at the same place, at distances d1 and d2: the
// pixel ratio is (d1/d2)^2 exp(-2 c (d2 - d1)) per channel (issue 11's closed form). A tilt of the
// wall by theta multiplies by cos(theta) (and moves the point's distance, which we keep). Tolerance:
// relative 1e-6, transmittance() being single precision (relative error ~1e-7).
TEST(OpticsTest, LambertianWallFollowsInverseSquareAndTwoWayAttenuation) {
  SpotLight light;  // at the origin, looking along +x
  const Rgb c(0.45, 0.12, 0.08);
  const Rgb white = Rgb::Ones();
  const Eigen::Vector3d n(-1.0, 0.0, 0.0);
  const double d1 = 2.0, d2 = 5.0;
  const Rgb L1 = lambertian_radiance(white, light, Eigen::Vector3d(d1, 0, 0), n, c, d1);
  const Rgb L2 = lambertian_radiance(white, light, Eigen::Vector3d(d2, 0, 0), n, c, d2);
  for (int k = 0; k < 3; ++k) {
    const double expected = (d1 / d2) * (d1 / d2) * std::exp(-2.0 * c[k] * (d2 - d1));
    EXPECT_NEAR(L2[k] / L1[k], expected, 1e-6 * expected);
  }
  const double expected = 100.0 / kPi / (d1 * d1) * std::exp(-2.0 * c[0] * d1);
  EXPECT_NEAR(L1[0], expected, 1e-6 * expected);
  const double tilt = 0.5;
  const Rgb L_tilted = lambertian_radiance(white, light, Eigen::Vector3d(d1, 0, 0),
                                           Eigen::Vector3d(-std::cos(tilt), std::sin(tilt), 0.0), c, d1);
  EXPECT_NEAR(L_tilted[1] / L1[1], std::cos(tilt), 1e-12);
  // Back side, and outside the beam: dark.
  EXPECT_TRUE((lambertian_radiance(white, light, Eigen::Vector3d(d1, 0, 0), -n, c, d1) == 0.0).all());
  EXPECT_TRUE((lambertian_radiance(white, light, Eigen::Vector3d(0, d1, 0), Eigen::Vector3d(0, -1, 0), c, d1) == 0.0).all());
}

// Isotropic scattering (g = 0) with a light at the camera: along the axis the light is seen at 180 deg
// and r = s, so L_b = b I / (4 pi) * integral of exp(-2 c s) / s^2. With b = 1e-6 /m and no absorption
// the exponential is 1 within 2e-3 over [0.1, 100] m and L_b = b I / (4 pi) (1/s0 - 1/s1).
// Tolerance 0.5 %: the exponential's share (< 0.2 %) plus the quadrature's (< 0.1 %).
TEST(OpticsTest, BackscatterOfACoLocatedLightMatchesTheClosedForm) {
  WaterOptics water;
  water.scattering_per_m = Rgb::Constant(1e-6);
  water.phase_g = 0.0;
  SpotLight light;
  light.inner_half_angle_rad = 1.0;
  light.outer_half_angle_rad = 1.2;
  light.p_WL = Eigen::Vector3d(0.0, 0.0, 0.0);
  const double s0 = 0.1, s1 = 100.0;
  const Rgb L = backscatter_radiance(water, {light}, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), s0, s1);
  const double expected = 1e-6 * 100.0 / (4.0 * kPi) * (1.0 / s0 - 1.0 / s1);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(L[k] / expected, 1.0, 5e-3);
  std::printf("co-located backscatter / closed form = %.6f\n", L[1] / expected);
}

// Backscatter grows with b (at fixed c, in proportion), is zero in clear water, and falls as the light
// moves away from the camera's axis (the paper's reason for wide light separation).
TEST(OpticsTest, BackscatterGrowsWithScatteringAndFallsWithLightSeparation) {
  WaterOptics water;
  water.absorption_per_m = Rgb(0.4, 0.07, 0.03);
  water.scattering_per_m = Rgb::Constant(0.05);
  SpotLight light;
  light.p_WL = Eigen::Vector3d(0.0, 0.3, 0.0);
  const Eigen::Vector3d o = Eigen::Vector3d::Zero(), d = Eigen::Vector3d::UnitX();
  const Rgb base = backscatter_radiance(water, {light}, o, d, 0.05, 20.0);
  EXPECT_TRUE((base > 0.0).all());
  WaterOptics twice = water;
  twice.scattering_per_m *= 2.0;
  twice.absorption_per_m -= water.scattering_per_m;  // same c
  const Rgb doubled = backscatter_radiance(twice, {light}, o, d, 0.05, 20.0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(doubled[k] / base[k], 2.0, 1e-12);
  WaterOptics clear = water;
  clear.scattering_per_m = Rgb::Zero();
  EXPECT_TRUE((backscatter_radiance(clear, {light}, o, d, 0.05, 20.0) == 0.0).all());
  double previous = base[1];
  for (double offset : {0.6, 1.2, 2.4}) {
    SpotLight moved = light;
    moved.p_WL.y() = offset;
    const double L = backscatter_radiance(water, {moved}, o, d, 0.05, 20.0)[1];
    EXPECT_LT(L, previous) << offset;
    previous = L;
  }
  // A light pointing away from the camera's field lights no water in front of it.
  SpotLight away = light;
  away.axis_W = -Eigen::Vector3d::UnitX();
  EXPECT_LT(backscatter_radiance(water, {away}, o, d, 0.05, 20.0)[1], 1e-3 * base[1]);
}

// The scattering angle: a light ahead of the camera shining back at it is seen in forward scatter
// (psi = 0), a light at the camera shining ahead in backscatter (psi = pi). Over a thin slab at equal
// distances from both lights everything else is equal, so the ratio is p(0) / p(pi) =
// ((1 + g) / (1 - g))^3 for Henyey–Greenstein.
TEST(OpticsTest, ForwardScatterOutshinesBackscatterByThePhaseFunction) {
  WaterOptics water;
  water.absorption_per_m = Rgb(0.3, 0.05, 0.02);
  water.scattering_per_m = Rgb::Constant(0.1);
  water.phase_g = 0.8;
  SpotLight behind;  // at the camera, shining along +x
  SpotLight ahead;   // 10 m ahead, shining back along -x
  ahead.p_WL = Eigen::Vector3d(10.0, 0.0, 0.0);
  ahead.axis_W = -Eigen::Vector3d::UnitX();
  const Eigen::Vector3d o = Eigen::Vector3d::Zero(), d = Eigen::Vector3d::UnitX();
  const double L_forward = backscatter_radiance(water, {ahead}, o, d, 4.9999, 5.0001, 1)[1];
  const double L_back = backscatter_radiance(water, {behind}, o, d, 4.9999, 5.0001, 1)[1];
  EXPECT_NEAR(L_forward / L_back, std::pow(1.8 / 0.2, 3), 1e-6 * std::pow(1.8 / 0.2, 3));
}

// Daylight's path radiance against a direct midpoint quadrature of its defining integral,
// b p(psi) E_d(z(s)) exp(-c s) ds with E_d evaluated at each sample's own depth: a downward-looking
// ray, a level one to infinity (truncated at 2000 m in the quadrature, where exp(-c s) < 1e-40), and an
// upward one that ends at the surface. Tolerance 1e-5: the midpoint rule's relative error on an
// exponential is (k h)^2 / 24, at most 2.4e-6 here (level ray, red: k = 0.38 /m, h = 0.02 m).
TEST(OpticsTest, DaylightPathRadianceMatchesItsIntegral) {
  WaterOptics water;
  water.absorption_per_m = Rgb(0.35, 0.06, 0.02);
  water.scattering_per_m = Rgb(0.03, 0.04, 0.05);
  water.phase_g = 0.85;
  Daylight daylight;
  daylight.surface_irradiance_W_per_m2 = Rgb(120.0, 150.0, 140.0);
  daylight.Kd_per_m = Rgb(0.36, 0.063, 0.019);  // Jerlov type I at 650 / 550 / 450 nm (docs/reference)
  daylight.surface_z_m = 0.0;
  const Eigen::Vector3d o(0.0, 0.0, -30.0);
  struct Ray { Eigen::Vector3d d; double s0, s1, s_quadrature_end; };
  const Ray rays[] = {{Eigen::Vector3d(1.0, 0.2, -0.6).normalized(), 0.2, 15.0, 15.0},
                      {Eigen::Vector3d(0.0, 1.0, 0.0), 0.1, std::numeric_limits<double>::infinity(), 2000.0},
                      {Eigen::Vector3d(0.3, 0.0, 1.0).normalized(), 0.1, 100.0, 30.0 * std::sqrt(1.09)}};
  for (const Ray& ray : rays) {
    const Rgb closed = daylight_path_radiance(water, daylight, o, ray.d, ray.s0, ray.s1);
    const int n = 100000;
    Rgb sum = Rgb::Zero();
    const double h = (ray.s_quadrature_end - ray.s0) / n;
    for (int i = 0; i < n; ++i) {
      const double s = ray.s0 + (i + 0.5) * h;
      const Eigen::Vector3d x = o + s * ray.d;
      sum += water.scattering_per_m * henyey_greenstein(water.phase_g, ray.d.z()) * daylight.irradiance_at(x.z()) *
             (-water.attenuation_per_m() * s).exp() * h;
    }
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(closed[ch] / sum[ch], 1.0, 1e-5) << ray.d.transpose() << " ch " << ch;
  }
  // Lambertian under daylight: E_d(z) (1 + n_z) / 2 albedo / pi, attenuated towards the camera (relative
  // 1e-6: single-precision transmittance); a vertical face gets half a level one's, a downward face none.
  const Rgb L = daylight_surface_radiance(Rgb::Constant(0.5), daylight, Eigen::Vector3d(0, 0, -30.0),
                                          Eigen::Vector3d(0.6, 0.0, 0.8), water.attenuation_per_m(), 4.0);
  for (int ch = 0; ch < 3; ++ch) {
    const double expected = 0.5 / kPi * daylight.surface_irradiance_W_per_m2[ch] * std::exp(-daylight.Kd_per_m[ch] * 30.0) *
                            0.9 * std::exp(-water.attenuation_per_m()[ch] * 4.0);
    EXPECT_NEAR(L[ch], expected, 1e-6 * expected);
  }
  EXPECT_TRUE((daylight_surface_radiance(Rgb::Ones(), daylight, Eigen::Vector3d(0, 0, -30.0), Eigen::Vector3d(0, 0, -1),
                                         water.attenuation_per_m(), 4.0) == 0.0).all());
  const Rgb level = daylight_surface_radiance(Rgb::Ones(), daylight, Eigen::Vector3d(0, 0, -30.0),
                                              Eigen::Vector3d(0, 0, 1), water.attenuation_per_m(), 4.0);
  const Rgb vertical = daylight_surface_radiance(Rgb::Ones(), daylight, Eigen::Vector3d(0, 0, -30.0),
                                                 Eigen::Vector3d(1, 0, 0), water.attenuation_per_m(), 4.0);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(vertical[ch], 0.5 * level[ch], 1e-12 * level[ch]);
}

TEST(OpticsTest, InvalidParametersAreRejected) {
  WaterOptics water;
  water.phase_g = 1.0;
  EXPECT_THROW(validate(water), std::invalid_argument);
  water.phase_g = 0.9;
  water.absorption_per_m[2] = -0.1;
  EXPECT_THROW(validate(water), std::invalid_argument);
  SpotLight light;
  light.axis_W = Eigen::Vector3d(1.0, 1.0, 0.0);
  EXPECT_THROW(validate(light), std::invalid_argument);
  light.axis_W = Eigen::Vector3d::UnitX();
  light.inner_half_angle_rad = 0.7;
  EXPECT_THROW(validate(light), std::invalid_argument);
  EXPECT_NO_THROW(validate(SpotLight{}));
  EXPECT_NO_THROW(validate(WaterOptics{}));
  EXPECT_THROW(backscatter_radiance(WaterOptics{}, {}, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 0.0, 1.0),
               std::invalid_argument);
}

}  // namespace
}  // namespace hadal::render
