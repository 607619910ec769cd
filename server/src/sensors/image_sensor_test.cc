// The image sensor model against its closed forms: the noise-free response, the photon-transfer
// variance, exact Poisson statistics in low light, full-well and 8-bit saturation, vignetting, black at
// depth, and seeded repeatability.
#include "hadal/sensors/image_sensor.h"

#include <gtest/gtest.h>

#include <functional>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace hadal::sensors {
namespace {

std::vector<Eigen::Array3f> uniform(std::size_t n, double L) {
  return std::vector<Eigen::Array3f>(n, Eigen::Array3f::Constant(static_cast<float>(L)));
}
std::vector<float> on_axis(std::size_t n) { return std::vector<float>(n, 1.0f); }

ImageSensorSpec noiseless() {
  ImageSensorSpec spec;
  spec.shot_noise = false;
  spec.read_noise_e = 0.0;
  return spec;
}

struct Moments {
  double mean = 0.0, variance = 0.0;
};
Moments moments(const std::vector<std::uint8_t>& dn) {
  Moments m;
  for (std::uint8_t x : dn) m.mean += x;
  m.mean /= dn.size();
  for (std::uint8_t x : dn) m.variance += (x - m.mean) * (x - m.mean);
  m.variance /= dn.size() - 1;
  return m;
}

// Counts that need rounding: L = 1.2371 W/(m^2 sr) gives 1237.1, 2474.2, 3711.3 electrons in 10 ms, 61.855,
// 123.71, 185.565 DN at 0.05 DN/e: rounded 62, 124, 186 (truncated they would be 61, 123, 185); all three
// below the 8-bit clip, each channel its own sensitivity. Then L = 2.0: 100, 200 and 300 DN, the last
// clipped at 255 (the spec's gain and exposure checked first: the figures depend on them).
TEST(ImageSensorTest, NoiselessResponseIsLinearThenRounded) {
  ImageSensorSpec spec = noiseless();
  ASSERT_EQ(spec.gain_dn_per_e, 0.05);
  ASSERT_EQ(spec.exposure_s, 0.01);
  spec.sensitivity = Eigen::Array3d(1.0e5, 2.0e5, 3.0e5);
  const auto rgb = expose_rgb8(spec, uniform(4, 1.2371), on_axis(4), 1, 0);
  const std::uint8_t rounded[3] = {62, 124, 186};
  for (std::size_t i = 0; i < rgb.size(); ++i) EXPECT_EQ(rgb[i], rounded[i % 3]) << i;
  const auto bright = expose_rgb8(spec, uniform(1, 2.0), on_axis(1), 1, 0);
  EXPECT_EQ(bright[0], 100);
  EXPECT_EQ(bright[1], 200);
  EXPECT_EQ(bright[2], 255);
}

// negligible_radiance(spec, counts) is the radiance worth `counts` on the axis: noise off, raising a
// pixel's radiance by negligible_radiance(spec, 1) raises its count by exactly one in every channel
// (means at 40.25 and 41.25 counts, away from rounding's half), and a twentieth of a count's worth
// (kNegligibleCounts) moves the mean by 0.05 counts: 40.25 -> 40.30, the same rounded count.
TEST(ImageSensorTest, NegligibleRadianceIsTheRadianceOfThatManyCounts) {
  ImageSensorSpec spec = noiseless();
  spec.sensitivity = Eigen::Array3d(1.0e5, 2.0e5, 3.0e5);
  spec.vignetting = false;
  const Eigen::Array3d one_count = negligible_radiance(spec, 1.0);
  EXPECT_TRUE(((negligible_radiance(spec) / one_count - kNegligibleCounts).abs() < 1e-15).all());
  std::vector<Eigen::Array3f> radiance(3);
  radiance[0] = (40.25 * one_count).cast<float>();
  radiance[1] = (41.25 * one_count).cast<float>();
  radiance[2] = (40.25 * one_count + negligible_radiance(spec)).cast<float>();
  const auto rgb = expose_rgb8(spec, radiance, on_axis(3), 1, 0);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_EQ(rgb[ch], 40) << ch;
    EXPECT_EQ(rgb[3 + ch], 41) << ch;
    EXPECT_EQ(rgb[6 + ch], 40) << ch;
  }
  spec.exposure_s = 0.0;
  EXPECT_THROW(negligible_radiance(spec), std::invalid_argument);
}

