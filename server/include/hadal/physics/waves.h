// Waves: the sea state of a scenario (YAML `world.waves`, WaveSpec) as a sum of linear (Airy) wave components over
// water of finite depth (docs/ARCHITECTURE.md, "Waves"). Immutable after construction; every query is const,
// thread-safe and a pure function of its arguments.
//
// Components. A spectrum (JONSWAP, or Pierson-Moskowitz: JONSWAP with gamma = 1) is sampled into N components:
//   S(omega) = alpha g^2 omega^-5 exp(-5/4 (omega_p / omega)^4) gamma^r,  r = exp(-(omega - omega_p)^2 / (2 sigma^2
//   omega_p^2)), sigma = 0.07 below omega_p and 0.09 above, omega_p = 2 pi / Tp, alpha such that the spectrum's
//   m0 = integral S = (Hs / 4)^2 (the integral taken numerically, so Hs is exact for any gamma).
// The band [0.5 omega_p, 4 omega_p] (all but ~1e-4 of the energy for gamma in [1, 7]) is cut into N equal bins; each
// component sits at a seeded random frequency within its bin (so the record does not repeat after 2 pi / d_omega)
// with the amplitude a_i = sqrt(2 S(omega_i) d_omega), rescaled so that sum a_i^2 / 2 = (Hs / 4)^2 exactly, a seeded
// uniform phase and, with `spreading` s, a direction drawn from the cos^2s((theta - theta_0) / 2) distribution around
// the mean direction theta_0 (one direction per frequency: no phase-locked standing patterns); without it every
// component travels along theta_0 (long-crested). Or the scenario lists its components (`regular`). Random draws
// come from a std::mt19937_64 seeded with splitmix64(seed ^ fnv1a("waves")): same seed, same waves, same bytes.
//
// Kinematics, for the mean surface z = surface_z and the depth h below it (`depth`; infinite: deep water), each
// component's wave number from the dispersion relation omega^2 = g k tanh(k h) (Newton), phase
// theta_i = k_i (x cos beta_i + y sin beta_i) - omega_i t + phi_i:
//   elevation          eta = sum a_i cos theta_i
//   orbital velocity   u_h = sum a_i omega_i cosh(k_i (z' + h)) / sinh(k_i h) cos theta_i (cos beta_i, sin beta_i)
//                      w   = sum a_i omega_i sinh(k_i (z' + h)) / sinh(k_i h) sin theta_i
//   acceleration       the time derivatives of those (omega_i times, phase advanced by pi / 2)
//   dynamic pressure   p_d = rho g sum a_i cosh(k_i (z' + h)) / cosh(k_i h) cos theta_i
// with z relative to the mean surface and, above it, Wheeler stretching: the water column [-h, eta] is mapped onto
// [-h, 0] by z' = h (z - eta) / (h + eta) (deep water: z' = z - eta), so that at the instantaneous surface the
// kinematics are those linear theory gives at the mean level and the total pressure -rho g z + p_d is zero there.
// Build-up: every quantity is multiplied by r(t) = (1 - cos(pi t / T_r)) / 2 for t < T_r (`ramp_time`), 1 after (the
// acceleration also gets r'(t) times the velocity), so that bodies starting at rest in calm water are not thrown into
// a sea already moving (a floating body let go in full orbital flow keeps the velocity difference as a drift).
// Above the instantaneous surface there is no water: velocity, acceleration and dynamic pressure are zero. Deep
// water uses exp(k z') for the ratios. Everything decays with depth as those ratios do: at z < -lambda / 2 a
// component keeps < 5 % of its surface value, and at z < -lambda less than 0.2 %.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "hadal/config/key_table_fwd.h"

namespace hadal::physics {

enum class WaveSpectrum { kNone, kJonswap, kPiersonMoskowitz, kRegular };

// One listed component (`regular:`).
struct WaveComponentSpec {
  double amplitude = 0.0;  // [m]
  double period = 0.0;     // [s]
  double direction = 0.0;  // the way it travels, from W's x axis toward y [rad]
  double phase = 0.0;      // [rad]
};

struct WaveSpec {
  WaveSpectrum spectrum = WaveSpectrum::kNone;
  double significant_height = 0.0;  // Hs [m]
  double peak_period = 0.0;         // Tp [s]
  double gamma = 3.3;               // JONSWAP peak enhancement
  double direction = 0.0;           // mean direction the waves travel toward, from W's x axis toward y [rad]
  std::optional<double> spreading;  // s of cos^2s((theta - theta_0) / 2); none: long-crested
  int components = 128;             // N
  std::vector<WaveComponentSpec> regular;  // spectrum kRegular
  // Water depth for the dispersion relation and the kinematics' decay [m]; infinite: deep water.
  double depth = std::numeric_limits<double>::infinity();
  // The build-up from calm water at t = 0 [s]; none: two peak periods (two of the longest listed period).
  std::optional<double> ramp_time;

