// The backscatter table against backscatter_radiance() evaluated per pixel (render/optics.h), the
// integral it replaces.
#include "hadal/render/backscatter_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "hadal/core/units.h"
#include "hadal/render/camera_rays.h"
#include "hadal/render/frame.h"
#include "render_test_support.h"

namespace hadal::render {
namespace {

// A camera at the origin looking along +x with two lights 0.8 m left and right of it, their beams
// along the axis: the case whose banding set backscatter_samples (render/frame.h), in turbid water.
struct LitWater {
  WaterOptics water;
  std::vector<SpotLight> lights;
  Eigen::Isometry3d X_WC = X_SC();
  LitWater(double b, double half_spacing_m, const Eigen::Vector3d& axis_W = Eigen::Vector3d::UnitX()) {
    water.absorption_per_m = Rgb(0.35, 0.07, 0.04);
    water.scattering_per_m = Rgb::Constant(b);
    for (double side : {half_spacing_m, -half_spacing_m}) {
      SpotLight light;
      light.p_WL = Eigen::Vector3d(0.0, side, 0.0);
      light.axis_W = axis_W.normalized();
      light.inner_half_angle_rad = 0.35;
      light.outer_half_angle_rad = 0.45;
      light.intensity_W_per_sr = Rgb(250.0, 300.0, 280.0);
      lights.push_back(light);
    }
  }
  Rgb exact(const Lens& lens, int u, int v, double s0, double s_end, int samples) const {
    const Eigen::Vector3d d_W = (X_WC.linear() * lens.ray_C(u, v).cast<double>()).normalized();
    return backscatter_radiance(water, lights, X_WC.translation(), d_W, s0, s_end, samples);
  }
};

// At a node and at the end of the s grid, the table holds backscatter_radiance's own sum (same grid,
// same order of additions), rounded to float: 1e-6 relative.
TEST(BackscatterTableTest, NodesAtTheFarEndHoldThePerPixelIntegral) {
  const LitWater setup(0.15, 0.8);
  const Lens lens = make_lens(lens_from_horizontal_fov(64, 48, 1.2));
  const BackscatterTable table(setup.water, setup.lights, lens, setup.X_WC, 0.1, 20.0, 128, 8);
  EXPECT_EQ(table.nodes(), 9u * 7u);  // columns 0, 8, ..., 56, 63; rows 0, 8, ..., 40, 47
  for (int v : {0, 8, 24, 47}) {
    for (int u : {0, 16, 32, 63}) {
      const Rgb expected = setup.exact(lens, u, v, 0.1, 20.0, 128);
      const Rgb got = table.at(u, v, 20.0);
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], expected[ch], 1e-6 * expected[ch] + 1e-300) << u << " " << v;
    }
  }
}

// Pixels all over a 640x480 frame (a 60 deg and a 100 deg barrel lens), each with its ray's end drawn
// across [s0, s_max], lights on the axis and turned 20 deg off it, the defaults of render/frame.h (128
// samples, nodes every 8 px): the table against a reference integral per pixel (1024 samples; the
// midpoint rule's error falls as 1/samples^2, so the reference is ~64x closer than the 128-sample
// per-pixel integral, whose own error is printed beside). Errors relative to the frame's largest
// backscatter (a pixel's own value can be tiny at a beam edge). Measured: 60 deg 0.30 % and 0.40 %,
// 100 deg 1.4 % and 1.8 % (the image's edges, whose rays pass within 0.5 m of a light, where the
// backscatter changes fastest with direction and with distance); bounds 0.6 % and 3 %.
TEST(BackscatterTableTest, InterpolationStaysCloseToTheIntegral) {
  LensSpec narrow = lens_from_horizontal_fov(640, 480, 60.0 * kDegToRad);
  narrow.model = LensModel::kRadialTangential;
  narrow.distortion = {-0.2, 0.05, 0.0, 0.0, 0.0};
  LensSpec wide = lens_from_horizontal_fov(640, 480, 100.0 * kDegToRad);
  wide.model = LensModel::kRadialTangential;
  wide.distortion = {-0.3, 0.08, 0.0, 0.0, 0.0};
  const double s0 = 0.1, s_max = 30.0;
  const FrameLighting defaults;
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> log_s(std::log(s0), std::log(s_max));
  for (const auto& [spec, bound] : {std::pair{narrow, 0.006}, std::pair{wide, 0.03}}) {
    const Lens lens = make_lens(spec);
    for (const Eigen::Vector3d& axis : {Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d(1.0, 0.0, -0.364)}) {
      const LitWater setup(0.15, 0.8, axis);
      const BackscatterTable table(setup.water, setup.lights, lens, setup.X_WC, s0, s_max, defaults.backscatter_samples,
                                   defaults.backscatter_grid_px);
      double largest = 0.0, worst = 0.0, per_pixel_worst = 0.0;
      std::vector<std::array<Rgb, 3>> results;  // table, reference, per pixel
      // Every 7th pixel in each direction (mostly off the nodes), one draw of s each.
      for (int v = 2; v < 480; v += 7) {
        for (int u = 1; u < 640; u += 7) {
          const double s_end = std::exp(log_s(random));
          const Rgb reference = setup.exact(lens, u, v, s0, s_end, 1024);
          results.push_back({table.at(u, v, s_end), reference,
                             setup.exact(lens, u, v, s0, s_end, defaults.backscatter_samples)});
          largest = std::max(largest, reference.maxCoeff());
        }
      }
      for (const auto& [got, reference, per_pixel] : results) {
        worst = std::max(worst, (got - reference).abs().maxCoeff() / largest);
        per_pixel_worst = std::max(per_pixel_worst, (per_pixel - reference).abs().maxCoeff() / largest);
      }
      std::printf("hfov %.0f deg, beam axis z %.3f: table %.2e, per-pixel integral %.2e of the largest\n",
                  2.0 * std::atan(spec.width_px / (2.0 * spec.fx)) / kDegToRad, axis.z(), worst, per_pixel_worst);
      EXPECT_LT(worst, bound);
      EXPECT_GT(largest, 0.0);
    }
  }
}

