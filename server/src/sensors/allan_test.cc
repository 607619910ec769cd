#include "hadal/sensors/allan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hadal/sensors/noise.h"

namespace hadal::sensors {
namespace {

// The textbook definition, O(N m): half the mean square difference of adjacent m-sample averages taken
// at every start sample.
double direct_allan_deviation(const std::vector<double>& y, std::size_t m) {
  const std::size_t n = y.size();
  std::vector<double> averages(n - m + 1);
  for (std::size_t k = 0; k + m <= n; ++k) {
    double sum = 0.0;
    for (std::size_t i = k; i < k + m; ++i) sum += y[i];
    averages[k] = sum / static_cast<double>(m);
  }
  double total = 0.0;
  const std::size_t terms = n - 2 * m + 1;
  for (std::size_t k = 0; k < terms; ++k) {
    const double d = averages[k + m] - averages[k];
    total += d * d;
  }
  return std::sqrt(total / (2.0 * static_cast<double>(terms)));
}

TEST(AllanTest, MatchesDirectDefinition) {
  RandomStream stream(5);
  std::vector<double> y(2000);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = 3.0 + stream.normal() + 1e-3 * static_cast<double>(i);
  const std::vector<std::size_t> sizes = {1, 2, 3, 7, 50, 333, 1000};
  const auto curve = overlapping_allan_deviation(y, 0.01, sizes);
  ASSERT_EQ(curve.size(), sizes.size());
  for (std::size_t j = 0; j < sizes.size(); ++j) {
    EXPECT_EQ(curve[j].cluster_size, sizes[j]);
    EXPECT_EQ(curve[j].term_count, y.size() - 2 * sizes[j] + 1);
    EXPECT_DOUBLE_EQ(curve[j].tau_s, 0.01 * static_cast<double>(sizes[j]));
    EXPECT_NEAR(curve[j].deviation / direct_allan_deviation(y, sizes[j]), 1.0, 1e-11) << "m " << sizes[j];
  }
}

// +1, -1, ...: adjacent single samples differ by 2, so sigma(1) = sqrt(4 / 2); pairs average to 0.
TEST(AllanTest, AlternatingSequenceExact) {
  std::vector<double> y(1000);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = i % 2 == 0 ? 1.0 : -1.0;
  const auto curve = overlapping_allan_deviation(y, 1.0, {1, 2});
  EXPECT_DOUBLE_EQ(curve[0].deviation, std::sqrt(2.0));
  EXPECT_EQ(curve[1].deviation, 0.0);
}

// A ramp y_i = a i: adjacent m-averages differ by a m, so sigma = a m / sqrt(2).
TEST(AllanTest, LinearRamp) {
  std::vector<double> y(1001);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = 0.5 * static_cast<double>(i);
  const auto curve = overlapping_allan_deviation(y, 0.1, {4, 100});
  EXPECT_NEAR(curve[0].deviation, 0.5 * 4.0 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(curve[1].deviation, 0.5 * 100.0 / std::sqrt(2.0), 1e-10);
}

TEST(AllanTest, SkipsImpossibleClusterSizes) {
  const std::vector<double> y(10, 1.0);
  const auto curve = overlapping_allan_deviation(y, 1.0, {0, 1, 5, 6});
  ASSERT_EQ(curve.size(), 2u);
  EXPECT_EQ(curve[0].cluster_size, 1u);
  EXPECT_EQ(curve[1].cluster_size, 5u);
  EXPECT_EQ(curve[1].term_count, 1u);
  EXPECT_TRUE(overlapping_allan_deviation(std::vector<double>{1.0}, 1.0, {1}).empty());
}

TEST(AllanTest, LogSpacedClusterSizes) {
  const std::vector<std::size_t> expected = {1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, 32, 40, 50, 63, 79, 100};
  EXPECT_EQ(log_spaced_cluster_sizes(1000), expected);  // default: m <= N / 10
  const auto sizes = log_spaced_cluster_sizes(100000, 3, 50000);
  EXPECT_EQ(sizes.front(), 1u);
  EXPECT_EQ(sizes.back(), 46416u);
  for (std::size_t i = 1; i < sizes.size(); ++i) EXPECT_LT(sizes[i - 1], sizes[i]);
  EXPECT_EQ(log_spaced_cluster_sizes(100, 10, 1000).back(), 50u);  // never past N / 2
}

// On an exact power law the log-log readouts are exact: sigma = 2 sqrt(tau) gives slope 1/2 everywhere
// and interpolates exactly between points.
TEST(AllanTest, ReadoutsOnPowerLaws) {
  std::vector<AllanPoint> curve;
  for (double tau : {0.1, 0.3, 1.0, 3.0, 10.0}) curve.push_back({tau, 2.0 * std::sqrt(tau), 1, 1});
  EXPECT_NEAR(allan_deviation_at(curve, 2.0), 2.0 * std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(allan_deviation_at(curve, 1.0), 2.0, 0.0);
  EXPECT_NEAR(allan_slope(curve, 0.2, 7.0), 0.5, 1e-13);
  EXPECT_TRUE(std::isnan(allan_deviation_at(curve, 0.05)));
  EXPECT_TRUE(std::isnan(allan_deviation_at(curve, 11.0)));

  // White (N = 1) plus random walk (K sqrt(tau / 3) with K^2 = 3e-2): sigma^2 = 1 / tau + tau / 100, minimum
  // at tau = 10 (sigma = sqrt(0.2)), where the slope over the next decade is the mixture's.
  std::vector<AllanPoint> v;
  for (int i = -20; i <= 30; ++i) {
    const double tau = std::pow(10.0, i / 10.0);
    v.push_back({tau, std::sqrt(1.0 / tau + tau / 100.0), 1, 1});
  }
  const AllanReadout readout = read_allan(v);
  EXPECT_NEAR(readout.deviation_at_1s, std::sqrt(1.01), 1e-15);
  EXPECT_NEAR(readout.floor.tau_s, 10.0, 1e-12);
  EXPECT_NEAR(readout.floor.deviation, std::sqrt(0.2), 1e-15);
  EXPECT_NEAR(readout.slope_after_floor, std::log(std::sqrt(1.01 / 0.2)) / std::log(10.0), 1e-12);
  EXPECT_NEAR(allan_minimum(v, 100.0, 1000.0).tau_s, 100.0, 1e-9);
  EXPECT_EQ(allan_minimum(v, 1e5, 1e6).term_count, 0u);
}

// An exact three-term curve is recovered exactly; a white-only curve gives B = K = 0 (no negative terms).
TEST(AllanTest, FitRecoversDatasheetTerms) {
  const double n = 2e-3;
  const double b = 3e-4;
  const double k = 1e-6;
  std::vector<AllanPoint> curve;
  for (int i = -20; i <= 40; ++i) {
    const double tau = std::pow(10.0, i / 10.0);
    const double floor = kBiasInstabilityAllanFactor * b;
    curve.push_back({tau, std::sqrt(n * n / tau + floor * floor + k * k * tau / 3.0), 1, 1000});
  }
  const AllanFit fit = fit_allan_terms(curve);
  EXPECT_NEAR(fit.white_noise_density / n, 1.0, 1e-9);
  EXPECT_NEAR(fit.bias_instability / b, 1.0, 1e-9);
  EXPECT_NEAR(fit.rate_random_walk_density / k, 1.0, 1e-9);

  for (AllanPoint& p : curve) p.deviation = n / std::sqrt(p.tau_s);
  const AllanFit white = fit_allan_terms(curve);
  EXPECT_NEAR(white.white_noise_density / n, 1.0, 1e-9);
  EXPECT_EQ(white.bias_instability, 0.0);
  EXPECT_EQ(white.rate_random_walk_density, 0.0);
  EXPECT_EQ(fit_allan_terms({}).white_noise_density, 0.0);
}

}  // namespace
}  // namespace hadal::sensors