// Photon transfer: var(DN) = K^2 (mu + sigma_r^2) + 1/12 (quantisation), mean K mu. 120 000 samples:
// the variance's relative standard error is sqrt(2/N) = 0.4 %, the tolerance 3 % (7 sigma). Both ways
// the sensor draws it: one merged normal (full well far above) and shot then read noise apart (full well
// 5.9 sigma above mu, inside the 6 sigma that merging needs, yet practically never reached).
TEST(ImageSensorTest, VarianceFollowsThePhotonTransferCurve) {
  const double mu = 1000.0;
  for (const double full_well : {10000.0, mu + 5.9 * std::sqrt(mu)}) {
    ImageSensorSpec spec;  // gain 0.05 DN/e-, read noise 3 e-
    spec.full_well_e = full_well;
    const double L = mu / (spec.sensitivity[0] * spec.exposure_s);
    const auto rgb = expose_rgb8(spec, uniform(40000, L), on_axis(40000), 7, 3);
    const Moments m = moments(rgb);
    const double K = spec.gain_dn_per_e;
    EXPECT_NEAR(m.mean, K * mu, 0.02) << full_well;
    const double expected = K * K * (mu + spec.read_noise_e * spec.read_noise_e) + 1.0 / 12.0;
    EXPECT_NEAR(m.variance / expected, 1.0, 0.03) << full_well;
  }
}

// Low light, one count per electron, no read noise: the counts are Poisson(mu), drawn by inversion.
// mu = 2: mean and variance 2, P(0) = exp(-2) = 0.1353; mu = 17: mean and variance 17, P(K <= 12) =
// 0.1270. 120 000 samples: standard errors 0.004, 0.008, 0.001 and 0.012, 0.07, 0.001; tolerances
// about five of them.
TEST(ImageSensorTest, LowLightCountsArePoisson) {
  for (const double mu : {2.0, 17.0}) {
    SCOPED_TRACE(mu);
    ImageSensorSpec spec;
    spec.gain_dn_per_e = 1.0;
    spec.read_noise_e = 0.0;
    const double L = mu / (spec.sensitivity[0] * spec.exposure_s);
    const auto rgb = expose_rgb8(spec, uniform(40000, L), on_axis(40000), 11, 0);
    const Moments m = moments(rgb);
    EXPECT_NEAR(m.mean, mu, 5.0 * std::sqrt(mu / 120000.0));
    EXPECT_NEAR(m.variance, mu, 5.0 * mu * std::sqrt(2.0 / 120000.0));
    const int k_max = mu < 5.0 ? 0 : 12;
    double cdf = 0.0, term = std::exp(-mu);
    for (int k = 0; k <= k_max; ++k) {
      cdf += term;
      term *= mu / (k + 1);
    }
    const double below = static_cast<double>(std::count_if(rgb.begin(), rgb.end(), [&](std::uint8_t x) { return x <= k_max; })) / rgb.size();
    EXPECT_NEAR(below, cdf, 0.005);
  }
}

// Read noise alone (no shot noise): the counts are the rounded normal of mean 120 DN and 20 DN rms
// that the counter-based Box-Muller draws give (header). Chi-square of the 121 counts within 3 sigma
// plus the two tails against the normal's bin probabilities (122 degrees of freedom: 0.1 % critical
// value 173); neighbouring samples (a pixel's R and G, a pixel and the next) uncorrelated within
// 4 / sqrt(N) (4 sigma of a sample correlation).
TEST(ImageSensorTest, ReadNoiseIsNormalAndUncorrelated) {
  ImageSensorSpec spec;
  spec.shot_noise = false;
  spec.read_noise_e = 200.0;
  spec.gain_dn_per_e = 0.1;  // 20 DN rms
  const double mean = 120.0, sd = 20.0;
  const double L = (mean / spec.gain_dn_per_e) / (spec.sensitivity[0] * spec.exposure_s);
  const std::size_t pixels = 100000;
  const auto rgb = expose_rgb8(spec, uniform(pixels, L), on_axis(pixels), 21, 4);
  const auto cdf = [&](double x) { return 0.5 * std::erfc(-(x - mean) / (sd * std::sqrt(2.0))); };
  std::vector<double> observed(123, 0.0), expected(123, 0.0);  // [0]: below 60, [1..121]: 60..180, [122]: above
  const auto bin = [](int dn) { return dn < 60 ? 0 : dn > 180 ? 122 : dn - 59; };
  for (std::uint8_t x : rgb) observed[static_cast<std::size_t>(bin(x))] += 1.0;
  const double n = static_cast<double>(rgb.size());
  expected[0] = n * cdf(59.5);
  expected[122] = n * (1.0 - cdf(180.5));
  for (int dn = 60; dn <= 180; ++dn) expected[static_cast<std::size_t>(bin(dn))] = n * (cdf(dn + 0.5) - cdf(dn - 0.5));
  double chi2 = 0.0;
  for (std::size_t k = 0; k < observed.size(); ++k) chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
  EXPECT_LT(chi2, 173.0);
  const auto correlation = [&](std::size_t offset, std::size_t stride) {
    double sa = 0, sb = 0, sab = 0, saa = 0, sbb = 0, count = 0;
    for (std::size_t i = 0; i + offset < rgb.size(); i += stride) {
      const double a = rgb[i] - mean, b = rgb[i + offset] - mean;
      sa += a, sb += b, sab += a * b, saa += a * a, sbb += b * b, count += 1;
    }
    return (sab - sa * sb / count) / std::sqrt((saa - sa * sa / count) * (sbb - sb * sb / count));
  };
  const double bound = 4.0 / std::sqrt(static_cast<double>(pixels));
  EXPECT_LT(std::abs(correlation(1, 3)), bound);  // R and G of a pixel
  EXPECT_LT(std::abs(correlation(3, 3)), bound);  // R of a pixel and of the next
  EXPECT_LT(std::abs(correlation(3 * 640, 3)), bound);  // the pixel below in a 640 px wide image
}

