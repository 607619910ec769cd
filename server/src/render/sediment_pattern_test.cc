// The sediment pattern: in range, mean-preserving, textured at the configured scale, seeded.
#include "hadal/render/sediment_pattern.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace hadal::render {
namespace {

// Correlation of the noise with itself shifted by `lag` along x, over a 200 x 200 grid of points 0.37 m apart.
double autocorrelation(const SedimentPattern& p, double lag) {
  std::vector<double> a, b;
  for (int i = 0; i < 200; ++i) {
    for (int j = 0; j < 200; ++j) {
      a.push_back(sediment_noise(p, 0.37 * i, 0.37 * j));
      b.push_back(sediment_noise(p, 0.37 * i + lag, 0.37 * j));
    }
  }
  double ma = 0, mb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) ma += a[k], mb += b[k];
  ma /= a.size();
  mb /= b.size();
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    sab += (a[k] - ma) * (b[k] - mb);
    saa += (a[k] - ma) * (a[k] - ma);
    sbb += (b[k] - mb) * (b[k] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

TEST(SedimentPatternTest, AlbedoStaysInRangeAndKeepsTheMean) {
  SedimentPattern p;
  p.amplitude = 0.4;
  p.scale_m = 1.0;
  p.octaves = 4;
  p.seed = 42;
  const Eigen::Array3d mean(0.30, 0.28, 0.22);
  double sum = 0.0, sum2 = 0.0;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Eigen::Array3d a = sediment_albedo(p, mean, 0.31 * i - 40.0, 0.29 * j + 7.0);
      ASSERT_TRUE((a >= 0.0).all() && (a <= 1.0).all());
      ASSERT_NEAR(a[1] / a[0], mean[1] / mean[0], 1e-12);  // one factor for every channel
      const double f = a[0] / mean[0];
      ASSERT_GE(f, 1.0 - p.amplitude - 1e-12);
      ASSERT_LE(f, 1.0 + p.amplitude + 1e-12);
      sum += f;
      sum2 += f * f;
    }
  }
  const double m = sum / (n * n), sd = std::sqrt(sum2 / (n * n) - m * m);
  // The lattice values are uniform with mean 1/2: over ~8 000 unit cells the factor's mean is 1 within
  // ~0.4 (amplitude x 2) x 0.29 / sqrt(8000) x a few; 2 % is > 5 of those standard errors.
  EXPECT_NEAR(m, 1.0, 0.02);
  EXPECT_GT(sd, 0.05);  // visible texture
  p.amplitude = 0.0;
  EXPECT_TRUE((sediment_albedo(p, mean, 3.0, 4.0) == mean).all());
}

// One octave: neighbours 5 % of the scale apart are nearly the same, points 3 scales apart unrelated.
TEST(SedimentPatternTest, TextureHasTheConfiguredScale) {
  SedimentPattern p;
  p.amplitude = 0.3;
  p.scale_m = 2.0;
  p.octaves = 1;
  p.seed = 7;
  EXPECT_GT(autocorrelation(p, 0.1), 0.9);
  EXPECT_LT(std::abs(autocorrelation(p, 6.0)), 0.1);
  p.scale_m = 0.2;  // the same lag is now many patches
  EXPECT_LT(autocorrelation(p, 0.1), 0.9);
}

TEST(SedimentPatternTest, SeededAndValidated) {
  SedimentPattern a;
  a.amplitude = 0.3;
  a.seed = 1;
  SedimentPattern b = a;
  EXPECT_EQ(sediment_noise(a, 1.234, -5.678), sediment_noise(b, 1.234, -5.678));
  b.seed = 2;
  EXPECT_NE(sediment_noise(a, 1.234, -5.678), sediment_noise(b, 1.234, -5.678));
  for (double x : {-1e4, -3.3, 0.0, 0.5, 2e4}) {
    const double v = sediment_noise(a, x, 0.7 * x);
    EXPECT_GE(v, 0.0);
    EXPECT_LT(v, 1.0);
  }
  SedimentPattern bad;
  bad.amplitude = 1.5;
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad.amplitude = 0.5;
  bad.scale_m = 0.0;
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad.scale_m = 1.0;
  bad.octaves = 9;
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad.octaves = 3;
  EXPECT_NO_THROW(validate(bad));
}

// The batch form (a camera band's seabed) gives the per-point albedo to single precision, whatever the
// batch's origin: points far from the world origin, on both sides of cell edges, and kilometres out.
TEST(SedimentPatternTest, BatchAgreesWithPerPoint) {
  SedimentPattern p;
  p.amplitude = 0.6;
  p.scale_m = 1.0;
  p.octaves = 5;
  p.seed = 42;
  const Eigen::Array3d mean(0.30, 0.28, 0.22);
  for (const Eigen::Vector2d& origin : {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(-37.25, 12.5),
                                        Eigen::Vector2d(4321.7, -2718.3)}) {
    std::vector<float> x, y;
    for (int k = 0; k < 1000; ++k) {
      x.push_back(0.0137f * k - 7.0f);
      y.push_back(0.0071f * k + 2.0f * std::sin(0.1f * k));
    }
    std::vector<float> r(x.size()), g(x.size()), b(x.size());
    sediment_albedo(p, mean, origin, x.data(), y.data(), x.size(), r.data(), g.data(), b.data());
    for (std::size_t k = 0; k < x.size(); ++k) {
      const Eigen::Array3d single = sediment_albedo(p, mean, origin.x() + x[k], origin.y() + y[k]);
      // The batch's offsets are floats: a point moves by up to ~1e-6 of its distance from the origin,
      // ~1e-4 lattice cells of the finest octave here; the value changes by less than 1e-4.
      ASSERT_NEAR(r[k], single[0], 1e-4) << k;
      ASSERT_NEAR(g[k], single[1], 1e-4) << k;
      ASSERT_NEAR(b[k], single[2], 1e-4) << k;
    }
  }
}

}  // namespace
}  // namespace hadal::render
