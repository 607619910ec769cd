#include "hadal/sensors/acoustic_channel.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "hadal/core/state.h"
#include "hadal/geometry/scene_rays.h"
#include "hadal/physics/ocean.h"

namespace hadal::sensors {

namespace {

// 8-point Gauss–Legendre nodes and weights on [-1, 1].
constexpr std::array<double, 8> kGaussNodes = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                               -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                               0.7966664774136267,  0.9602898564975363};
constexpr std::array<double, 8> kGaussWeights = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                                 0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                                 0.2223810344533745, 0.1012285362903763};

// Below this depth difference [m] a path is horizontal: c and alpha at its depth.
constexpr double kHorizontal = 1e-3;

}  // namespace

double ambient_noise_psd_db(double frequency_hz, const AmbientNoiseSpec& noise) {
  const double f = frequency_hz / 1000.0;  // [kHz]
  const double lf = std::log10(f);
  const double turbulence = 17.0 - 30.0 * lf;
  const double shipping = 40.0 + 20.0 * (noise.shipping - 0.5) + 26.0 * lf - 60.0 * std::log10(f + 0.03);
  const double wind = 50.0 + 7.5 * std::sqrt(noise.wind_speed) + 20.0 * lf - 40.0 * std::log10(f + 0.4);
  const double thermal = -15.0 + 20.0 * lf;
  double power = 0.0;
  for (const double level : {turbulence, shipping, wind, thermal}) power += std::pow(10.0, level / 10.0);
  return 10.0 * std::log10(power);
}

