// Forward scatter against its closed forms: the Henyey–Greenstein share within an angle, the point
// spread's normalisation and encircled energy, the pixel kernel's energy and shape, and a rendered
// frame's halo carrying exp(b_f d) - 1 of the surface's light.
#include "hadal/render/forward_scatter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/render/camera_rays.h"
#include "hadal/render/frame.h"
#include "render_test_support.h"

namespace hadal::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

// int_{cos max}^1 2 pi p_HG(mu) dmu by the midpoint rule in the angle (1e5 intervals).
double hg_share_numerically(double g, double max_angle) {
  const int n = 100000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double psi = (i + 0.5) * max_angle / n;
    sum += 2.0 * kPi * henyey_greenstein(g, std::cos(psi)) * std::sin(psi) * max_angle / n;
  }
  return sum;
}

TEST(ForwardScatterTest, HenyeyGreensteinShareMatchesItsIntegral) {
  for (double g : {0.0, 0.5, 0.924, -0.3}) {
    for (double angle : {0.05, 0.1745, 0.5, 3.0}) {
      EXPECT_NEAR(hg_fraction_within(g, angle), hg_share_numerically(g, angle), 1e-6) << g << " " << angle;
    }
    EXPECT_NEAR(hg_fraction_within(g, kPi), 1.0, 1e-12);
    EXPECT_NEAR(hg_fraction_within(g, 0.0), 0.0, 1e-14);
  }
  EXPECT_NEAR(hg_fraction_within(0.0, 1.0), (1.0 - std::cos(1.0)) / 2.0, 1e-15);
  // Petzold-like g = 0.924 within 10 deg: 61 % of the scattering.
  EXPECT_NEAR(hg_fraction_within(0.924, 10.0 * kDegToRad), 0.611, 0.001);
  WaterOptics water;
  water.scattering_per_m = Rgb(0.1, 0.2, 0.3);
  EXPECT_TRUE((forward_scattering_per_m(water) == 0.0).all());  // off by default
  water.forward_scatter_max_angle_rad = 0.2;
  EXPECT_TRUE(((forward_scattering_per_m(water) - water.scattering_per_m * hg_fraction_within(0.924, 0.2)).abs() < 1e-15).all());
  EXPECT_THROW(hg_fraction_within(0.5, -0.1), std::invalid_argument);
  EXPECT_THROW(ForwardScatterPsf(0.9, 0.6), std::invalid_argument);  // beyond 30 deg
  water.forward_scatter_max_angle_rad = 0.6;
  EXPECT_THROW(validate(water), std::invalid_argument);
}

// 2 pi int_0^theta K(alpha) alpha dalpha by the midpoint rule on a log grid (K ~ 1/alpha at 0).
double encircled_numerically(const ForwardScatterPsf& psf, double theta) {
  const int n = 20000;
  const double lo = 1e-9;
  double sum = 2.0 * kPi * psf.density_per_sr(lo) * lo * lo;  // K ~ C / alpha below lo: 2 pi C lo
  for (int i = 0; i < n; ++i) {
    const double a0 = lo * std::pow(theta / lo, static_cast<double>(i) / n);
    const double a1 = lo * std::pow(theta / lo, static_cast<double>(i + 1) / n);
    const double a = 0.5 * (a0 + a1);
    sum += 2.0 * kPi * psf.density_per_sr(a) * a * (a1 - a0);
  }
  return sum;
}

TEST(ForwardScatterTest, PointSpreadIsNormalisedAndItsEncircledEnergyIsItsIntegral) {
  for (double g : {0.924, 0.7}) {
    const ForwardScatterPsf psf(g, 10.0 * kDegToRad);
    EXPECT_EQ(psf.encircled(psf.max_angle_rad()), 1.0);
    EXPECT_EQ(psf.density_per_sr(psf.max_angle_rad()), 0.0);
    double previous_e = 0.0, previous_k = psf.density_per_sr(1e-6);
    for (double alpha : {1e-4, 1e-3, 0.01, 0.05, 0.1, 0.17}) {
      const double e = psf.encircled(alpha);
      EXPECT_NEAR(e, encircled_numerically(psf, alpha), 2e-4) << g << " " << alpha;
      EXPECT_GT(e, previous_e);  // light within a wider circle
      EXPECT_LT(psf.density_per_sr(alpha), previous_k);  // fainter further out
      previous_e = e;
      previous_k = psf.density_per_sr(alpha);
    }
    EXPECT_NEAR(encircled_numerically(psf, psf.max_angle_rad()), 1.0, 2e-4);
  }
  // A more forward-peaked phase function keeps more of the light close in.
  EXPECT_GT(ForwardScatterPsf(0.95, 0.2).encircled(0.01), ForwardScatterPsf(0.8, 0.2).encircled(0.01));
}

