#include "hadal/sensors/noise.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include "hadal/core/validation_error.h"

namespace hadal::sensors {

namespace {

constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15ULL;

std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

std::uint64_t fnv1a64_le64(std::uint64_t value, std::uint64_t h) {
  for (int i = 0; i < 8; ++i) {
    h ^= (value >> (8 * i)) & 0xffU;
    h *= 0x100000001b3ULL;
  }
  return h;
}

[[noreturn]] void invalid(const std::string& field, const std::string& requirement, double got) {
  validation::invalid("noise: " + field, requirement, got);
}

void validate_axis(const AxisNoiseParams& p, const std::string& prefix) {
  if (!(p.white_noise_density >= 0.0) || std::isinf(p.white_noise_density)) {
    invalid(prefix + "white_noise_density", "must be finite and >= 0", p.white_noise_density);
  }
  if (!(p.bias_random_walk_density >= 0.0) || std::isinf(p.bias_random_walk_density)) {
    invalid(prefix + "bias_random_walk_density", "must be finite and >= 0", p.bias_random_walk_density);
  }
  if (p.gauss_markov.size() > static_cast<std::size_t>(kMaxGaussMarkovTerms)) {
    invalid(prefix + "gauss_markov", "must have at most " + std::to_string(kMaxGaussMarkovTerms) + " terms",
            static_cast<double>(p.gauss_markov.size()));
  }
  for (std::size_t j = 0; j < p.gauss_markov.size(); ++j) {
    const std::string term = prefix + "gauss_markov[" + std::to_string(j) + "].";
    if (!(p.gauss_markov[j].sigma >= 0.0) || std::isinf(p.gauss_markov[j].sigma)) {
      invalid(term + "sigma", "must be finite and >= 0", p.gauss_markov[j].sigma);
    }
    if (!(p.gauss_markov[j].correlation_time_s > 0.0)) {
      invalid(term + "correlation_time_s", "must be > 0", p.gauss_markov[j].correlation_time_s);
    }
  }
  if (!std::isfinite(p.turn_on_bias)) invalid(prefix + "turn_on_bias", "must be finite", p.turn_on_bias);
  if (!(p.turn_on_bias_sigma >= 0.0) || std::isinf(p.turn_on_bias_sigma)) {
    invalid(prefix + "turn_on_bias_sigma", "must be finite and >= 0", p.turn_on_bias_sigma);
  }
}

void validate_output(double lsb, double min, double max) {
  if (!(lsb >= 0.0) || std::isinf(lsb)) invalid("lsb", "must be finite and >= 0", lsb);
  if (std::isnan(min)) invalid("min", "must not be NaN", min);
  if (std::isnan(max)) invalid("max", "must not be NaN", max);
  if (!(min <= max)) invalid("min", "must be <= max", min);
}

void validate_sigma(const char* field, double sigma) {
  if (!(sigma >= 0.0) || std::isinf(sigma)) invalid(field, "must be finite and >= 0", sigma);
}

// b0 (one draw per axis from the turn-on stream, only when its sigma is set).
double draw_turn_on_bias(const AxisNoiseParams& p, RandomStream& stream) {
  return p.turn_on_bias_sigma > 0.0 ? p.turn_on_bias + p.turn_on_bias_sigma * stream.normal() : p.turn_on_bias;
}

// Stationary start of every Gauss-Markov term of one axis.
void start_gauss_markov(const AxisNoiseParams& p, AxisNoiseState& s, RandomStream& stream) {
  for (std::size_t j = 0; j < p.gauss_markov.size(); ++j) {
    if (p.gauss_markov[j].sigma > 0.0) s.gauss_markov[j] = p.gauss_markov[j].sigma * stream.normal();
  }
}

NoiseStreams make_streams(std::uint64_t key) {
  NoiseStreams streams;
  streams.white_noise = RandomStream(derive_key(key, "white_noise"));
  streams.bias_random_walk = RandomStream(derive_key(key, "bias_random_walk"));
  streams.gauss_markov = RandomStream(derive_key(key, "gauss_markov"));
  return streams;
}

// Steps one axis over dt and returns b0 + b_rw + sum n_j + n_w.
double step_axis(const AxisNoiseParams& p, AxisNoiseState& s, NoiseStreams& streams, double dt) {
  if (p.bias_random_walk_density > 0.0) {
    s.bias_random_walk =
        bias_random_walk_step(p.bias_random_walk_density, s.bias_random_walk, dt, streams.bias_random_walk.normal());
  }
  double error = s.turn_on_bias + s.bias_random_walk;
  for (std::size_t j = 0; j < p.gauss_markov.size(); ++j) {
    if (p.gauss_markov[j].sigma > 0.0) {
      s.gauss_markov[j] = gauss_markov_step(p.gauss_markov[j], s.gauss_markov[j], dt, streams.gauss_markov.normal());
    }
    error += s.gauss_markov[j];
  }
  if (p.white_noise_density > 0.0) error += white_noise(p.white_noise_density, dt, streams.white_noise.normal());
  return error;
}

}  // namespace

// --- random streams ----------------------------------------------------------------------------------

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h) {
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::uint64_t derive_key(std::uint64_t parent, std::string_view name) {
  std::uint64_t h = fnv1a64_le64(parent, 0xcbf29ce484222325ULL);
  h = fnv1a64_le64(static_cast<std::uint64_t>(name.size()), h);
  return splitmix64(fnv1a64(name, h));
}

std::uint64_t channel_key(std::uint64_t scenario_seed, std::string_view vehicle, std::string_view sensor,
                          std::string_view channel) {
  return derive_key(derive_key(derive_key(scenario_seed, vehicle), sensor), channel);
}

double portable_log(double x) {
  // fdlibm's split of ln 2: ln2_hi has 21 trailing zero bits, so e * ln2_hi is exact.
  constexpr double kLn2Hi = 0x1.62e42fee00000p-1;
  constexpr double kLn2Lo = 0x1.a39ef35793c76p-33;
  constexpr double kSqrtHalf = 0.70710678118654752440;
  int e = 0;
  double m = std::frexp(x, &e);  // x = m 2^e, m in [1/2, 1), exact
  if (m < kSqrtHalf) {
    m *= 2.0;
    --e;
  }
  const double z = (m - 1.0) / (m + 1.0);  // m - 1 exact (Sterbenz)
  const double z2 = z * z;
  double p = 1.0 / 21.0;
  p = p * z2 + 1.0 / 19.0;
  p = p * z2 + 1.0 / 17.0;
  p = p * z2 + 1.0 / 15.0;
  p = p * z2 + 1.0 / 13.0;
  p = p * z2 + 1.0 / 11.0;
  p = p * z2 + 1.0 / 9.0;
  p = p * z2 + 1.0 / 7.0;
  p = p * z2 + 1.0 / 5.0;
  p = p * z2 + 1.0 / 3.0;
  p = p * z2 + 1.0;
  const double de = static_cast<double>(e);
  return de * kLn2Hi + (de * kLn2Lo + 2.0 * z * p);
}

double portable_exp(double x) {
  constexpr double kLn2Hi = 0x1.62e42fee00000p-1;
  constexpr double kLn2Lo = 0x1.a39ef35793c76p-33;
  constexpr double kInvLn2 = 1.44269504088896338700;
  const double k = std::floor(x * kInvLn2 + 0.5);  // |k| <= 1010: k ln2_hi exact (21 trailing zero bits)
  const double r = (x - k * kLn2Hi) - k * kLn2Lo;  // |r| <= ln 2 / 2 (+ rounding)
  // e^r = 1 + r (1 + r/2 (1 + r/3 (... (1 + r/14)))).
  double p = 1.0;
  for (int n = 14; n >= 1; --n) p = 1.0 + r / n * p;
  return std::ldexp(p, static_cast<int>(k));
}

RandomStream::RandomStream(std::uint64_t key) {
  for (std::uint64_t i = 0; i < 4; ++i) s_[i] = splitmix64(key + i * kGolden);
}

std::uint64_t RandomStream::next_u64() {
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

double RandomStream::uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

double RandomStream::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u = 0.0;
  double v = 0.0;
  double s = 0.0;
  do {  // accepts with probability pi / 4
    u = 2.0 * uniform() - 1.0;
    v = 2.0 * uniform() - 1.0;
    s = u * u + v * v;
  } while (!(s > 0.0 && s < 1.0));
  const double f = std::sqrt(-2.0 * portable_log(s) / s);
  spare_ = v * f;
  has_spare_ = true;
  return u * f;
}

namespace {

// The 256-layer ziggurat of N(0, 1)'s density f(x) = exp(-x^2 / 2) (unnormalised): layer i (0..255) is
// the rectangle [0, x[i]] x [f(x[i]), f(x[i + 1])], x decreasing from x[1] = r to x[256] = 0; every
// layer has area v, and layer 0 (width x[0] = v / f(r)) stands for the base strip [0, r] x [0, f(r)]
// plus the tail beyond r. r and v: Marsaglia & Tsang (2000), 256 layers.
struct Ziggurat {
  static constexpr double kR = 3.6541528853610088;
  static constexpr double kV = 0.00492867323399;
  std::array<double, 257> x{};
  std::array<double, 257> f{};
  Ziggurat() {
    x[0] = kV / portable_exp(-0.5 * kR * kR);
    x[1] = kR;
    for (int i = 1; i < 255; ++i) x[i + 1] = std::sqrt(-2.0 * portable_log(kV / x[i] + portable_exp(-0.5 * x[i] * x[i])));
    x[256] = 0.0;
    for (int i = 0; i <= 256; ++i) f[i] = portable_exp(-0.5 * x[i] * x[i]);
  }
};

const Ziggurat& ziggurat() {
  static const Ziggurat table;
  return table;
}

}  // namespace

double RandomStream::ziggurat_normal() {
  const Ziggurat& z = ziggurat();
  for (;;) {
    const std::uint64_t bits = next_u64();
    const int i = static_cast<int>(bits & 0xff);
    const double sign = (bits & 0x100) ? -1.0 : 1.0;
    const double x = static_cast<double>(bits >> 11) * 0x1.0p-53 * z.x[i];
    if (x < z.x[i + 1]) return sign * x;  // inside the part of the layer under the curve
    if (i == 0) {  // the tail beyond r (Marsaglia 1964): r + a, a ~ Exp(r), accepted with exp(-a^2 / 2)
      double a = 0.0, b = 0.0;
      do {
        a = -portable_log(1.0 - uniform()) / Ziggurat::kR;
        b = -portable_log(1.0 - uniform());
      } while (b + b < a * a);
      return sign * (Ziggurat::kR + a);
    }
    // The wedge: a uniform height in the layer, accepted under the curve.
    if (z.f[i] + uniform() * (z.f[i + 1] - z.f[i]) < portable_exp(-0.5 * x * x)) return sign * x;
  }
}

// --- processes -----------------------------------------------------------------------------------------

double white_noise_sigma(double density, double dt) { return density / std::sqrt(dt); }

double white_noise(double density, double dt, double w) { return white_noise_sigma(density, dt) * w; }

double bias_random_walk_step(double density, double bias, double dt, double w) {
  return bias + density * std::sqrt(dt) * w;
}

double gauss_markov_phi(const GaussMarkovParams& p, double dt) { return std::exp(-dt / p.correlation_time_s); }

double gauss_markov_step(const GaussMarkovParams& p, double n, double dt, double w) {
  const double phi = gauss_markov_phi(p, dt);
  const double innovation = std::sqrt(-std::expm1(-2.0 * dt / p.correlation_time_s));  // sqrt(1 - phi^2)
  return phi * n + innovation * p.sigma * w;
}

double gauss_markov_allan_variance(const GaussMarkovParams& p, double tau) {
  const double x = tau / p.correlation_time_s;
  const double s2 = p.sigma * p.sigma;
  // Below x = 0.1 the closed form cancels (2x - 3 + 4 e^-x - e^-2x = O(x^3)); its Taylor series
  // sum_{n>=3} (4 (-1)^n - (-2)^n) x^(n-2) / n! to n = 10 is exact to 1e-12 there.
  if (x < 0.1) {
    double sum = 0.0;
    double power = x;         // x^(n-2)
    double factorial = 6.0;   // n!
    double sign = -1.0;       // (-1)^n
    double two_power = -8.0;  // (-2)^n
    for (int n = 3; n <= 10; ++n) {
      sum += (4.0 * sign - two_power) * power / factorial;
      power *= x;
      factorial *= n + 1;
      sign = -sign;
      two_power *= -2.0;
    }
    return s2 * sum;
  }
  return s2 * (2.0 * x - 3.0 + 4.0 * std::exp(-x) - std::exp(-2.0 * x)) / (x * x);
}

double quantize(double x, double lsb) { return lsb > 0.0 ? lsb * std::round(x / lsb) : x; }

double clip(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

Eigen::Vector3d scale_and_misalign(const Eigen::Matrix3d& misalignment, const Eigen::Vector3d& scale_factor,
                                   const Eigen::Vector3d& x) {
  const Eigen::Matrix3d transform = misalignment * (Eigen::Vector3d::Ones() + scale_factor).asDiagonal();
  return transform * x;
}

// --- channels ------------------------------------------------------------------------------------------

void validate(const NoiseChannelParams& params) {
  validate_axis(params.noise, "noise.");
  if (!std::isfinite(params.scale_factor)) invalid("scale_factor", "must be finite", params.scale_factor);
  validate_sigma("scale_factor_sigma", params.scale_factor_sigma);
  validate_output(params.lsb, params.min, params.max);
}

void validate(const NoiseTriadParams& params) {
  for (int i = 0; i < 3; ++i) validate_axis(params.axes[i], "axes[" + std::to_string(i) + "].");
  if (!params.misalignment.allFinite()) invalid("misalignment", "must be finite", params.misalignment.sum());
  validate_sigma("misalignment_sigma", params.misalignment_sigma);
  if (!params.scale_factor.allFinite()) invalid("scale_factor", "must be finite", params.scale_factor.sum());
  validate_sigma("scale_factor_sigma", params.scale_factor_sigma);
  validate_output(params.lsb, params.min, params.max);
}

NoiseChannelParams per_sample_white_noise(double stddev, double period, double lsb, double min, double max) {
  NoiseChannelParams channel;
  channel.noise.white_noise_density = stddev * std::sqrt(period);
  channel.lsb = lsb;
  channel.min = min;
  channel.max = max;
  return channel;
}

NoiseChannelState make_noise_state(const NoiseChannelParams& params, std::uint64_t key) {
  validate(params);
  NoiseChannelState state;
  state.scale_factor = params.scale_factor;
  if (params.scale_factor_sigma > 0.0) {
    RandomStream scale_stream(derive_key(key, "scale_factor"));
    state.scale_factor += params.scale_factor_sigma * scale_stream.normal();
  }
  RandomStream turn_on_stream(derive_key(key, "turn_on_bias"));
  state.axis.turn_on_bias = draw_turn_on_bias(params.noise, turn_on_stream);
  state.streams = make_streams(key);
  start_gauss_markov(params.noise, state.axis, state.streams.gauss_markov);
  return state;
}

NoiseTriadState make_noise_state(const NoiseTriadParams& params, std::uint64_t key) {
  validate(params);
  NoiseTriadState state;
  Eigen::Vector3d scale = params.scale_factor;
  if (params.scale_factor_sigma > 0.0) {
    RandomStream scale_stream(derive_key(key, "scale_factor"));
    for (int i = 0; i < 3; ++i) scale[i] += params.scale_factor_sigma * scale_stream.normal();
  }
  Eigen::Matrix3d misalignment = params.misalignment;
  if (params.misalignment_sigma > 0.0) {
    RandomStream misalignment_stream(derive_key(key, "misalignment"));
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        if (r != c) misalignment(r, c) += params.misalignment_sigma * misalignment_stream.normal();
      }
    }
  }
  state.transform = misalignment * (Eigen::Vector3d::Ones() + scale).asDiagonal();
  RandomStream turn_on_stream(derive_key(key, "turn_on_bias"));
  for (int i = 0; i < 3; ++i) state.axes[i].turn_on_bias = draw_turn_on_bias(params.axes[i], turn_on_stream);
  state.streams = make_streams(key);
  for (int i = 0; i < 3; ++i) start_gauss_markov(params.axes[i], state.axes[i], state.streams.gauss_markov);
  return state;
}