double ambient_noise_level_db(double frequency_hz, double bandwidth_hz, const AmbientNoiseSpec& noise) {
  constexpr int kIntervals = 64;  // even: composite Simpson
  const double f_low = frequency_hz - 0.5 * bandwidth_hz;
  const double h = bandwidth_hz / kIntervals;
  double sum = 0.0;
  for (int i = 0; i <= kIntervals; ++i) {
    const double weight = (i == 0 || i == kIntervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    sum += weight * std::pow(10.0, ambient_noise_psd_db(f_low + i * h, noise) / 10.0);
  }
  return 10.0 * std::log10(sum * h / 3.0);
}

AcousticChannel::AcousticChannel(const physics::Ocean& ocean, const AcousticsSpec& acoustics)
    : ocean_(ocean), acoustics_(acoustics) {
  const std::size_t nodes = static_cast<std::size_t>(kTableDepth / kTableStep) + 1;
  integral_.resize(nodes);
  slowness_.resize(nodes);
  constexpr int kSub = 4;  // Simpson intervals per table step
  const double h = kTableStep / kSub;
  slowness_[0] = 1.0 / ocean_.sound_speed(0.0);
  integral_[0] = 0.0;
  for (std::size_t k = 1; k < nodes; ++k) {
    const double d0 = static_cast<double>(k - 1) * kTableStep;
    double sum = slowness_[k - 1];
    for (int i = 1; i < kSub; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) / ocean_.sound_speed(d0 + i * h);
    slowness_[k] = 1.0 / ocean_.sound_speed(static_cast<double>(k) * kTableStep);
    sum += slowness_[k];
    integral_[k] = integral_[k - 1] + sum * h / 3.0;
  }
}

double AcousticChannel::slowness_integral(double depth) const {
  const double d = std::clamp(depth, 0.0, kTableDepth);
  const std::size_t k = std::min(static_cast<std::size_t>(d / kTableStep), integral_.size() - 2);
  const double h = kTableStep;
  const double s = (d - static_cast<double>(k) * h) / h;
  // Cubic Hermite on [k, k+1] with values integral_ and slopes slowness_.
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  return h00 * integral_[k] + h10 * h * slowness_[k] + h01 * integral_[k + 1] + h11 * h * slowness_[k + 1];
}

double AcousticChannel::mean_sound_speed(const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb) const {
  const double d_a = ocean_.depth(p_Wa.z()), d_b = ocean_.depth(p_Wb.z());
  if (std::abs(d_b - d_a) < kHorizontal) return ocean_.sound_speed(std::max(0.5 * (d_a + d_b), 0.0));
  const double above = std::min(d_a, d_b), below = std::max(d_a, d_b);
  // Above the surface the water's properties are those at the surface (physics/ocean.h).
  const double integral = slowness_integral(below) - slowness_integral(above) +
                          (std::min(below, 0.0) - std::min(above, 0.0)) * slowness_[0];
  return (below - above) / integral;
}

double AcousticChannel::travel_time(const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb) const {
  return (p_Wb - p_Wa).norm() / mean_sound_speed(p_Wa, p_Wb);
}

double AcousticChannel::mean_absorption_db_per_m(const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb,
                                                 double frequency_hz) const {
  const double d_a = ocean_.depth(p_Wa.z()), d_b = ocean_.depth(p_Wb.z());
  if (std::abs(d_b - d_a) < kHorizontal) return ocean_.sound_absorption_db_per_m(0.5 * (d_a + d_b), frequency_hz);
  double sum = 0.0;
  for (std::size_t i = 0; i < kGaussNodes.size(); ++i) {
    const double d = 0.5 * (d_a + d_b) + 0.5 * (d_b - d_a) * kGaussNodes[i];
    sum += kGaussWeights[i] * ocean_.sound_absorption_db_per_m(d, frequency_hz);
  }
  return 0.5 * sum;
}

double AcousticChannel::transmission_loss_db(const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb,
                                             double frequency_hz) const {
  const double r = std::max((p_Wb - p_Wa).norm(), 1.0);
  return acoustics_.spreading_exponent * 10.0 * std::log10(r) + mean_absorption_db_per_m(p_Wa, p_Wb, frequency_hz) * r;
}

std::optional<double> AcousticChannel::arrival(double t_emit, const Eigen::Vector3d& p_Wemit, double t0,
                                               const Eigen::Vector3d& p_W0, double t1,
                                               const Eigen::Vector3d& p_W1) const {
  if (!(t1 > t_emit)) return std::nullopt;
  const auto position = [&](double t) -> Eigen::Vector3d {
    const double s = (t - t0) / (t1 - t0);
    return p_W0 + s * (p_W1 - p_W0);
  };
  // g(t) = c_bar (t - t_emit) - |p(t) - p_emit|: negative before the wavefront arrives.
  const auto g = [&](double t) {
    const Eigen::Vector3d p = position(t);
    return mean_sound_speed(p_Wemit, p) * (t - t_emit) - (p - p_Wemit).norm();
  };
  double a = std::max(t0, t_emit);
  double b = t1;
  double g_a = g(a);
  double g_b = g(b);
  if (g_b < 0.0) return std::nullopt;   // not yet
  if (g_a >= 0.0) return std::nullopt;  // already arrived (before this interval)
  // Illinois (safeguarded regula falsi): the bracket shrinks every step, superlinearly near the root.
  int side = 0;
  for (int i = 0; i < 100 && b - a > 1e-10; ++i) {
    double t = (a * g_b - b * g_a) / (g_b - g_a);
    if (!(t > a && t < b)) t = 0.5 * (a + b);
    const double g_t = g(t);
    if (g_t >= 0.0) {
      b = t;
      g_b = g_t;
      if (side == -1) g_a *= 0.5;
      side = -1;
    } else {
      a = t;
      g_a = g_t;
      if (side == 1) g_b *= 0.5;
      side = 1;
    }
  }
  return b;
}

bool AcousticChannel::occluded(geometry::SceneRays& rays, const SimState& state, const Eigen::Vector3d& p_Wa,
                               int body_a, const Eigen::Vector3d& p_Wb, int body_b) {
  const Eigen::Vector3d ab = p_Wb - p_Wa;
  const double distance = ab.norm();
  if (distance < 1e-6) return false;
  const Eigen::Vector3d u = ab / distance;
  const double h_a = rays.cast(state, p_Wa, std::array<Eigen::Vector3d, 1>{u}, body_a, distance)[0];
  if (!(h_a < distance)) return false;  // nothing at all between a and b
  const double h_b = rays.cast(state, p_Wb, std::array<Eigen::Vector3d, 1>{-u}, body_b, distance)[0];
  return h_a + std::min(h_b, distance) < distance;
}

}  // namespace hadal::sensors
