// Overlapping Allan deviation of a uniformly sampled rate signal (IEEE Std 952 / 1554; Riley, "Handbook
// of Frequency Stability Analysis", NIST SP 1065, eq. 11), used to check the noise models against
// datasheet figures (noise.h) and by the validation tools.
//
// For samples y_0 .. y_{N-1} (a rate: gyro [rad/s], accelerometer [m/s^2], ...) at period tau_0, and a
// cluster of m samples (tau = m tau_0), with the cumulative sums S_0 = 0, S_k = sum_{i<k} (y_i - mean(y)):
//   sigma^2(tau) = sum_{k=0}^{N-2m} (S_{k+2m} - 2 S_{k+m} + S_k)^2 / (2 m^2 (N - 2m + 1)),
// i.e. half the mean square difference of adjacent cluster averages, taken at every start sample (fully
// overlapping). O(N) per tau. Subtracting the mean changes nothing mathematically and keeps the sums
// small. Units: those of y.
//
// Readouts (IEEE 952 asymptotes): white rate noise N gives N / sqrt(tau) (so sigma(1 s) = N), rate random
// walk K gives K sqrt(tau / 3) (slope +1/2), bias instability B a floor of about 0.664 B.
// Statistics: with M = N / m independent clusters the relative std of sigma(tau) is about
// 1 / sqrt(2 (M - 1)) for white noise (the overlapping estimator is somewhat better).
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

namespace hadal::sensors {

struct AllanPoint {
  double tau_s = 0.0;             // m tau_0 [s]
  double deviation = 0.0;         // sigma(tau) [unit of y]
  std::size_t cluster_size = 0;   // m
  std::size_t term_count = 0;     // N - 2m + 1 overlapping differences averaged
};

// Cluster sizes 1 .. max_cluster_size, about points_per_decade per decade (round(10^(i / ppd)), duplicates
// removed). max_cluster_size 0 means sample_count / 10 (at least ten non-overlapping clusters).
std::vector<std::size_t> log_spaced_cluster_sizes(std::size_t sample_count, int points_per_decade = 10,
                                                  std::size_t max_cluster_size = 0);

// sigma(tau) at each cluster size (m >= 1, 2m <= N; others are skipped), in the order given.
std::vector<AllanPoint> overlapping_allan_deviation(const double* samples, std::size_t count, double sample_period_s,
                                                    const std::vector<std::size_t>& cluster_sizes);
std::vector<AllanPoint> overlapping_allan_deviation(const std::vector<double>& samples, double sample_period_s,
                                                    const std::vector<std::size_t>& cluster_sizes);
// At log_spaced_cluster_sizes(samples.size()).
std::vector<AllanPoint> overlapping_allan_deviation(const std::vector<double>& samples, double sample_period_s);

// Readouts from a curve sorted by tau. sigma at tau by linear interpolation in log-log (NaN outside the
// curve); the point of smallest deviation with tau in [tau_min_s, tau_max_s] (the bias-instability floor;
// term_count 0 if none); the log-log slope d ln(sigma) / d ln(tau) between two interpolated taus.
double allan_deviation_at(const std::vector<AllanPoint>& curve, double tau_s);
AllanPoint allan_minimum(const std::vector<AllanPoint>& curve, double tau_min_s = 0.0,
                         double tau_max_s = std::numeric_limits<double>::infinity());
double allan_slope(const std::vector<AllanPoint>& curve, double tau1_s, double tau2_s);

// The three figures a datasheet comparison needs: sigma(1 s) (= N for white rate noise), the floor, and
// the slope over the decade above the floor (+1/2 where rate random walk dominates).
struct AllanReadout {
  double deviation_at_1s = 0.0;
  AllanPoint floor;
  double slope_after_floor = 0.0;  // between floor.tau_s and 10 floor.tau_s; NaN past the curve's end
};
AllanReadout read_allan(const std::vector<AllanPoint>& curve);

// IEEE 952 least-squares fit of the three terms a datasheet quotes,
//   sigma^2(tau) = N^2 / tau + (0.664 B)^2 + K^2 tau / 3,
// linear in (N^2, (0.664 B)^2, K^2 / 3). Each point is weighted by its number of independent clusters
// over the model's sigma^4 (the variance of an Allan variance estimate is about 2 sigma^4 / edf),
// iterated three times from the measured values; the coefficients are kept non-negative by solving every
// subset of the three terms and keeping the feasible one of least weighted residual. Reads B even where
// white noise still hides the floor inside the record (the minimum does not). Curves with fewer than
// three points return zeros.
struct AllanFit {
  double white_noise_density = 0.0;       // N [u/sqrt(Hz)]
  double bias_instability = 0.0;          // B [u]
  double rate_random_walk_density = 0.0;  // K [u/s/sqrt(Hz)]
};
AllanFit fit_allan_terms(const std::vector<AllanPoint>& curve);

}  // namespace hadal::sensors