TEST(ImageSensorTest, FullWellAndEightBitsSaturate) {
  ImageSensorSpec spec = noiseless();
  const auto bright = expose_rgb8(spec, uniform(2, 1e6), on_axis(2), 1, 0);
  for (std::uint8_t x : bright) EXPECT_EQ(x, 255);  // 0.05 DN/e- * 10 000 e- = 500 > 255
  spec.gain_dn_per_e = 0.02;                        // full well = 200 DN
  for (std::uint8_t x : expose_rgb8(spec, uniform(2, 1e6), on_axis(2), 1, 0)) EXPECT_EQ(x, 200);
}

TEST(ImageSensorTest, VignettingFollowsCosineFourth) {
  const ImageSensorSpec spec = noiseless();
  const double L = 100.0 / (spec.gain_dn_per_e * spec.sensitivity[0] * spec.exposure_s);  // 100 DN on the axis
  const auto rgb = expose_rgb8(spec, uniform(2, L), {1.0f, 0.8f}, 1, 0);
  EXPECT_EQ(rgb[0], 100);
  EXPECT_EQ(rgb[3], std::lround(100.0 * std::pow(0.8, 4)));  // 41
}

// The deep sea without lights: radiance of order 1e-15 W/(m^2 sr) is 2e-12 electrons; only read noise
// (3 e- * 0.05 DN/e- = 0.15 DN rms) remains, which rounds to 0 except beyond 3.3 sigma.
TEST(ImageSensorTest, DarknessIsBlack) {
  const auto rgb = expose_rgb8(ImageSensorSpec{}, uniform(40000, 1e-15), on_axis(40000), 5, 0);
  const double zeros = static_cast<double>(std::count(rgb.begin(), rgb.end(), 0)) / rgb.size();
  EXPECT_GT(zeros, 0.998);
  EXPECT_LE(*std::max_element(rgb.begin(), rgb.end()), 1);
}

TEST(ImageSensorTest, SameSeedAndFrameGiveTheSameImage) {
  const ImageSensorSpec spec;
  const auto radiance = uniform(1000, 0.3);
  const auto a = expose_rgb8(spec, radiance, on_axis(1000), 42, 9);
  EXPECT_EQ(a, expose_rgb8(spec, radiance, on_axis(1000), 42, 9));
  EXPECT_NE(a, expose_rgb8(spec, radiance, on_axis(1000), 42, 10));
  EXPECT_NE(a, expose_rgb8(spec, radiance, on_axis(1000), 43, 9));
}

// Blocks of pixels draw from streams of their own: exposed in reverse block order (as threads might),
// a 3-block image is the same; its blocks are not copies of each other.
TEST(ImageSensorTest, BlocksGiveTheSameImageInAnyOrder) {
  const ImageSensorSpec spec;
  const std::size_t n = 3 * kExposureBlockPixels;
  const auto radiance = uniform(n, 0.3);
  const auto a = expose_rgb8(spec, radiance, on_axis(n), 42, 9);
  const auto b = expose_rgb8(spec, radiance, on_axis(n), 42, 9, [](std::size_t count, const std::function<void(std::size_t)>& task) {
    for (std::size_t i = count; i-- > 0;) task(i);
  });
  EXPECT_EQ(a, b);
  const std::size_t block_bytes = 3 * kExposureBlockPixels;
  EXPECT_FALSE(std::equal(a.begin(), a.begin() + block_bytes, a.begin() + block_bytes));
}

TEST(ImageSensorTest, InvalidSpecsAreRejected) {
  ImageSensorSpec spec;
  spec.exposure_s = 0.0;
  EXPECT_THROW(validate(spec), std::invalid_argument);
  spec = ImageSensorSpec{};
  spec.read_noise_e = -1.0;
  EXPECT_THROW(validate(spec), std::invalid_argument);
  spec = ImageSensorSpec{};
  spec.sensitivity[1] = 0.0;
  EXPECT_THROW(validate(spec), std::invalid_argument);
  EXPECT_THROW(expose_rgb8(ImageSensorSpec{}, uniform(2, 1.0), on_axis(3), 1, 0), std::invalid_argument);
}

}  // namespace
}  // namespace hadal::sensors
