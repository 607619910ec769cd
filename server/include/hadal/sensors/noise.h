// Sensor noise, implemented once for every channel (docs/ARCHITECTURE.md, "Noise and random
// streams"). A sensor computes its ideal value, then a NoiseChannel (scalar) or a
// NoiseTriad (three axes) turns it into the measured value, following the paper's IMU chain:
//
//   x_s   = M (I + S) x_ideal                 misalignment M, scale-factor error S = diag(s)   [triad]
//   x_s   = (1 + s) x_ideal                                                                    [scalar]
//   x_m   = x_s + b0 + b_rw(t) + sum_j n_j(t) + n_w                  turn-on bias, random walk, GM, white
//   x_m  += sensor-specific terms (temperature drift (T - T_ref) k_T, vibration A sin(2 pi f t): caller)
//   out   = clip(quantize(x_m, lsb), min, max)
//
// Parameters (the model; loaded once) and state (turn-on draws, bias and Gauss-Markov values, generator
// states) are separate types; states are plain copyable values compared with ==, and live in SimState.
//
// Processes, with w ~ N(0, 1) drawn from the channel's own stream and dt the time since the previous
// sample [s] (dt > 0). Units: u is the channel's unit (rad/s for a gyro, m/s^2 for an accelerometer).
//   white noise      n_w = sigma w,  sigma = N sqrt(f_s) = N / sqrt(dt).  N [u/sqrt(Hz)] is the square root
//                    of the two-sided PSD (IEEE Std 952): the sample is the average over dt of continuous
//                    white noise, and the Allan deviation is N / sqrt(tau) at every tau >= dt.
//   bias rand. walk  b_rw <- b_rw + K sqrt(dt) w  (the paper's b(t+dt) = b + eta sqrt(dt), eta = K w).
//                    K [u/s/sqrt(Hz)] = [u s^-1/2]; b_rw(0) = 0; Allan deviation K sqrt(tau / 3).
//   Gauss-Markov     n <- phi n + sqrt(1 - phi^2) sigma w,  phi = exp(-dt / tau_c)  (the paper's form, exact
//                    discretisation of an Ornstein-Uhlenbeck process). Stationary std = sigma, started from
//                    n(0) ~ N(0, sigma^2) so it is stationary from the first sample; autocorrelation
//                    exp(-|t| / tau_c). tau_c = inf: a constant; tau_c -> 0: white with std sigma.
//                    sqrt(1 - phi^2) is evaluated as sqrt(-expm1(-2 dt / tau_c)) (no cancellation).
//   turn-on bias     b0 = fixed + sigma w, drawn once when the state is made.
//   quantization     x -> lsb * round(x / lsb), ties away from zero (std::round: independent of the FP
//                    rounding mode); lsb = 0 disables it.
//   clipping         x -> min(max(x, min), max) (saturation), applied after quantization.
// Each process steps first and is then read: the value returned for a sample includes the step over dt.
//
// Random streams. Each channel owns one key,
//   key = derive(derive(derive(scenario_seed, vehicle), sensor), channel),
//   derive(parent, name) = splitmix64(fnv1a64(le64(parent) || le64(byte length of name) || name)),
// (le64: 8 bytes little-endian; the length prefix keeps ("ab", "c") apart from ("a", "bc")), and each
// process draws from its own sub-stream derive(key, process) with process one of "white_noise",
// "bias_random_walk", "gauss_markov", "turn_on_bias", "scale_factor", "misalignment" — so switching one
// process on or off leaves the realisation of the others unchanged (a white-noise-only run and a full run
// share their white noise). Triad axes draw x, y, z in turn from the same sub-stream; Gauss-Markov terms
// draw axis by axis, term by term. A disabled process (zero parameter) draws nothing.
//
// Generator: xoshiro256** (Blackman & Vigna 2018), state seeded with four successive splitmix64 outputs
// from the key (the authors' recommendation). Uniform: the top 53 bits times 2^-53, in [0, 1). Normal:
// Marsaglia's polar method (two normals per accepted pair, the second kept in the state) with its
// logarithm computed by portable_log from +, -, *, / and frexp only (and sqrt, which IEEE 754 rounds
// correctly), so the normal stream depends on no libm approximation and is bit-identical on every IEEE-754 binary64 platform evaluating without FMA contraction (the
// x86-64 default; add -ffp-contract=off on FMA targets). std::normal_distribution is not used: its
// algorithm is implementation-defined. Process coefficients use std::exp/std::expm1/std::sqrt of the
// parameters, so across different libms phi may differ in the last bit; on one platform everything is
// bit-identical for the same seed.
//
// Datasheet figures convert to the parameters above (functions below, each with its formula), and
// bias instability B maps to Gauss-Markov terms whose Allan floor is 0.664 B (IEEE 952 flicker floor,
// sqrt(2 ln 2 / pi) B): see bias_instability_to_gauss_markov and ..._bank.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <string_view>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/core/value_noise.h"
#include "hadal/sensors/noise_params.h"

