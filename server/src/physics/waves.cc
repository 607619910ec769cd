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
    derive();
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
  derive();
}

void Waves::derive() {
  for (WaveComponent& c : components_) {
    c.cos_b = std::cos(c.direction);
    c.sin_b = std::sin(c.direction);
    c.k_x = c.k * c.cos_b;
    c.k_y = c.k * c.sin_b;
  }
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
  for (const WaveComponent& c : components_) eta += c.amplitude * std::cos(c.k_x * x + c.k_y * y - c.omega * t + c.phase);
  return surface_z_ + ramp(t) * eta;
}

Eigen::Vector2d Waves::surface_slope(double x, double y, double t) const {
  double eta = 0.0;
  Eigen::Vector2d slope;
  surface(x, y, t, &eta, &slope);
  return slope;
}

double Waves::stretched(double z_rel, double eta) const {
  if (!std::isfinite(depth_)) return z_rel - eta;
  return depth_ * (z_rel - eta) / (depth_ + eta);
}

void Waves::surface(double x, double y, double t, double* eta, Eigen::Vector2d* slope) const {
  double e = 0.0, sx = 0.0, sy = 0.0;
  for (const WaveComponent& c : components_) {
    const double theta = c.k_x * x + c.k_y * y - c.omega * t + c.phase;
    e += c.amplitude * std::cos(theta);
    const double s = -c.amplitude * std::sin(theta);  // d/dx of cos(theta) is -k_x sin(theta)
    sx += s * c.k_x;
    sy += s * c.k_y;
  }
  const double r = ramp(t);
  *eta = r * e;
  *slope = r * Eigen::Vector2d(sx, sy);
}

WaveKinematics Waves::kinematics(const Eigen::Vector3d& p_W, double t) const {
  WaveKinematics out;
  out.surface_height = surface_z_;
  if (components_.empty()) return out;
  double eta = 0.0;
  surface(p_W.x(), p_W.y(), t, &eta, &out.slope);
  out.surface_height = surface_z_ + eta;
  eta = out.surface_height - surface_z_;  // as rounded in W: a point given at surface_height is at the surface
  const double z_rel = p_W.z() - surface_z_;
  if (z_rel > eta) return out;  // in the air
  out.wet = true;
  const double z = stretched(z_rel, eta);
  // Wheeler's z' = h (z - eta) / (h + eta) (deep: z - eta): its derivatives in z and in eta.
  const bool finite = std::isfinite(depth_);
  const double dz_dz = finite ? depth_ / (depth_ + eta) : 1.0;
  const double dz_deta = finite ? -depth_ * (depth_ + z_rel) / ((depth_ + eta) * (depth_ + eta)) : -1.0;
  double p = 0.0, dp_dzp = 0.0, dp_dx = 0.0, dp_dy = 0.0;  // sums over the components, per rho g r
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), a = Eigen::Vector3d::Zero();
  for (const WaveComponent& c : components_) {
    const double theta = c.k_x * p_W.x() + c.k_y * p_W.y() - c.omega * t + c.phase;
    // horizontal, vertical: cosh(k (z' + h)) / sinh(kh), sinh(k (z' + h)) / sinh(kh); pressure: cosh(k (z' + h)) /
    // cosh(kh) and its z' derivative k sinh(k (z' + h)) / cosh(kh). Deep water: all exp(k z').
    double horizontal = 0.0, vertical = 0.0, pressure = 0.0, pressure_dz = 0.0;
    if (deep(c.k, depth_)) {
      horizontal = vertical = pressure = std::exp(c.k * z);
      pressure_dz = c.k * pressure;
    } else {
      const double ch = std::cosh(c.k * (z + depth_)), sh = std::sinh(c.k * (z + depth_));
      const double s = std::sinh(c.k * depth_), cc = std::cosh(c.k * depth_);
      horizontal = ch / s;
      vertical = sh / s;
      pressure = ch / cc;
      pressure_dz = c.k * sh / cc;
    }
    const double cos_t = std::cos(theta), sin_t = std::sin(theta), a_omega = c.amplitude * c.omega;
    const double u = a_omega * horizontal * cos_t;
    v += Eigen::Vector3d(u * c.cos_b, u * c.sin_b, a_omega * vertical * sin_t);
    // d/dt of cos(theta) is omega sin(theta); of sin(theta), -omega cos(theta).
    const double du = a_omega * c.omega * horizontal * sin_t;
    a += Eigen::Vector3d(du * c.cos_b, du * c.sin_b, -a_omega * c.omega * vertical * cos_t);
    p += c.amplitude * pressure * cos_t;
    dp_dzp += c.amplitude * pressure_dz * cos_t;
    dp_dx -= c.amplitude * pressure * c.k_x * sin_t;
    dp_dy -= c.amplitude * pressure * c.k_y * sin_t;
  }
  const double r = ramp(t), rho_g_r = density_ * g_ * r;
  out.velocity_W = r * v;
  out.acceleration_W = r * a + ramp_rate(t) * v;
  out.dynamic_pressure = rho_g_r * p;
  // Through z'(z, eta(x, y)): d/dx = d/dx at fixed z' + dp/dz' dz'/deta deta/dx (the slope holds the ramp already).
  out.pressure_gradient_W = Eigen::Vector3d(rho_g_r * (dp_dx + dp_dzp * dz_deta * out.slope.x()),
                                            rho_g_r * (dp_dy + dp_dzp * dz_deta * out.slope.y()),
                                            rho_g_r * dp_dzp * dz_dz);
  return out;
}

void Waves::orbital(const Eigen::Vector3d& p_W, double t, Eigen::Vector3d* v_W, Eigen::Vector3d* a_W) const {
  const WaveKinematics k = kinematics(p_W, t);
  *v_W = k.velocity_W;
  *a_W = k.acceleration_W;
}

Eigen::Vector3d Waves::velocity_W(const Eigen::Vector3d& p_W, double t) const { return kinematics(p_W, t).velocity_W; }

Eigen::Vector3d Waves::acceleration_W(const Eigen::Vector3d& p_W, double t) const {
  return kinematics(p_W, t).acceleration_W;
}

double Waves::dynamic_pressure(const Eigen::Vector3d& p_W, double t) const {
  return kinematics(p_W, t).dynamic_pressure;
}

}  // namespace hadal::physics