double apply_noise(const NoiseChannelParams& params, NoiseChannelState& state, double ideal, double dt) {
  const double scaled = (1.0 + state.scale_factor) * ideal;
  return scaled + step_axis(params.noise, state.axis, state.streams, dt);
}

Eigen::Vector3d apply_noise(const NoiseTriadParams& params, NoiseTriadState& state, const Eigen::Vector3d& ideal,
                            double dt) {
  Eigen::Vector3d measured = state.transform * ideal;
  for (int i = 0; i < 3; ++i) measured[i] += step_axis(params.axes[i], state.axes[i], state.streams, dt);
  return measured;
}

double apply_output_stage(const NoiseChannelParams& params, double value) {
  return clip(quantize(value, params.lsb), params.min, params.max);
}

Eigen::Vector3d apply_output_stage(const NoiseTriadParams& params, const Eigen::Vector3d& value) {
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) out[i] = clip(quantize(value[i], params.lsb), params.min, params.max);
  return out;
}

double measure(const NoiseChannelParams& params, NoiseChannelState& state, double ideal, double dt,
               double sensor_terms) {
  return apply_output_stage(params, apply_noise(params, state, ideal, dt) + sensor_terms);
}

Eigen::Vector3d measure(const NoiseTriadParams& params, NoiseTriadState& state, const Eigen::Vector3d& ideal,
                        double dt, const Eigen::Vector3d& sensor_terms) {
  return apply_output_stage(params, apply_noise(params, state, ideal, dt) + sensor_terms);
}