namespace hadal::sensors {

// ---------------------------------------------------------------------------------------------------
// Deterministic random streams
// ---------------------------------------------------------------------------------------------------

// splitmix64 output for state x: mix(x + 0x9e3779b97f4a7c15) (Steele, Lea & Flood 2014;
// hadal/core/value_noise.h, shared with the ocean and the seabed noise).
using hadal::splitmix64;
// FNV-1a 64 over bytes, continuing from hash h.
std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ULL);
// derive(parent, name) above.
std::uint64_t derive_key(std::uint64_t parent, std::string_view name);
// The key of one channel: derive(derive(derive(scenario_seed, vehicle), sensor), channel).
std::uint64_t channel_key(std::uint64_t scenario_seed, std::string_view vehicle, std::string_view sensor,
                          std::string_view channel);

// Natural logarithm of x > 0 (finite) from exact frexp reduction to m in [sqrt(1/2), sqrt(2)) and the
// series ln m = 2 atanh(z) = 2 z sum_{k=0}^{10} z^2k / (2k + 1), z = (m - 1) / (m + 1), |z| <= 0.1716
// (truncation < 1e-18), plus e ln 2 (fdlibm's split ln2_hi + ln2_lo). Within 2 ulp of a correctly
// rounded log; used by the normal generator so its output depends on no libm.
double portable_log(double x);
// e^x for finite x in [-700, 700] from +, -, *, / and ldexp only: x = k ln 2 + r with |r| <= ln 2 / 2
// (fdlibm's split of ln 2, k ln2_hi exact), the Taylor series of e^r to r^14 (truncation < 1e-17
// relative), times 2^k. Within 2 ulp of a correctly rounded exp; no libm.
double portable_exp(double x);

// One xoshiro256** stream plus the polar method's spare normal. A plain value: copy it to snapshot,
// assign it to restore; equal streams produce equal sequences.
class RandomStream {
 public:
  RandomStream() : RandomStream(0) {}
  explicit RandomStream(std::uint64_t key);

  std::uint64_t next_u64();
  double uniform();  // [0, 1), 53 random bits
  double normal();   // N(0, 1)
  // N(0, 1) by the ziggurat (256 layers, Marsaglia & Tsang 2000, with Doornik's 2005 split of one
  // 64-bit draw: bits 0-7 the layer, bit 8 the sign, bits 11-63 the position, so that layer and
  // value are independent). ~99 % of draws cost one next_u64, a multiply and a compare; the wedges
  // and the tail beyond r = 3.654 use portable_exp and portable_log, so, like normal(), the stream
  // depends on no libm. A different sequence from normal() (and it never touches normal()'s spare):
  // for bulk draws such as an image sensor's per-pixel noise.
  double ziggurat_normal();

  friend bool operator==(const RandomStream& a, const RandomStream& b) {
    return a.s_ == b.s_ && a.has_spare_ == b.has_spare_ && a.spare_ == b.spare_;
  }
  friend bool operator!=(const RandomStream& a, const RandomStream& b) { return !(a == b); }

