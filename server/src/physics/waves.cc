#include "hadal/physics/waves.h"

#include <cmath>
#include <algorithm>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string_view>

#include "hadal/core/value_noise.h"

namespace hadal::physics {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// The sampled band, in multiples of the peak frequency.
constexpr double kBandLow = 0.5, kBandHigh = 4.0;
// kh beyond which a component is in deep water (tanh(kh) = 1 to 1e-15; cosh and sinh ratios as exponentials).
constexpr double kDeepKh = 18.0;

// [0, 1) from 53 bits of the generator (std::mt19937_64 is fully specified: the same numbers everywhere).
double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

bool deep(double k, double depth) { return !std::isfinite(depth) || k * depth > kDeepKh; }

}  // namespace

double wave_number(double omega, double depth, double g) {
  const double k_deep = omega * omega / g;
  if (!std::isfinite(depth) || k_deep * depth > kDeepKh) return k_deep;
  // Newton on f(k) = g k tanh(k h) - omega^2 from above the root (f is increasing and convex there).
  double k = std::max(k_deep, omega / std::sqrt(g * depth));
  for (int i = 0; i < 50; ++i) {
    const double t = std::tanh(k * depth);
    const double f = g * k * t - omega * omega;
    const double df = g * (t + k * depth * (1.0 - t * t));
    const double step = f / df;
    k -= step;
    if (std::abs(step) < 1e-15 * k) break;
  }
  return k;
}

double jonswap_shape(double omega, double omega_p, double gamma, double g) {
  if (omega <= 0.0) return 0.0;
  const double sigma = omega <= omega_p ? 0.07 : 0.09;
  const double x = (omega - omega_p) / (sigma * omega_p);
  const double r = std::exp(-0.5 * x * x);
  const double ratio = omega_p / omega;
  return g * g * std::pow(omega, -5.0) * std::exp(-1.25 * ratio * ratio * ratio * ratio) * std::pow(gamma, r);
}

Waves::Waves(const WaveSpec& spec, double surface_z, double density, double g, std::uint64_t seed)
    : surface_z_(surface_z), density_(density), g_(g), depth_(spec.depth) {
  if (!spec.enabled()) return;
  if (spec.spectrum == WaveSpectrum::kRegular) {
    double longest = 0.0;
    for (const WaveComponentSpec& c : spec.regular) longest = std::max(longest, c.amplitude > 0.0 ? c.period : 0.0);
    ramp_time_ = spec.ramp_time.value_or(2.0 * longest);
    for (const WaveComponentSpec& c : spec.regular) {
      const double omega = kTwoPi / c.period;
      components_.push_back({c.amplitude, omega, wave_number(omega, depth_, g_), c.direction, c.phase});
    }
    return;
  }
  ramp_time_ = spec.ramp_time.value_or(2.0 * spec.peak_period);
  std::mt19937_64 rng(splitmix64(seed ^ fnv1a("waves")));
  const double omega_p = kTwoPi / spec.peak_period;
  const double gamma = spec.spectrum == WaveSpectrum::kPiersonMoskowitz ? 1.0 : spec.gamma;
  const int n = spec.components;
  const double lo = kBandLow * omega_p, d_omega = (kBandHigh - kBandLow) * omega_p / n;
  double variance = 0.0;
  for (int i = 0; i < n; ++i) {
    WaveComponent c;
    c.omega = lo + (i + uniform(rng)) * d_omega;
    c.amplitude = std::sqrt(2.0 * jonswap_shape(c.omega, omega_p, gamma, g_) * d_omega);
    c.phase = kTwoPi * uniform(rng);
    c.direction = spec.direction;
    if (spec.spreading) {  // rejection sampling of cos^2s((theta - theta_0) / 2) on (-pi, pi]
      for (;;) {
        const double offset = std::numbers::pi * (2.0 * uniform(rng) - 1.0);
        if (uniform(rng) <= std::pow(std::cos(0.5 * offset), 2.0 * *spec.spreading)) {
          c.direction += offset;
          break;
        }
      }
    }
    c.k = wave_number(c.omega, depth_, g_);
    variance += 0.5 * c.amplitude * c.amplitude;
    components_.push_back(c);
  }
  // The sampled spectrum's shape, scaled to the target m0 = (Hs / 4)^2 (alpha).
  const double scale = variance > 0.0 ? 0.25 * spec.significant_height / std::sqrt(variance) : 0.0;
  for (WaveComponent& c : components_) c.amplitude *= scale;
}

double Waves::significant_height() const {
  double variance = 0.0;
  for (const WaveComponent& c : components_) variance += 0.5 * c.amplitude * c.amplitude;
  return 4.0 * std::sqrt(variance);
}