// --- datasheet mappings --------------------------------------------------------------------------------

GaussMarkovParams bias_instability_to_gauss_markov(double bias_instability, double correlation_time_s) {
  if (!(bias_instability >= 0.0) || std::isinf(bias_instability)) {
    invalid("bias_instability", "must be finite and >= 0", bias_instability);
  }
  if (!(correlation_time_s > 0.0)) invalid("correlation_time_s", "must be > 0", correlation_time_s);
  return {kBiasInstabilityAllanFactor / kGaussMarkovAllanPeakRatio * bias_instability, correlation_time_s};
}

std::vector<GaussMarkovParams> bias_instability_to_gauss_markov_bank(double bias_instability, double tau_min_s,
                                                                     double tau_max_s) {
  if (!(bias_instability >= 0.0) || std::isinf(bias_instability)) {
    invalid("bias_instability", "must be finite and >= 0", bias_instability);
  }
  if (!(tau_min_s > 0.0) || std::isinf(tau_min_s)) invalid("tau_min_s", "must be finite and > 0", tau_min_s);
  if (!(tau_max_s >= tau_min_s) || std::isinf(tau_max_s)) {
    invalid("tau_max_s", "must be finite and >= tau_min_s", tau_max_s);
  }
  // 1e-9 keeps an exact number of decades (tau_max / tau_min = 1e4) from rounding up to one more.
  const int decades = static_cast<int>(std::ceil(std::log10(tau_max_s / tau_min_s) - 1e-9));
  const int terms = std::max(decades, 0) + 3;
  if (terms > kMaxGaussMarkovTerms) {
    invalid("tau_max_s / tau_min_s", "must span at most " + std::to_string(kMaxGaussMarkovTerms - 3) + " decades",
            tau_max_s / tau_min_s);
  }
  const double sigma = kBiasInstabilityAllanFactor / kDecadeBankAllanRatio * bias_instability;
  std::vector<GaussMarkovParams> bank;
  for (int k = -1; k < terms - 1; ++k) {
    const double peak_tau = tau_min_s * std::pow(10.0, k);
    bank.push_back({sigma, peak_tau / kGaussMarkovAllanPeakTauRatio});
  }
  return bank;
}

}  // namespace hadal::sensors