 private:
  std::array<std::uint64_t, 4> s_{};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// ---------------------------------------------------------------------------------------------------
// Processes: pure kernels, w ~ N(0, 1) supplied by the caller (the channel draws it from its stream)
// ---------------------------------------------------------------------------------------------------

// Per-sample std of white noise of density N [u/sqrt(Hz)] sampled every dt [s]: N / sqrt(dt) = N sqrt(f_s).
double white_noise_sigma(double density, double dt);
// One white-noise sample: white_noise_sigma(density, dt) * w.
double white_noise(double density, double dt, double w);
// Bias random walk step: b + K sqrt(dt) w.
double bias_random_walk_step(double density, double bias, double dt, double w);

// phi = exp(-dt / tau_c).
double gauss_markov_phi(const GaussMarkovParams& p, double dt);
// n' = phi n + sqrt(1 - phi^2) sigma w.
double gauss_markov_step(const GaussMarkovParams& p, double n, double dt, double w);
// Allan variance of the continuous-time process at averaging time tau [u^2]:
//   sigma^2 (2x - 3 + 4 e^-x - e^-2x) / x^2,  x = tau / tau_c
// (from the autocovariance sigma^2 exp(-|t| / tau_c)). It rises like a random walk for tau << tau_c,
// falls like white noise for tau >> tau_c and peaks at tau = 1.8926 tau_c with deviation 0.61736 sigma.
double gauss_markov_allan_variance(const GaussMarkovParams& p, double tau);

// lsb * round(x / lsb) for lsb > 0, else x.
double quantize(double x, double lsb);
// min(max(x, lo), hi).
double clip(double x, double lo, double hi);
// M (I + diag(s)) x.
Eigen::Vector3d scale_and_misalign(const Eigen::Matrix3d& misalignment, const Eigen::Vector3d& scale_factor,
                                   const Eigen::Vector3d& x);

// ---------------------------------------------------------------------------------------------------
// Channel composition
// ---------------------------------------------------------------------------------------------------

struct AxisNoiseState {
  double turn_on_bias = 0.0;      // b0 = fixed + drawn [u]
  double bias_random_walk = 0.0;  // b_rw [u]
  std::array<double, kMaxGaussMarkovTerms> gauss_markov{};  // n_j [u], one per AxisNoiseParams term

  friend bool operator==(const AxisNoiseState& a, const AxisNoiseState& b) {
    return a.turn_on_bias == b.turn_on_bias && a.bias_random_walk == b.bias_random_walk &&
           a.gauss_markov == b.gauss_markov;
  }
  friend bool operator!=(const AxisNoiseState& a, const AxisNoiseState& b) { return !(a == b); }
};

// The sub-streams one channel draws from while running (turn-on draws use their own, at start only).
struct NoiseStreams {
  RandomStream white_noise;
  RandomStream bias_random_walk;
  RandomStream gauss_markov;

  friend bool operator==(const NoiseStreams& a, const NoiseStreams& b) {
    return a.white_noise == b.white_noise && a.bias_random_walk == b.bias_random_walk &&
           a.gauss_markov == b.gauss_markov;
  }
};

struct NoiseChannelState {
  double scale_factor = 0.0;  // s, fixed + drawn
  AxisNoiseState axis;
  NoiseStreams streams;

  friend bool operator==(const NoiseChannelState& a, const NoiseChannelState& b) {
    return a.scale_factor == b.scale_factor && a.axis == b.axis && a.streams == b.streams;
  }
  friend bool operator!=(const NoiseChannelState& a, const NoiseChannelState& b) { return !(a == b); }
};

struct NoiseTriadState {
  Eigen::Matrix3d transform = Eigen::Matrix3d::Identity();  // M (I + diag(s)) with the draws, fixed per run
  std::array<AxisNoiseState, 3> axes;
  NoiseStreams streams;