double Waves::ramp(double t) const {
  if (t >= ramp_time_) return 1.0;
  if (t <= 0.0) return 0.0;
  return 0.5 * (1.0 - std::cos(std::numbers::pi * t / ramp_time_));
}

double Waves::ramp_rate(double t) const {
  if (t >= ramp_time_ || t <= 0.0) return 0.0;
  return 0.5 * std::numbers::pi / ramp_time_ * std::sin(std::numbers::pi * t / ramp_time_);
}

double Waves::surface_height(double x, double y, double t) const {
  double eta = 0.0;
  for (const WaveComponent& c : components_) {
    eta += c.amplitude * std::cos(c.k * (x * std::cos(c.direction) + y * std::sin(c.direction)) - c.omega * t + c.phase);
  }
  return surface_z_ + ramp(t) * eta;
}

Eigen::Vector2d Waves::surface_slope(double x, double y, double t) const {
  Eigen::Vector2d slope = Eigen::Vector2d::Zero();
  for (const WaveComponent& c : components_) {
    const double cb = std::cos(c.direction), sb = std::sin(c.direction);
    const double s = -c.amplitude * c.k * std::sin(c.k * (x * cb + y * sb) - c.omega * t + c.phase);
    slope += Eigen::Vector2d(s * cb, s * sb);
  }
  return ramp(t) * slope;
}

double Waves::stretched(double z_rel, double eta) const {
  if (!std::isfinite(depth_)) return z_rel - eta;
  return depth_ * (z_rel - eta) / (depth_ + eta);
}

void Waves::orbital(const Eigen::Vector3d& p_W, double t, Eigen::Vector3d* v_W, Eigen::Vector3d* a_W) const {
  v_W->setZero();
  a_W->setZero();
  if (components_.empty()) return;
  const double eta = surface_height(p_W.x(), p_W.y(), t) - surface_z_;
  const double z_rel = p_W.z() - surface_z_;
  if (z_rel > eta) return;  // in the air
  const double z = stretched(z_rel, eta);
  for (const WaveComponent& c : components_) {
    const double cb = std::cos(c.direction), sb = std::sin(c.direction);
    const double theta = c.k * (p_W.x() * cb + p_W.y() * sb) - c.omega * t + c.phase;
    double horizontal = 0.0, vertical = 0.0;  // cosh(k (z + h)) / sinh(kh), sinh(k (z + h)) / sinh(kh)
    if (deep(c.k, depth_)) {
      horizontal = vertical = std::exp(c.k * z);
    } else {
      const double s = std::sinh(c.k * depth_);
      horizontal = std::cosh(c.k * (z + depth_)) / s;
      vertical = std::sinh(c.k * (z + depth_)) / s;
    }
    const double cos_t = std::cos(theta), sin_t = std::sin(theta), a_omega = c.amplitude * c.omega;
    const double u = a_omega * horizontal * cos_t;
    *v_W += Eigen::Vector3d(u * cb, u * sb, a_omega * vertical * sin_t);
    // d/dt of cos(theta) is omega sin(theta); of sin(theta), -omega cos(theta).
    const double du = a_omega * c.omega * horizontal * sin_t;
    *a_W += Eigen::Vector3d(du * cb, du * sb, -a_omega * c.omega * vertical * cos_t);
  }
  const double r = ramp(t);
  *a_W = r * *a_W + ramp_rate(t) * *v_W;
  *v_W *= r;
}

Eigen::Vector3d Waves::velocity_W(const Eigen::Vector3d& p_W, double t) const {
  Eigen::Vector3d v, a;
  orbital(p_W, t, &v, &a);
  return v;
}

Eigen::Vector3d Waves::acceleration_W(const Eigen::Vector3d& p_W, double t) const {
  Eigen::Vector3d v, a;
  orbital(p_W, t, &v, &a);
  return a;
}

double Waves::dynamic_pressure(const Eigen::Vector3d& p_W, double t) const {
  if (components_.empty()) return 0.0;
  const double eta = surface_height(p_W.x(), p_W.y(), t) - surface_z_;
  const double z_rel = p_W.z() - surface_z_;
  if (z_rel > eta) return 0.0;
  const double z = stretched(z_rel, eta);
  double p = 0.0;
  for (const WaveComponent& c : components_) {
    const double theta =
        c.k * (p_W.x() * std::cos(c.direction) + p_W.y() * std::sin(c.direction)) - c.omega * t + c.phase;
    const double ratio = deep(c.k, depth_) ? std::exp(c.k * z)
                                            : std::cosh(c.k * (z + depth_)) / std::cosh(c.k * depth_);
    p += c.amplitude * ratio * std::cos(theta);
  }
  return density_ * g_ * ramp(t) * p;
}

}  // namespace hadal::physics
