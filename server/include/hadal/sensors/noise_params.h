// The parameters of a noise channel (sensors/noise.h models it, with the processes, their state and the
// data-sheet conversions): what a sensor's spec holds. SI; u is the channel's unit.
#pragma once

#include <Eigen/Core>

#include <array>
#include <limits>
#include <vector>

namespace hadal::sensors {

// First-order Gauss-Markov process: stationary std sigma [u], correlation time tau_c [s] (> 0, may be inf).
struct GaussMarkovParams {
  double sigma = 0.0;
  double correlation_time_s = std::numeric_limits<double>::infinity();

  friend bool operator==(const GaussMarkovParams& a, const GaussMarkovParams& b) {
    return a.sigma == b.sigma && a.correlation_time_s == b.correlation_time_s;
  }
};
// Most Gauss-Markov terms one axis sums (a bias-instability bank over seven decades needs ten).
inline constexpr int kMaxGaussMarkovTerms = 10;

// Stochastic errors of one axis (u = the channel's unit). YAML keys belong to the sensor that embeds
// this (and take datasheet units there); here everything is SI.
struct AxisNoiseParams {
  double white_noise_density = 0.0;       // N [u/sqrt(Hz)]; 0 = off
  double bias_random_walk_density = 0.0;  // K [u/s/sqrt(Hz)]; 0 = off
  std::vector<GaussMarkovParams> gauss_markov;  // summed, at most kMaxGaussMarkovTerms; sigma 0 = off
  double turn_on_bias = 0.0;                    // fixed part of b0 [u]
  double turn_on_bias_sigma = 0.0;              // 1-sigma of the drawn part of b0 [u]
};

// A scalar channel (pressure, altimeter range, one DVL beam, ...).
struct NoiseChannelParams {
  AxisNoiseParams noise;
  double scale_factor = 0.0;        // s: x_s = (1 + s) x [-]
  double scale_factor_sigma = 0.0;  // 1-sigma of a drawn addition to s [-]
  double lsb = 0.0;                 // quantization step [u]; 0 = off
  double min = -std::numeric_limits<double>::infinity();  // range [u]
  double max = std::numeric_limits<double>::infinity();
};

// A three-axis channel (gyro, accelerometer, magnetometer, DVL velocity).
struct NoiseTriadParams {
  std::array<AxisNoiseParams, 3> axes;
  Eigen::Matrix3d misalignment = Eigen::Matrix3d::Identity();  // M [-]
  double misalignment_sigma = 0.0;  // 1-sigma [rad] of drawn additions to the off-diagonal entries of M
  Eigen::Vector3d scale_factor = Eigen::Vector3d::Zero();  // s per axis [-]
  double scale_factor_sigma = 0.0;                         // 1-sigma of drawn additions to s [-]
  double lsb = 0.0;                                        // [u], every axis; 0 = off
  double min = -std::numeric_limits<double>::infinity();   // range [u], every axis
  double max = std::numeric_limits<double>::infinity();
};

}  // namespace hadal::sensors