  friend bool operator==(const NoiseTriadState& a, const NoiseTriadState& b) {
    return a.transform == b.transform && a.axes == b.axes && a.streams == b.streams;
  }
  friend bool operator!=(const NoiseTriadState& a, const NoiseTriadState& b) { return !(a == b); }
};

// A scalar channel with white noise of `stddev` per sample [u] at sample period `period` [s] (the
// density stddev sqrt(period)), quantised to `lsb` and clipped to [min, max]: a sensor's figures "noise
// per sample, resolution, range" as channel parameters.
NoiseChannelParams per_sample_white_noise(double stddev, double period, double lsb,
                                          double min = -std::numeric_limits<double>::infinity(),
                                          double max = std::numeric_limits<double>::infinity());

// Checks parameters (non-negative sigmas and densities, tau_c > 0, at most kMaxGaussMarkovTerms terms,
// lsb >= 0, min <= max, finite scale and misalignment); throws std::invalid_argument naming the field.
void validate(const NoiseChannelParams& params);
void validate(const NoiseTriadParams& params);

// The state at the start of a run for the channel with this key (channel_key above): validates, draws
// the turn-on bias, scale-factor and misalignment errors, and starts each Gauss-Markov term from its
// stationary distribution.
NoiseChannelState make_noise_state(const NoiseChannelParams& params, std::uint64_t key);
NoiseTriadState make_noise_state(const NoiseTriadParams& params, std::uint64_t key);

// Scale (and misalignment), then biases, Gauss-Markov and white noise, stepping the state over dt > 0.
double apply_noise(const NoiseChannelParams& params, NoiseChannelState& state, double ideal, double dt);
Eigen::Vector3d apply_noise(const NoiseTriadParams& params, NoiseTriadState& state, const Eigen::Vector3d& ideal,
                            double dt);
// Quantization, then clipping.
double apply_output_stage(const NoiseChannelParams& params, double value);
Eigen::Vector3d apply_output_stage(const NoiseTriadParams& params, const Eigen::Vector3d& value);
// The whole chain: apply_output_stage(apply_noise(ideal) + sensor_terms), sensor_terms being the
// sensor-specific additions (temperature drift, vibration) the caller computed.
double measure(const NoiseChannelParams& params, NoiseChannelState& state, double ideal, double dt,
               double sensor_terms = 0.0);
Eigen::Vector3d measure(const NoiseTriadParams& params, NoiseTriadState& state, const Eigen::Vector3d& ideal,
                        double dt, const Eigen::Vector3d& sensor_terms = Eigen::Vector3d::Zero());

// ---------------------------------------------------------------------------------------------------
// Datasheet figures -> parameters (IEEE Std 952 definitions)
// ---------------------------------------------------------------------------------------------------

inline constexpr double kStandardGravity = 9.80665;  // g_n [m/s^2], for mg / ug figures
inline constexpr double kFootInMeters = 0.3048;
// Allan floor of flicker (bias-instability) noise of coefficient B: sqrt(2 ln 2 / pi) B = 0.664 B.
inline constexpr double kBiasInstabilityAllanFactor = 0.6642824702679601;
// Gauss-Markov Allan peak (gauss_markov_allan_variance): at tau = 1.8926 tau_c, deviation 0.61736 sigma.
inline constexpr double kGaussMarkovAllanPeakTauRatio = 1.8926178246856253;
inline constexpr double kGaussMarkovAllanPeakRatio = 0.6173642831444414;
// Allan deviation / sigma of an unbounded bank of equal-sigma Gauss-Markov terms one decade apart in
// tau_c: it ripples between 0.76818 and 0.78360 (+-1 %) with period one decade; this is the geometric mean.
inline constexpr double kDecadeBankAllanRatio = 0.7758548539028967;

// Gyro angle random walk ARW [deg/sqrt(h)] -> rate noise density N [rad/s/sqrt(Hz)]:
// 1 deg/sqrt(h) = 1 deg / sqrt(3600 s) = (1/60) deg/s/sqrt(Hz), so N = ARW (pi / 180) / 60.
constexpr double arw_to_noise_density(double arw_deg_per_sqrt_h) { return arw_deg_per_sqrt_h * kPi / 180.0 / 60.0; }
// Velocity random walk VRW [m/s/sqrt(h)] -> acceleration noise density N [m/s^2/sqrt(Hz)]: N = VRW / 60.
constexpr double vrw_to_noise_density(double vrw_m_per_s_per_sqrt_h) { return vrw_m_per_s_per_sqrt_h / 60.0; }
// Acceleration noise density [ug/sqrt(Hz)] -> [m/s^2/sqrt(Hz)]: x 1e-6 g_n.
constexpr double micro_g_per_sqrt_hz_to_noise_density(double ug_per_sqrt_hz) {
  return ug_per_sqrt_hz * 1e-6 * kStandardGravity;
}
// Angular rate [deg/h] -> [rad/s] (bias instability, bias): x (pi / 180) / 3600.
constexpr double deg_per_h_to_rad_per_s(double deg_per_h) { return deg_per_h * kPi / 180.0 / 3600.0; }
// Acceleration [mg] / [ug] -> [m/s^2] (accelerometer bias instability, bias).
constexpr double milli_g_to_mps2(double mg) { return mg * 1e-3 * kStandardGravity; }
constexpr double micro_g_to_mps2(double ug) { return ug * 1e-6 * kStandardGravity; }
// Gyro rate random walk [deg/h/sqrt(h)] -> K [rad/s^2/sqrt(Hz)] = [rad s^-3/2]:
// 1 deg/h/sqrt(h) = 1 deg / (3600 s * 60 s^1/2), so K = RRW (pi / 180) / 216000.
constexpr double rrw_to_random_walk_density(double rrw_deg_per_h_per_sqrt_h) {
  return rrw_deg_per_h_per_sqrt_h * kPi / 180.0 / 216000.0;
}
// Accelerometer random walk [m/s/h/sqrt(h)] -> K [m/s^3/sqrt(Hz)]: / 216000.
constexpr double accel_rrw_to_random_walk_density(double m_per_s_per_h_per_sqrt_h) {
  return m_per_s_per_h_per_sqrt_h / 216000.0;
}

// Bias instability B [u] (datasheet figure, converted to SI) -> one Gauss-Markov process (the paper's
// model) with correlation time tau_c whose Allan deviation peaks at the flicker floor:
//   sigma = 0.664 B / 0.61736 = 1.0760 B, the peak at tau = 1.8926 tau_c.
// A single process only touches the floor near its peak (it rises as sqrt(tau) before and falls as
// 1/sqrt(tau) after); prefer the bank below when the floor has to be read off a whole curve.
GaussMarkovParams bias_instability_to_gauss_markov(double bias_instability, double correlation_time_s);

// Bias instability B [u] -> a bank of equal Gauss-Markov terms approximating flicker noise (a 1/f PSD is
// a sum of Lorentzians with log-spaced corners, one per decade here) whose Allan deviation is flat at
// 0.664 B over [tau_min_s, tau_max_s]: peaks at tau_min 10^k for k = -1 .. ceil(log10(tau_max/tau_min)) + 1
// (one decade past each end keeps the edges up), tau_c = peak / 1.8926, each sigma = 0.664 B / 0.77585
// = 0.85619 B. The closed-form Allan deviation of the bank stays within [-2 %, +1 %] of 0.664 B over
// the range, falling off as sqrt(tau) below and 1/sqrt(tau) above it. At most seven decades (ten terms).
// Keep tau_min_s >= ~20 sample periods: the lowest term's tau_c = tau_min / 18.9 should not be shorter
// than dt, since a term much faster than the sampling is point-sampled at its full variance sigma^2 (not
// averaged over dt) and adds white noise. Each term costs one normal draw and one exp per sample.
std::vector<GaussMarkovParams> bias_instability_to_gauss_markov_bank(double bias_instability, double tau_min_s,
                                                                     double tau_max_s);

}  // namespace hadal::sensors