  bool enabled() const { return spectrum != WaveSpectrum::kNone; }
};
const config::KeyTable<WaveSpec>& wave_keys();

// The largest number of components a sea state may have (`components`, `regular`).
inline constexpr int kMaxWaveComponents = 2048;

// A component as the waves use it.
struct WaveComponent {
  double amplitude = 0.0;  // a [m]
  double omega = 0.0;      // [rad/s]
  double k = 0.0;          // wave number [rad/m]
  double direction = 0.0;  // beta [rad]
  double phase = 0.0;      // phi [rad]
  // Derived once (Waves' constructor): cos beta, sin beta and the wave vector k (cos beta, sin beta) [rad/m].
  double cos_b = 1.0, sin_b = 0.0, k_x = 0.0, k_y = 0.0;
};

// The wave number of frequency omega in water of depth h (infinite: omega^2 / g).
double wave_number(double omega, double depth, double g);

// The JONSWAP spectral density at omega [m^2 s] for unit alpha (multiply by alpha).
double jonswap_shape(double omega, double omega_p, double gamma, double g);

// Everything the waves are at one point and instant (Waves::kinematics), from one pass over the components for the
// surface over the point and one for the water there; zero (and wet false) above the surface.
struct WaveKinematics {
  double surface_height = 0.0;                          // eta over the point, W [m]
  Eigen::Vector2d slope = Eigen::Vector2d::Zero();       // d eta / dx, d eta / dy
  bool wet = false;                                     // the point is at or below the surface
  double dynamic_pressure = 0.0;                        // p_d [Pa]
  Eigen::Vector3d pressure_gradient_W = Eigen::Vector3d::Zero();  // grad p_d, analytic (through Wheeler's z') [Pa/m]
  Eigen::Vector3d velocity_W = Eigen::Vector3d::Zero();           // orbital velocity [m/s]
  Eigen::Vector3d acceleration_W = Eigen::Vector3d::Zero();       // its rate [m/s^2]
};

class Waves {
 public:
  // No waves (a flat surface at surface_z).
  Waves() = default;
  Waves(const WaveSpec& spec, double surface_z, double density, double g, std::uint64_t seed);

  bool enabled() const { return !components_.empty(); }
  const std::vector<WaveComponent>& components() const { return components_; }
  double surface_z() const { return surface_z_; }
  double depth() const { return depth_; }
  double density() const { return density_; }  // rho of the dynamic pressure rho g ... [kg/m^3]
  double ramp_time() const { return ramp_time_; }  // T_r [s]
  // The build-up factor r(t) in [0, 1] and its rate [1/s].
  double ramp(double t) const;
  double ramp_rate(double t) const;
  // 4 sqrt(sum a_i^2 / 2): the components' significant height [m].
  double significant_height() const;

  // The surface's height at (x, y) and sim time t [m, W].
  double surface_height(double x, double y, double t) const;
  // Its slopes d eta / dx, d eta / dy there.
  Eigen::Vector2d surface_slope(double x, double y, double t) const;
  // Orbital velocity and acceleration of the water at p_W [m/s, m/s^2, W]; zero above the surface.
  Eigen::Vector3d velocity_W(const Eigen::Vector3d& p_W, double t) const;
  Eigen::Vector3d acceleration_W(const Eigen::Vector3d& p_W, double t) const;
  // The elevation relative to the mean level and its slopes at (x, y), in one pass.
  void surface(double x, double y, double t, double* eta, Eigen::Vector2d* slope) const;
  // Both at once.
  void orbital(const Eigen::Vector3d& p_W, double t, Eigen::Vector3d* v_W, Eigen::Vector3d* a_W) const;
  // All of it at once, with the dynamic pressure's gradient.
  WaveKinematics kinematics(const Eigen::Vector3d& p_W, double t) const;
  // The wave's dynamic pressure at p_W [Pa] (add the hydrostatic rho g (surface_z - z)); zero above the surface.
  double dynamic_pressure(const Eigen::Vector3d& p_W, double t) const;

 private:
  // Wheeler's stretched height below the mean level of a point z_rel below the surface eta (relative to the mean
  // level) [m].
  double stretched(double z_rel, double eta) const;
  // Each component's cos_b, sin_b and wave vector from its direction and k.
  void derive();
  std::vector<WaveComponent> components_;
  double surface_z_ = 0.0;
  double density_ = 1025.0;
  double g_ = 9.80665;
  double depth_ = std::numeric_limits<double>::infinity();
  double ramp_time_ = 0.0;
};

}  // namespace hadal::physics
