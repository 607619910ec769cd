#include "hadal/sensors/allan.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

#include "hadal/sensors/noise.h"

namespace hadal::sensors {

std::vector<std::size_t> log_spaced_cluster_sizes(std::size_t sample_count, int points_per_decade,
                                                  std::size_t max_cluster_size) {
  if (max_cluster_size == 0) max_cluster_size = sample_count / 10;
  max_cluster_size = std::min(max_cluster_size, sample_count / 2);
  std::vector<std::size_t> sizes;
  const int per_decade = std::max(points_per_decade, 1);
  for (int i = 0;; ++i) {
    const double m = std::round(std::pow(10.0, static_cast<double>(i) / per_decade));
    if (m > static_cast<double>(max_cluster_size)) break;
    const auto size = static_cast<std::size_t>(m);
    if (sizes.empty() || size != sizes.back()) sizes.push_back(size);
  }
  return sizes;
}

std::vector<AllanPoint> overlapping_allan_deviation(const double* samples, std::size_t count, double sample_period_s,
                                                    const std::vector<std::size_t>& cluster_sizes) {
  std::vector<AllanPoint> curve;
  if (count < 2) return curve;
  double mean = 0.0;
  for (std::size_t i = 0; i < count; ++i) mean += samples[i];
  mean /= static_cast<double>(count);
  std::vector<double> sums(count + 1);
  sums[0] = 0.0;
  for (std::size_t i = 0; i < count; ++i) sums[i + 1] = sums[i] + (samples[i] - mean);
  for (const std::size_t m : cluster_sizes) {
    if (m == 0 || 2 * m > count) continue;
    const std::size_t terms = count - 2 * m + 1;
    double total = 0.0;
    for (std::size_t k = 0; k < terms; ++k) {
      const double d = sums[k + 2 * m] - 2.0 * sums[k + m] + sums[k];
      total += d * d;
    }
    const double md = static_cast<double>(m);
    AllanPoint point;
    point.tau_s = md * sample_period_s;
    point.deviation = std::sqrt(total / (2.0 * md * md * static_cast<double>(terms)));
    point.cluster_size = m;
    point.term_count = terms;
    curve.push_back(point);
  }
  return curve;
}

std::vector<AllanPoint> overlapping_allan_deviation(const std::vector<double>& samples, double sample_period_s,
                                                    const std::vector<std::size_t>& cluster_sizes) {
  return overlapping_allan_deviation(samples.data(), samples.size(), sample_period_s, cluster_sizes);
}

std::vector<AllanPoint> overlapping_allan_deviation(const std::vector<double>& samples, double sample_period_s) {
  return overlapping_allan_deviation(samples, sample_period_s, log_spaced_cluster_sizes(samples.size()));
}

double allan_deviation_at(const std::vector<AllanPoint>& curve, double tau_s) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (curve.empty() || !(tau_s >= curve.front().tau_s) || !(tau_s <= curve.back().tau_s)) return nan;
  const auto upper = std::lower_bound(curve.begin(), curve.end(), tau_s,
                                      [](const AllanPoint& p, double t) { return p.tau_s < t; });
  if (upper->tau_s == tau_s) return upper->deviation;
  const AllanPoint& b = *upper;
  const AllanPoint& a = *(upper - 1);
  const double u = std::log(tau_s / a.tau_s) / std::log(b.tau_s / a.tau_s);
  return std::exp((1.0 - u) * std::log(a.deviation) + u * std::log(b.deviation));
}

AllanPoint allan_minimum(const std::vector<AllanPoint>& curve, double tau_min_s, double tau_max_s) {
  AllanPoint best;
  best.deviation = std::numeric_limits<double>::infinity();
  for (const AllanPoint& p : curve) {
    if (p.tau_s >= tau_min_s && p.tau_s <= tau_max_s && p.deviation < best.deviation) best = p;
  }
  return best;
}

double allan_slope(const std::vector<AllanPoint>& curve, double tau1_s, double tau2_s) {
  return std::log(allan_deviation_at(curve, tau2_s) / allan_deviation_at(curve, tau1_s)) / std::log(tau2_s / tau1_s);
}

AllanReadout read_allan(const std::vector<AllanPoint>& curve) {
  AllanReadout readout;
  readout.deviation_at_1s = allan_deviation_at(curve, 1.0);
  readout.floor = allan_minimum(curve);
  readout.slope_after_floor = allan_slope(curve, readout.floor.tau_s, 10.0 * readout.floor.tau_s);
  return readout;
}

AllanFit fit_allan_terms(const std::vector<AllanPoint>& curve) {
  AllanFit fit;
  std::vector<const AllanPoint*> points;
  for (const AllanPoint& p : curve) {
    if (p.term_count > 0 && p.cluster_size > 0 && p.deviation > 0.0 && p.tau_s > 0.0) points.push_back(&p);
  }
  if (points.size() < 3) return fit;
  // Basis 1 / tau, 1, tau / 3 for the coefficients N^2, (0.664 B)^2, K^2.
  auto basis = [](double tau) { return Eigen::Vector3d(1.0 / tau, 1.0, tau / 3.0); };
  std::vector<double> model(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) model[i] = points[i]->deviation * points[i]->deviation;
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  for (int iteration = 0; iteration < 3; ++iteration) {
    std::vector<double> weights(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double m = static_cast<double>(points[i]->cluster_size);
      const double samples = static_cast<double>(points[i]->term_count) + 2.0 * m - 1.0;
      weights[i] = (samples / m) / (model[i] * model[i]);
    }
    double best_residual = std::numeric_limits<double>::infinity();
    for (int subset = 1; subset < 8; ++subset) {  // bit j set: term j is free, else fixed at 0
      Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
      Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d phi = basis(points[i]->tau_s);
        const double y = points[i]->deviation * points[i]->deviation;
        normal += weights[i] * phi * phi.transpose();
        rhs += weights[i] * y * phi;
      }
      for (int j = 0; j < 3; ++j) {
        if ((subset >> j & 1) == 0) {
          normal.row(j).setZero();
          normal.col(j).setZero();
          normal(j, j) = 1.0;
          rhs[j] = 0.0;
        }
      }
      // Scale to unit diagonal: 1 / tau and tau span many decades.
      const Eigen::Vector3d scale = normal.diagonal().cwiseSqrt().cwiseInverse();
      const Eigen::Matrix3d scaled = scale.asDiagonal() * normal * scale.asDiagonal();
      const Eigen::Vector3d coefficients = scale.cwiseProduct(scaled.ldlt().solve(scale.cwiseProduct(rhs)));
      if (!coefficients.allFinite() || (coefficients.array() < 0.0).any()) continue;
      double residual = 0.0;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const double r = points[i]->deviation * points[i]->deviation - basis(points[i]->tau_s).dot(coefficients);
        residual += weights[i] * r * r;
      }
      if (residual < best_residual) {
        best_residual = residual;
        best = coefficients;
      }
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
      model[i] = std::max(basis(points[i]->tau_s).dot(best), 1e-300);
    }
  }
  fit.white_noise_density = std::sqrt(best[0]);
  fit.bias_instability = std::sqrt(best[1]) / kBiasInstabilityAllanFactor;
  fit.rate_random_walk_density = std::sqrt(best[2]);
  return fit;
}

}  // namespace hadal::sensors
