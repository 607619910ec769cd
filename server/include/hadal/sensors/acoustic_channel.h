// The acoustic channel between two points of the water column, for acoustic positioning and
// communications (USBL, LBL, modems; docs/ARCHITECTURE.md, "Acoustic positioning"): the same ocean the
// sonars hear (physics/ocean.h), so a link degrades with range, frequency, depth and noise as they do.
//
// Travel time along the straight ray from a to b (refraction, i.e. ray bending, is left out):
//   t = |b - a| / c_bar,  c_bar = (d_b - d_a) / integral_{d_a}^{d_b} dd / c(d)
// c_bar is the harmonic mean of the sound speed over the path: along a straight ray the slowness 1/c
// is averaged uniformly in depth. integral dd / c is tabulated once from the surface to 11 km at 1 m
// nodes (composite Simpson on 8 sub-intervals, then cubic Hermite interpolation with the exact slopes
// 1 / c at the nodes: relative error ~1e-12 for any CTD profile); a path within 1 mm of horizontal takes
// c at its depth.
//
// Transmission loss (one way, dB re 1 m): TL = k 10 log10(r / 1 m) + alpha_bar r, with r >= 1 m,
// k = world.acoustics.spreading_exponent (2: spherical, 1.5: "practical", 1: cylindrical) and alpha_bar
// Francois–Garrison absorption (physics/seawater.h) at the frequency averaged over the path's depths
// (8-point Gauss–Legendre in depth).
//
// Ambient noise: Wenz's curves in the closed forms of Coates (1990) as used by Stojanovic (2007, "On the
// relationship between capacity and distance in an underwater acoustic communication channel"), power
// spectral densities in dB re 1 uPa^2/Hz with f in kHz:
//   turbulence  17 - 30 log10 f
//   shipping    40 + 20 (s - 0.5) + 26 log10 f - 60 log10(f + 0.03)      s: shipping activity in [0, 1]
//   wind        50 + 7.5 w^(1/2) + 20 log10 f - 40 log10(f + 0.4)         w: wind speed [m/s]
//   thermal     -15 + 20 log10 f
// summed as powers; a receiver's noise level NL is the sum integrated over its band [f0 - B/2, f0 + B/2]
// (composite Simpson, 64 intervals), dB re 1 uPa^2. The noise is the same at every depth (Wenz's curves
// are for the deep ocean's ambient field).
//
// Signal-to-noise ratio of a receiver (passive sonar equation): SNR = SL - TL - NL + DI [dB].
//
// Occlusion: the straight path is blocked when the seabed or a third body lies on it. Two rays, one
// from each end, each passing through its own end's body (the device's hull): a first hit at h_a from a
// and h_b from b with h_a + h_b < |b - a| means something lies between the two bodies; with nothing
// between, each ray reaches the other end's body, so h_a + h_b is close to 2 |b - a|. Devices must be in
// the water, not inside the seabed.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "hadal/render/acoustics_spec.h"

namespace hadal {
struct SimState;
}
namespace hadal::physics {
class Ocean;
}
namespace hadal::geometry {
class SceneRays;
}

namespace hadal::sensors {

// Wenz's ambient noise power spectral density at f [Hz] [dB re 1 uPa^2/Hz] (above).
double ambient_noise_psd_db(double frequency_hz, const AmbientNoiseSpec& noise);
// Its integral over [f0 - B/2, f0 + B/2] [dB re 1 uPa^2]; f0 > B/2 > 0.
double ambient_noise_level_db(double frequency_hz, double bandwidth_hz, const AmbientNoiseSpec& noise);

class AcousticChannel {
 public:
  AcousticChannel(const physics::Ocean& ocean, const AcousticsSpec& acoustics);

  // Harmonic-mean sound speed along the straight path a -> b (points in W) [m/s].
  double mean_sound_speed(const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb) const;
  // One-way travel time a -> b [s].
  double travel_time(const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb) const;
  // One-way transmission loss at frequency f [dB].
  double transmission_loss_db(const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb, double frequency_hz) const;
  // Absorption averaged over the path's depths [dB/m].
  double mean_absorption_db_per_m(const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb,
                                  double frequency_hz) const;
  // The ambient noise level in a receiver's band [dB re 1 uPa^2].
  double noise_level_db(double frequency_hz, double bandwidth_hz) const {
    return ambient_noise_level_db(frequency_hz, bandwidth_hz, acoustics_.ambient_noise);
  }

  // When the wavefront emitted at time t_emit from p_Wemit reaches a receiver that moves linearly from
  // p_W0 at t0 to p_W1 at t1 (t0 < t1): the time in (max(t0, t_emit), t1] where
  //   c_bar (t - t_emit) = |p(t) - p_Wemit|,
  // to 1e-10 s (a safeguarded secant search), or nullopt when it arrives after t1 (or arrived before t0:
  // the caller tracks what has arrived).
  std::optional<double> arrival(double t_emit, const Eigen::Vector3d& p_Wemit, double t0, const Eigen::Vector3d& p_W0,
                                double t1, const Eigen::Vector3d& p_W1) const;

  // Whether the straight path between a (on ray body `body_a`) and b (on `body_b`) is blocked (above).
  static bool occluded(geometry::SceneRays& rays, const SimState& state, const Eigen::Vector3d& p_Wa, int body_a,
                       const Eigen::Vector3d& p_Wb, int body_b);

  // Depth spacing of the slowness table [m] and the depth it covers.
  static constexpr double kTableStep = 1.0;
  static constexpr double kTableDepth = 11000.0;

 private:
  // integral_0^d dd' / c(d') [s/m * m = s], d clamped into the table (above the surface: c at 0).
  double slowness_integral(double depth) const;

  const physics::Ocean& ocean_;
  AcousticsSpec acoustics_;
  std::vector<double> integral_;  // at the nodes k * kTableStep
  std::vector<double> slowness_;  // 1 / c at the nodes [s/m]
};

}  // namespace hadal::sensors