// One pixel's light spread over a 640 x 480 image by the multi-scale kernel.
std::vector<Rgbf> spread_of_one_pixel(const ForwardScatterKernel& kernel, int x0, int y0) {
  const int w = 640, h = 480;
  std::array<std::vector<float>, 3> source;
  for (int ch = 0; ch < 3; ++ch) {
    source[ch].assign(static_cast<std::size_t>(w) * h, 0.0f);
    source[ch][static_cast<std::size_t>(y0) * w + x0] = 1.0f + ch;  // (1, 2, 3)
  }
  std::vector<Rgbf> out(source[0].size(), Rgbf::Zero());
  add_forward_scatter(kernel, w, h, source, out);
  return out;
}

TEST(ForwardScatterTest, PixelKernelKeepsTheEnergyAndTheEncircledEnergy) {
  const double f = 400.0;
  const ForwardScatterPsf psf(0.924, 10.0 * kDegToRad);  // reaches 70 px
  const ForwardScatterKernel kernel = make_forward_scatter_kernel(psf, f, f);
  double total = 0.0;
  for (const auto& level : kernel.levels) {
    for (double w : level.weight) {
      ASSERT_GE(w, 0.0);
      total += w;
    }
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  // A pixel well inside the image, at several positions relative to the blocks.
  for (const auto& [x0, y0] : std::vector<std::pair<int, int>>{{320, 240}, {301, 257}, {333, 222}}) {
    const std::vector<Rgbf> out = spread_of_one_pixel(kernel, x0, y0);
    Rgb sum = Rgb::Zero();
    for (const Rgbf& v : out) sum += v.cast<double>();
    // Float planes: the sum is exact to ~1e-6.
    EXPECT_TRUE(((sum - Rgb(1.0, 2.0, 3.0)).abs() < 1e-5).all()) << sum.transpose();
    // Encircled energy at radius r against the PSF's: the blocks of the ring holding r (r < 6 px on
    // 2 px blocks, then [1.5 s, 3 s) px on blocks of s) and their bilinear interpolation move its light
    // by a fraction of s, and the pixel grid counts whole pixels within r: measured within 0.033 of E
    // at these three places (0.013 at 3 px, 0.032 at 48 px, the tail pushed outwards); 0.035 allows
    // nothing more.
    for (double r : {3.0, 6.0, 12.0, 24.0, 48.0}) {
      double inside = 0.0;
      for (int y = 0; y < 480; ++y) {
        for (int x = 0; x < 640; ++x) {
          if (std::hypot(x - x0, y - y0) <= r) inside += out[static_cast<std::size_t>(y) * 640 + x][0];
        }
      }
      EXPECT_NEAR(inside, psf.encircled(r / f), 0.035) << r << " px from (" << x0 << ", " << y0 << ")";
    }
  }
}

// A pixel on the image's edge spreads its light into the image only: none wraps around to the
// opposite edge (the convolution reads zeros past a row's ends, not the neighbouring row), none is
// negative, and what stays inside is between half (a quarter in a corner) and all of it: the spread is
// symmetric about the pixel, and its part beyond the edge is lost.
TEST(ForwardScatterTest, LightAtAnEdgeStaysNearIt) {
  const ForwardScatterKernel kernel = make_forward_scatter_kernel(ForwardScatterPsf(0.924, 10.0 * kDegToRad), 400.0, 400.0);
  for (const auto& [x0, y0] : std::vector<std::pair<int, int>>{{0, 240}, {639, 240}, {320, 0}, {320, 479}, {639, 479}}) {
    const std::vector<Rgbf> out = spread_of_one_pixel(kernel, x0, y0);
    double inside = 0.0, far = 0.0;
    for (int y = 0; y < 480; ++y) {
      for (int x = 0; x < 640; ++x) {
        const double v = out[static_cast<std::size_t>(y) * 640 + x][0];
        ASSERT_GE(v, 0.0) << "(" << x << ", " << y << ") from (" << x0 << ", " << y0 << ")";
        inside += v;
        // The spread reaches 70 px, its coarsest blocks (32 px) and their interpolation another 64.
        if (std::abs(x - x0) > 200 || std::abs(y - y0) > 200) far += std::abs(v);
      }
    }
    EXPECT_EQ(far, 0.0) << "light from (" << x0 << ", " << y0 << ") far from it";
    const bool corner = (x0 == 0 || x0 == 639) && (y0 == 0 || y0 == 479);
    EXPECT_GT(inside, corner ? 0.25 : 0.5) << x0 << ", " << y0;
    EXPECT_LE(inside, 1.0 + 1e-5) << x0 << ", " << y0;
  }
}

// A white plate 3 m ahead on a black background, lit by a light at the camera: with forward scatter on,
// the frame gains a halo around the plate (and over it) that carries the plate's unscattered light
// times exp(b_f d) - 1, d each pixel's distance: all of it lands inside the image (the spread reaches
// ~50 px, the plate's edge is ~70 px from the image's). Within 1e-3: float planes and exp3.
TEST(ForwardScatterTest, FrameHaloCarriesTheScatteredShare) {
  // Coloured scattering, then grey (render_band's shared exponential).
  for (const Rgb& scattering : {Rgb(0.1, 0.2, 0.4), Rgb(0.2, 0.2, 0.2)}) {
    const Lens lens = make_lens(lens_from_horizontal_fov(320, 240, 50.0 * kDegToRad));
    geometry::EmbreeScene scene;
    scene.add_static_mesh(testing::plate(3.0f, 0.0f, 0.0f, 0.15f), 0, "plate");
    scene.build();
    FrameLighting lighting;
    lighting.water.absorption_per_m = Rgb(0.3, 0.06, 0.03);
    lighting.water.scattering_per_m = scattering;
    lighting.lights = {SpotLight{}};
    lighting.lights[0].inner_half_angle_rad = 1.0;
    lighting.lights[0].outer_half_angle_rad = 1.2;
    const auto white = [](const SurfacePoint&) { return Rgb::Ones(); };
    const auto render = [&](const FrameLighting& l) {
      return render_radiance(scene, lens, X_SC(), 0.1f, 20.0f, geometry::kNoHit, l, white);
    };
    // The surface term alone: the same attenuation c, none of it scattering (no backscatter).
    FrameLighting clear = lighting;
    clear.water.absorption_per_m = lighting.water.attenuation_per_m();
    clear.water.scattering_per_m = Rgb::Zero();
    const RadianceFrame surface = render(clear);
    const RadianceFrame plain = render(lighting);
    lighting.water.forward_scatter_max_angle_rad = 8.0 * kDegToRad;
    const RadianceFrame blurred = render(lighting);
    const Rgb b_f = forward_scattering_per_m(lighting.water);
    ASSERT_TRUE((b_f > 0.0).all());
    Rgb halo = Rgb::Zero(), expected = Rgb::Zero();
    std::size_t outside_lit = 0;
    for (std::size_t i = 0; i < plain.radiance.size(); ++i) {
      halo += (blurred.radiance[i] - plain.radiance[i]).cast<double>();
      if (std::isnan(plain.depth_m[i])) {
        if ((blurred.radiance[i] > plain.radiance[i]).all()) ++outside_lit;
        continue;
      }
      const int u = static_cast<int>(i % lens.width_px()), v = static_cast<int>(i / lens.width_px());
      const double d = plain.depth_m[i] / lens.ray_C(u, v).z();
      expected += surface.radiance[i].cast<double>() * ((b_f * d).exp() - 1.0);
    }
    EXPECT_TRUE(((halo - expected).abs() < 1e-3 * expected).all()) << halo.transpose() << " vs " << expected.transpose();
    EXPECT_GT(outside_lit, 1000u);  // the halo reaches past the plate's edge
  }
}

}  // namespace
}  // namespace hadal::render
