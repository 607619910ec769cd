// Ocean: the water column a scenario defines (YAML `world.water`, hadal::WaterSpec) — surface height,
// density, hydrostatic pressure, temperature, salinity, sound speed, compression factor and currents.
// Immutable after construction; every const query is thread-safe and a pure function of its arguments.
//
// Depth below the surface d = surface_z - z_W [m]. Above the surface (d < 0) the properties are those at
// d = 0 (pressure = atmospheric): the hydrodynamics kernel clips faces at the surface anyway.
//
// Density, by `density_model`:
//   constant  rho = density.
//   ramp      rho(d) = rho0 + drho_pyc * min(d, d_pyc) / d_pyc (the paper's pycnocline model).
//   ctd       temperature T(d) and practical salinity S(d) interpolated linearly between CTD rows (held
//             constant above the first and below the last), rho(d) = EOS-80(S, T68, p(d)) (seawater.h).
// Hydrostatic pressure p(d) = p_atm + integral_0^d rho(s) g ds (absolute, Pa):
//   constant  p_atm + rho g d;
//   ramp      p_atm + g (rho0 d + drho d^2 / (2 d_pyc)) for d <= d_pyc, then linear with rho0 + drho;
//   ctd       density depends on pressure, so p and rho are marched together (classic RK4 on
//             dp/dd = g rho(S(d), T(d), p)) on a 0.5 m grid from 0 to 11 km, tabulated once; queries use
//             cubic Hermite interpolation of p (slopes rho g, exact at the nodes) and linear rho. Beyond
//             11 km the last density is held.
// Temperature and salinity: the CTD profile, else the constants `temperature_degc` / `salinity`.
// Sound speed: Chen & Millero (UNESCO 1983) at (S, T68, sea pressure (p - p_atm) / 1e4 dbar).
// Compression factor kappa(d) = 1 - p(d) / K (paper; K = bulk_modulus, default 2.2e9 Pa), p absolute.
//
// Current at p_W and sim time t [s], in W [m/s]:
//   v(p_W, t) = uniform + shear_surface * exp(-d / decay_depth) + g(t).
//   The exponential shear is a smooth boundary-layer-like decay: full strength at the surface, 37 % at one
//   decay depth, < 1 % below 4.6 decay depths; it has no kink (unlike a linear ramp to zero), so the
//   forces a vehicle feels while diving are smooth.
//   g(t) is a first-order Gauss-Markov (Ornstein-Uhlenbeck) process per axis, uniform in space, with
//   stationary std sigma and time constant tau: on the grid t_k = k h, h = tau / 64, exact discretisation
//   g_{k+1} = phi g_k + sigma sqrt(1 - phi^2) w_k, phi = exp(-h / tau), g_0 ~ N(0, sigma^2), w_k ~ N(0, 1)
//   from a std::mt19937_64 seeded with splitmix64(seed ^ fnv1a("ocean_current")); linear interpolation
//   in between (lowers the std by at most 0.4 %, at mid-interval). The grid is generated lazily in chunks,
//   always in order from t = 0 under a lock, so a value depends only on (seed, t) — not on which caller
//   asked first. Memory: 24 bytes per grid step, i.e. 24 * 64 / tau bytes per simulated second. t < 0
//   reads g(0).
//
// Waves (YAML `world.waves`, physics/waves.h): the sea state on the surface, built from the world's spec and seed.
// The properties above are those of the mean surface.
//
// YAML keys: physics::water_keys() (server/src/physics/water_spec.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "hadal/core/model.h"
#include "hadal/physics/waves.h"

namespace hadal::physics {

class Ocean {
 public:
  // The model's water; g = |world.gravity_W| (9.80665 m/s^2 if zero), seed = world.seed.
  explicit Ocean(const WorldSpec& world);
  Ocean(const WaterSpec& water, double gravity, std::uint64_t seed);
  ~Ocean();
  Ocean(Ocean&&) noexcept;
  Ocean& operator=(Ocean&&) noexcept;
  Ocean(const Ocean&) = delete;
  Ocean& operator=(const Ocean&) = delete;