TEST(BackscatterTableTest, EmptyWithoutLightsOrScatteringAndRejectsBadGrids) {
  const Lens lens = make_lens(lens_from_horizontal_fov(32, 24, 1.0));
  const LitWater setup(0.1, 0.5);
  const BackscatterTable dark(setup.water, {}, lens, setup.X_WC, 0.1, 10.0, 16, 4);
  EXPECT_TRUE((dark.at(5, 5, 5.0) == 0.0).all());
  WaterOptics clear = setup.water;
  clear.scattering_per_m = Rgb::Zero();
  const BackscatterTable unscattered(clear, setup.lights, lens, setup.X_WC, 0.1, 10.0, 16, 4);
  EXPECT_TRUE((unscattered.at(5, 5, 5.0) == 0.0).all());
  EXPECT_THROW(BackscatterTable(setup.water, setup.lights, lens, setup.X_WC, 0.0, 10.0, 16, 4), std::invalid_argument);
  EXPECT_THROW(BackscatterTable(setup.water, setup.lights, lens, setup.X_WC, 0.1, INFINITY, 16, 4), std::invalid_argument);
  EXPECT_THROW(BackscatterTable(setup.water, setup.lights, lens, setup.X_WC, 0.1, 10.0, 0, 4), std::invalid_argument);
  EXPECT_THROW(BackscatterTable(setup.water, setup.lights, lens, setup.X_WC, 0.1, 10.0, 16, 0), std::invalid_argument);
}

// add_row (single precision, a row at a time: what a frame uses) against at() (double precision), on
// every row of a 100x75 frame, node rows and rows between, every column including the last, with each
// pixel's ray end drawn across [s0, s_max] (and below s0 and beyond s_max), or on every other row rising
// slowly along the row: within 2e-6 of the frame's
// largest value (fast::log's 2 ulp and float sums), nothing where s_end <= s0, and added to what the
// row held (a second call doubles it, exactly).
TEST(BackscatterTableTest, RowsInSinglePrecisionMatchThePixelLookup) {
  const Lens lens = make_lens(lens_from_horizontal_fov(100, 75, 1.3));
  const LitWater setup(0.2, 0.5);
  const double s0 = 0.1, s_max = 18.0;
  const BackscatterTable table(setup.water, setup.lights, lens, setup.X_WC, s0, s_max, 128, 8);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> log_s(std::log(0.05), std::log(25.0));
  double largest = 0.0;
  for (int u = 0; u < 100; ++u) largest = std::max(largest, table.at(u, 37, s_max).maxCoeff());
  ASSERT_GT(largest, 0.0);
  for (int v = 0; v < 75; ++v) {
    std::vector<float> s_end(100), r(100, 0.0f), g(100, 0.0f), b(100, 0.0f);
    if (v % 2 == 0) {
      for (float& s : s_end) s = static_cast<float>(std::exp(log_s(rng)));
    } else {  // a slow ramp, as over a seabed: runs of pixels in the same interval of s and node column
      for (int u = 0; u < 100; ++u) s_end[u] = static_cast<float>(0.3 * std::exp(0.04 * u + 0.01 * v));
    }
    s_end[0] = static_cast<float>(s0);  // exactly at the start: nothing
    s_end[99] = 30.0f;                  // beyond s_max: the whole table
    table.add_row(v, s_end.data(), r.data(), g.data(), b.data());
    for (int u = 0; u < 100; ++u) {
      const Rgb expected = s_end[u] > s0 ? table.at(u, v, s_end[u]) : Rgb::Zero();
      const std::array<float, 3> got = {r[u], g[u], b[u]};
      for (int ch = 0; ch < 3; ++ch) {
        ASSERT_NEAR(got[ch], expected[ch], 2e-6 * largest) << "u " << u << " v " << v << " ch " << ch;
      }
    }
    ASSERT_EQ(r[0], 0.0f);
    const std::vector<float> once = g;
    table.add_row(v, s_end.data(), r.data(), g.data(), b.data());
    for (int u = 0; u < 100; ++u) ASSERT_EQ(g[u], 2.0f * once[u]);
  }
}

// Rows of nodes are independent: built on a loop that runs them backwards, the table is the same.
TEST(BackscatterTableTest, DoesNotDependOnTheOrderOfItsRows) {
  const Lens lens = make_lens(lens_from_horizontal_fov(96, 64, 1.2));
  const LitWater setup(0.1, 0.6);
  const BackscatterTable forward(setup.water, setup.lights, lens, setup.X_WC, 0.1, 15.0, 64, 8);
  const BackscatterTable backward(setup.water, setup.lights, lens, setup.X_WC, 0.1, 15.0, 64, 8,
                                  [](std::size_t count, const std::function<void(std::size_t)>& task) {
                                    for (std::size_t i = count; i-- > 0;) task(i);
                                  });
  for (int v = 0; v < 64; v += 3) {
    for (int u = 0; u < 96; u += 5) EXPECT_TRUE((forward.at(u, v, 7.3) == backward.at(u, v, 7.3)).all());
  }
}

}  // namespace
}  // namespace hadal::render