  const WaterSpec& spec() const { return water_; }
  // The sea state (a flat surface unless world.waves says otherwise).
  const Waves& waves() const { return waves_; }
  // The instantaneous surface's height at (x, y) and sim time t [m, W]: surface_z without waves.
  double surface_height(double x, double y, double t) const {
    return waves_.enabled() ? waves_.surface_height(x, y, t) : water_.surface_z;
  }
  // The instantaneous surface at (x, y) as its height [m, W] and slopes d eta / dx, d eta / dy (flat without waves).
  void surface_tangent(double x, double y, double t, double* height, Eigen::Vector2d* slope) const;
  // How far the unit ray p_W + s d_W runs under water before it meets the surface [m]: the instantaneous surface's
  // tangent plane over p_W (flat without waves). +inf when p_W is above the surface or the ray does not rise toward
  // the plane. An acoustic beam (a DVL's) reflects there.
  double range_to_surface(const Eigen::Vector3d& p_W, const Eigen::Vector3d& d_W, double t) const;
  // Absolute pressure at p_W and sim time t [Pa]: hydrostatic below the mean surface (pressure(depth)), plus the
  // waves' dynamic pressure, and between the mean surface and a crest rho(0) g times the height of water above;
  // atmospheric above the instantaneous surface.
  double pressure_at(const Eigen::Vector3d& p_W, double t) const;
  // Absolute hydrostatic pressure at depth d [Pa], continued above the mean surface (d < 0) with the surface's
  // gradient, p_atm + rho(0) g d: what the waves' dynamic pressure is added to under a crest.
  double signed_pressure(double depth) const {
    return depth >= 0.0 ? pressure(depth) : water_.atmospheric_pressure + density(0.0) * gravity_ * depth;
  }
  double surface_z() const { return water_.surface_z; }
  double gravity() const { return gravity_; }
  double atmospheric_pressure() const { return water_.atmospheric_pressure; }
  double bulk_modulus() const { return water_.bulk_modulus; }
  // d = surface_z - z_W [m].
  double depth(double z_W) const { return water_.surface_z - z_W; }

  // Properties at depth d [m] below the surface.
  double density(double depth) const;      // [kg/m^3]
  double pressure(double depth) const;     // absolute [Pa]
  double temperature(double depth) const;  // ITS-90 [degC]
  double salinity(double depth) const;     // practical salinity
  double sound_speed(double depth) const;  // [m/s]
  // Sound absorption at frequency f [Hz] [dB/m]: Francois & Garrison (1982) at the water's temperature,
  // salinity, depth and pH (physics/seawater.h).
  double sound_absorption_db_per_m(double depth, double frequency_hz) const;
  double kappa(double depth) const;        // 1 - p(d) / K

  // Current [m/s] in W at p_W and sim time t [s].
  Eigen::Vector3d current_W(const Eigen::Vector3d& p_W, double t) const;
  // The Gauss-Markov part alone (zero when sigma is zero).
  Eigen::Vector3d gauss_markov_current_W(double t) const;

  // Batch sampling for the hydrodynamics kernel (structure of arrays, n points at heights z_W[i]):
  // rho[i] = density, pressure[i] = p - pressure_offset [Pa] (subtracted in double before rounding to
  // float: pass e.g. p at the body's centre to keep float precision at depth). Either output may be null.
  void sample(const float* z_W, std::size_t n, float* rho, float* pressure, double pressure_offset = 0.0) const;
  // Currents at n points (x_W, y_W, z_W) and time t into (vx_W, vy_W, vz_W) [m/s]. Where the current is
  // the same everywhere (current_varies_in_space() false) the points are not read and may be null.
  bool current_varies_in_space() const;
  void sample_current(const float* x_W, const float* y_W, const float* z_W, std::size_t n, double t,
                      float* vx_W, float* vy_W, float* vz_W) const;

  // Depth spacing of the CTD pressure table [m], and the depth it covers.
  static constexpr double kTableStep = 0.5;
  static constexpr double kTableDepth = 11000.0;
  // The CTD table (empty for the other density models): absolute pressure [Pa] and density [kg/m^3] at
  // the depths k * kTableStep, k = 0 .. kTableDepth / kTableStep. pressure() and density() interpolate it;
  // OceanFluid::sample evaluates the same interpolants for a batch of points.
  const std::vector<double>& table_pressure() const { return table_pressure_; }
  const std::vector<double>& table_density() const { return table_density_; }

 private:
  struct GaussMarkovTrack;

  void build_ctd_table();
  // CTD temperature (ITS-90) and salinity at depth d (clamped into the table).
  void ctd_at(double depth, double* temperature, double* salinity) const;

  WaterSpec water_;
  double gravity_ = 9.80665;
  // CTD: pressure [Pa] and density at depths k * kTableStep.
  std::vector<double> table_pressure_;
  std::vector<double> table_density_;
  std::unique_ptr<GaussMarkovTrack> gauss_markov_;  // null when sigma is zero
  Waves waves_;
};

}  // namespace hadal::physics
