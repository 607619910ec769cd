#include "hadal/render/sonar.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hadal/core/value_noise.h"
#include "hadal/geometry/embree_scene.h"
#include "hadal/geometry/ray_batch.h"

namespace hadal::render {

namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

// A uniform in (0, 1] from a 64-bit hash: never 0, so that its log is finite.
double unit_open(std::uint64_t h) { return (static_cast<double>(h >> 11) + 1.0) * 0x1.0p-53; }

double db_to_linear(double db) { return std::pow(10.0, db / 10.0); }

// The key of beam `beam` of ping `ping_index`; its grid lines' jitter uses hashes of key ^ kLineU and
// key ^ kLineV plus the line, its speckle and noise those of key ^ kBinStream plus 4 bin + j.
std::uint64_t beam_key(std::uint64_t noise_key, std::uint64_t ping_index, int beam) {
  return splitmix64(splitmix64(noise_key ^ splitmix64(ping_index)) + static_cast<std::uint64_t>(beam));
}
constexpr std::uint64_t kBinStream = 0x5bd1e9955bd1e995ull;
constexpr std::uint64_t kLineU = 0x2545f4914f6cdd1dull;  // the grid lines' jitter
constexpr std::uint64_t kLineV = 0x9e6c63d0676a9a99ull;

void invalid(const std::string& what) { throw std::invalid_argument("sonar: " + what); }


}  // namespace

void cos_sin_near(double cos_c, double sin_c, double delta, double& cos_out, double& sin_out) {
  const double d2 = delta * delta;
  const double cos_d = 1.0 - d2 * (1.0 / 2.0 - d2 * (1.0 / 24.0 - d2 * (1.0 / 720.0)));
  const double sin_d = delta * (1.0 - d2 * (1.0 / 6.0 - d2 * (1.0 / 120.0 - d2 * (1.0 / 5040.0))));
  cos_out = cos_c * cos_d - sin_c * sin_d;
  sin_out = sin_c * cos_d + cos_c * sin_d;
}

Eigen::Vector3d SonarBeam::direction_S(double a, double e) const {
  return std::cos(e) * (std::cos(a) * axis_S + std::sin(a) * u_S) + std::sin(e) * v_S();
}

double SonarBeam::pattern(double a, double e) const {
  const double x = 2.0 * a / width_u_rad, y = 2.0 * e / width_v_rad;
  return std::exp2(-(x * x + y * y));
}

std::vector<SonarBeam> fan_beams(int count, double fov, double width_u, double width_v) {
  std::vector<SonarBeam> beams;
  for (int k = 0; k < count; ++k) {
    const double phi = -0.5 * fov + (k + 0.5) * fov / count;
    SonarBeam b;
    b.axis_S = Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0);
    b.u_S = Eigen::Vector3d(-std::sin(phi), std::cos(phi), 0.0);
    b.width_u_rad = width_u;
    b.width_v_rad = width_v;
    beams.push_back(b);
  }
  return beams;
}

int SonarPingSpec::bin_of(double r) const {
  if (!(r >= min_range && r < max_range)) return -1;
  const int bin = static_cast<int>((r - min_range) / bin_size_m());
  return std::min(bin, bins - 1);
}

void SonarPingSpec::validate() const {
  if (beams.empty()) invalid("no beams");
  for (std::size_t k = 0; k < beams.size(); ++k) {
    const SonarBeam& b = beams[k];
    const std::string name = "beam " + std::to_string(k) + ": ";
    if (!b.axis_S.allFinite() || std::abs(b.axis_S.norm() - 1.0) > 1e-9) invalid(name + "axis is not a unit vector");
    if (!b.u_S.allFinite() || std::abs(b.u_S.norm() - 1.0) > 1e-9 || std::abs(b.axis_S.dot(b.u_S)) > 1e-9) {
      invalid(name + "u is not a unit vector perpendicular to the axis");
    }
    if (!(b.width_u_rad > 0.0 && b.width_u_rad < 3.2 && b.width_v_rad > 0.0 && b.width_v_rad < 3.2)) {
      invalid(name + "widths must be in (0, pi]");
    }
    if (!(b.sampled_v_rad >= 0.0 && b.sampled_v_rad < 3.2)) invalid(name + "the sampled extent must be in [0, pi]");
  }
  if (!(min_range >= 0.0 && max_range > min_range && std::isfinite(max_range))) {
    invalid("the range window must satisfy 0 <= min_range < max_range < inf");
  }
  if (bins < 1 || rays_u < 1 || rays_v < 1) invalid("bins, rays_u and rays_v must be >= 1");
  for (double v : {source_level_db, noise_level_db, spreading_db_per_decade, tvg_spreading_db_per_decade}) {
    if (!std::isfinite(v)) invalid("levels and spreading coefficients must be finite");
  }
}

double transmission_loss_db(const SonarPingSpec& spec, const SonarWater& water, double r) {
  return spec.spreading_db_per_decade * std::log10(r) + water.absorption_db_per_m * r;
}

double tvg_db(const SonarPingSpec& spec, const SonarWater& water, double r) {
  return spec.tvg_spreading_db_per_decade * std::log10(r) + (spec.tvg_absorption ? 2.0 * water.absorption_db_per_m * r : 0.0);
}

void ping(const geometry::EmbreeScene& scene, const SonarPingSpec& spec, const Eigen::Isometry3d& X_WS,
          std::int32_t own_body, const SonarWater& water, const BackscatterOfHits& backscatter,
          std::uint64_t noise_key, std::uint64_t ping_index, const ParallelFor& parallel, const BeamEchoSink& sink) {
  spec.validate();
  if (!(water.absorption_db_per_m >= 0.0 && std::isfinite(water.absorption_db_per_m))) {
    invalid("the absorption must be finite and >= 0");
  }
  const int bins = spec.bins;
  const double bin_size = spec.bin_size_m();
  // The loss factor SL r^2 10^(-2 TL(r) / 10) at the bin edges (interpolated per hit), and the TVG per bin
  // centre.
  std::vector<double> loss_at_edge(static_cast<std::size_t>(bins) + 1);
  for (int i = 0; i <= bins; ++i) {
    const double r = std::max(spec.min_range + i * bin_size, 1e-3);
    loss_at_edge[static_cast<std::size_t>(i)] =
        db_to_linear(spec.source_level_db - 2.0 * transmission_loss_db(spec, water, r)) * r * r;
  }
  std::vector<double> tvg(static_cast<std::size_t>(bins));
  for (int b = 0; b < bins; ++b) tvg[static_cast<std::size_t>(b)] = db_to_linear(tvg_db(spec, water, spec.bin_centre_m(b)));
  const double noise_power = spec.receiver_noise ? db_to_linear(spec.noise_level_db) : 0.0;
  const Eigen::Vector3f p_WS = X_WS.translation().cast<float>();
  const Eigen::Matrix3d R_WS = X_WS.linear();
  const float t_far = static_cast<float>(spec.max_range);
  const int rays = spec.rays_u * spec.rays_v;
  // Adds echo e (and e a for the phase) to the bins of the ranges [x0, x1] (in bins from the window's start), in
  // proportion to their overlap: a patch's echo arrives over the range its footprint spans, so every bin it covers
  // gets its share, however sparse the rays are in range (grazing angles, far bins).
  const auto spread = [bins](double x0, double x1, double e, double a, std::vector<double>& echo,
                             std::vector<double>& echo_a) {
    const int b0 = std::max(0, static_cast<int>(std::floor(x0))), b1 = std::min(bins - 1, static_cast<int>(std::floor(x1)));
    if (b0 == b1 || !(x1 > x0)) {
      const int b = std::clamp(static_cast<int>(std::floor(0.5 * (x0 + x1))), 0, bins - 1);
      echo[static_cast<std::size_t>(b)] += e;
      echo_a[static_cast<std::size_t>(b)] += e * a;
      return;
    }
    const double per_bin = e / (x1 - x0);
    for (int b = b0; b <= b1; ++b) {
      const double overlap = std::min<double>(x1, b + 1) - std::max<double>(x0, b);
      if (overlap <= 0.0) continue;
      echo[static_cast<std::size_t>(b)] += per_bin * overlap;
      echo_a[static_cast<std::size_t>(b)] += per_bin * overlap * a;
    }
  };

  // The vertical grid lines' unjittered centres for the first beam's extent, and their cos and sin.
  const auto nv_lines = static_cast<std::size_t>(spec.rays_v);
  const double centre_extent = spec.beams.front().extent_v();
  std::vector<double> centre_e(nv_lines), centre_cos(nv_lines), centre_sin(nv_lines);
  for (std::size_t j = 0; j < nv_lines; ++j) {
    centre_e[j] = -0.5 * centre_extent + (static_cast<double>(j) + 0.5) * (centre_extent / spec.rays_v);
    centre_cos[j] = std::cos(centre_e[j]);
    centre_sin[j] = std::sin(centre_e[j]);
  }
  const double inv_bin_size = 1.0 / bin_size;

  parallel(spec.beams.size(), [&](std::size_t k) {
    const SonarBeam& beam = spec.beams[k];
    const std::uint64_t key = beam_key(noise_key, ping_index, static_cast<int>(k));
    const double du = beam.width_u_rad / spec.rays_u, dv = beam.extent_v() / spec.rays_v;
    // The grid's lines along u and along v, each at a seeded place within its cell (stratified jitter of
    // the lines, not of each cell: the trigonometry and the pattern are then per line, rays_u + rays_v
    // evaluations per beam instead of rays_u x rays_v).
    const auto nu = static_cast<std::size_t>(spec.rays_u), nv = static_cast<std::size_t>(spec.rays_v);
    std::vector<double> offset_a(nu), cos_a(nu), sin_a(nu), weight_a(nu), offset_e(nv), cos_e(nv), sin_e(nv), weight_e(nv);
    // Line k of `width` in cells of `cell`, its jitter from stream `lines`.
    const auto line_at = [&](std::size_t k, double width, double cell, std::uint64_t lines) {
      const double jitter = spec.jitter ? unit_open(splitmix64((key ^ lines) + k)) - 0.5 : 0.0;
      return -0.5 * width + (static_cast<double>(k) + 0.5 + jitter) * cell;
    };
    for (std::size_t i = 0; i < nu; ++i) {
      const double a = line_at(i, beam.width_u_rad, du, kLineU);
      offset_a[i] = a;
      cos_a[i] = std::cos(a);
      sin_a[i] = std::sin(a);
      weight_a[i] = beam.pattern(a, 0.0);
    }
    // The lines' centres are the first beam's (a fan's beams share their vertical extent): their cos and sin are
    // shared, each line's from its centre's (cos_sin_near) when its jitter is small.
    const bool shared = beam.extent_v() == centre_extent;
    for (std::size_t j = 0; j < nv; ++j) {
      const double e = line_at(j, beam.extent_v(), dv, kLineV);
      offset_e[j] = e;
      const double delta = shared ? e - centre_e[j] : 0.0;
      if (shared && std::abs(delta) <= kSmallAngleRad) {
        cos_sin_near(centre_cos[j], centre_sin[j], delta, cos_e[j], sin_e[j]);
      } else {
        cos_e[j] = std::cos(e);
        sin_e[j] = std::sin(e);
      }
      weight_e[j] = beam.pattern(0.0, e) * cos_e[j] * du * dv;  // with dOmega = cos e da de
    }
    const Eigen::Vector3d axis_W = R_WS * beam.axis_S, u_W = R_WS * beam.u_S, v_W = R_WS * beam.v_S();
    geometry::RayBatch batch;
    batch.coherence = geometry::RayCoherence::kCoherent;
    batch.reserve(static_cast<std::size_t>(rays));
    // Rays in v-major order: neighbours share an origin and nearly a direction.
    for (std::size_t j = 0; j < nv; ++j) {
      for (std::size_t i = 0; i < nu; ++i) {
        const Eigen::Vector3d d_W = cos_e[j] * (cos_a[i] * axis_W + sin_a[i] * u_W) + sin_e[j] * v_W;
        batch.add_ray(p_WS, d_W.cast<float>(), 0.0f, t_far, own_body);
      }
    }
    geometry::RayHits hits;
    hits.resize(batch.size());
    scene.intersect(batch, 0, batch.size(), geometry::QueryPath::kAuto, hits);
    std::vector<float> mu(batch.size(), 0.0f);
    backscatter(hits, batch.size(), mu.data());
    if (water.surface) {  // the sea surface where a ray rises to it first (SonarWater)
      const Eigen::Vector3d& m = water.surface_normal_W;
      const double below = m.dot(water.surface_point_W - p_WS.cast<double>());
      for (std::size_t n = 0; below > 0.0 && n < batch.size(); ++n) {
        const double rise = m.x() * batch.d_W_x[n] + m.y() * batch.d_W_y[n] + m.z() * batch.d_W_z[n];
        if (!(rise > 0.0)) continue;
        const double s = below / rise;
        if (!(s < t_far) || (hits.hit(n) && hits.distance[n] <= s)) continue;
        hits.distance[n] = static_cast<float>(s);
        hits.n_W_x[n] = static_cast<float>(m.x());
        hits.n_W_y[n] = static_cast<float>(m.y());
        hits.n_W_z[n] = static_cast<float>(m.z());
        mu[n] = static_cast<float>(water.surface_mu);
      }
    }

    std::vector<double> echo(static_cast<std::size_t>(bins), 0.0), echo_a(static_cast<std::size_t>(bins), 0.0);
    for (std::size_t n = 0; n < batch.size(); ++n) {
      if (!hits.hit(n)) continue;
      const double r = hits.distance[n];
      if (!(r >= spec.min_range && r < spec.max_range)) continue;  // outside the window (SonarPingSpec::bin_of)
      const double x = (r - spec.min_range) * inv_bin_size;          // in bins from the window's start
      const int b = std::min(static_cast<int>(x), bins - 1);
      const Eigen::Vector3d n_W(hits.n_W_x[n], hits.n_W_y[n], hits.n_W_z[n]);
      const std::size_t i = n % nu, j = n / nu;
      const double n_axis = n_W.dot(axis_W), n_u = n_W.dot(u_W), n_v = n_W.dot(v_W);
      const double n_d = cos_e[j] * (cos_a[i] * n_axis + sin_a[i] * n_u) + sin_e[j] * n_v;
      const double cos_theta = std::abs(n_d);
      const double f = x - b;
      const double loss = loss_at_edge[static_cast<std::size_t>(b)] +
                          f * (loss_at_edge[static_cast<std::size_t>(b) + 1] - loss_at_edge[static_cast<std::size_t>(b)]);
      const double e = weight_a[i] * weight_e[j] * mu[n] * cos_theta * loss;
      // The ray's patch spans ranges r +- footprint / 2; the tangent plane's rate r |n . dd| / |n . d| per
      // radian of the grid (dd the direction's derivative along a or e).
      const double n_da = cos_e[j] * (cos_a[i] * n_u - sin_a[i] * n_axis);
      const double n_de = cos_e[j] * n_v - sin_e[j] * (cos_a[i] * n_axis + sin_a[i] * n_u);
      const double inv_cos = 1.0 / std::max(cos_theta, 1e-12);
      // Along one direction: the range to the farther neighbouring ray that hit, its range difference where the
      // surface runs on (within kFootprintJump times the plane's rate times the angle to that ray's line: the
      // lines are jittered), else the plane's value (an edge: the neighbour lies beyond a jump); with no
      // neighbour that hit, the plane over the cell's own angle.
      const auto extent = [&](double rate, const std::vector<double>& line, std::size_t k, std::size_t count,
                              std::size_t stride, double cell) {
        double widest = -1.0;
        for (const int side : {-1, 1}) {
          if ((side < 0 && k == 0) || (side > 0 && k + 1 == count)) continue;
          const std::size_t m = side < 0 ? n - stride : n + stride;
          if (!hits.hit(m)) continue;
          const double plane = rate * std::abs(line[side < 0 ? k - 1 : k + 1] - line[k]);
          const double step = std::abs(static_cast<double>(hits.distance[m]) - r);
          widest = std::max(widest, step <= kFootprintJump * plane ? step : plane);
        }
        return widest < 0.0 ? rate * cell : widest;
      };
      const double along_u = extent(r * std::abs(n_da) * inv_cos, offset_a, i, nu, 1, du);
      const double along_v = extent(r * std::abs(n_de) * inv_cos, offset_e, j, nv, nu, dv);
      const double footprint = std::min(along_u + along_v, kMaxFootprintBins * bin_size);
      const double half_bins = 0.5 * footprint * inv_bin_size;
      spread(x - half_bins, x + half_bins, e, offset_a[i], echo, echo_a);
    }

    std::vector<float> intensity(static_cast<std::size_t>(bins)), mean_a(static_cast<std::size_t>(bins));
    const std::uint64_t bin_key = key ^ kBinStream;
    for (int b = 0; b < bins; ++b) {
      const auto s = static_cast<std::size_t>(b);
      const std::uint64_t h = bin_key + 4 * static_cast<std::uint64_t>(b);
      double received = echo[s];
      if (spec.speckle) {
        // |sqrt(I) s + n|^2 with s, n complex Gaussian: exponential with mean I + noise.
        received = -(echo[s] + noise_power) * std::log(unit_open(splitmix64(h)));
      } else if (noise_power > 0.0) {
        // Rician: the echo's amplitude plus complex Gaussian noise (Box-Muller).
        const double radius = std::sqrt(-std::log(unit_open(splitmix64(h + 1))) * noise_power);
        const double angle = kTwoPi * unit_open(splitmix64(h + 2));
        const double re = std::sqrt(echo[s]) + radius * std::cos(angle), im = radius * std::sin(angle);
        received = re * re + im * im;
      }
      intensity[s] = static_cast<float>(received * tvg[s]);
      mean_a[s] = echo[s] > 0.0 ? static_cast<float>(echo_a[s] / echo[s]) : std::numeric_limits<float>::quiet_NaN();
    }
    sink(BeamEcho{static_cast<int>(k), bins, intensity.data(), mean_a.data()});
  });
}

BottomDetection detect_bottom(const SonarPingSpec& spec, const SonarWater& water, const BeamEcho& echo,
                              double min_snr_db, double window_db) {
  BottomDetection detection;
  const int bins = echo.bins;
  if (bins < 1) return detection;
  // The profile smoothed over kDetectionSmoothingBins (speckle and empty bins between rays fill in).
  std::vector<double> smooth(static_cast<std::size_t>(bins), 0.0);
  const int half = kDetectionSmoothingBins / 2;
  for (int b = 0; b < bins; ++b) {
    double sum = 0.0;
    int count = 0;
    for (int i = std::max(0, b - half); i <= std::min(bins - 1, b + half); ++i, ++count) sum += echo.intensity[i];
    smooth[static_cast<std::size_t>(b)] = sum / count;
  }
  const int peak = static_cast<int>(std::max_element(smooth.begin(), smooth.end()) - smooth.begin());
  const double peak_level = smooth[static_cast<std::size_t>(peak)];
  const double noise =
      spec.receiver_noise ? db_to_linear(spec.noise_level_db + tvg_db(spec, water, spec.bin_centre_m(peak))) : 0.0;
  if (!(peak_level > 0.0) || !(peak_level > noise * db_to_linear(min_snr_db))) return detection;
  const double floor = peak_level * db_to_linear(-window_db);
  int first = peak, last = peak;
  while (first > 0 && smooth[static_cast<std::size_t>(first) - 1] >= floor) --first;
  while (last + 1 < bins && smooth[static_cast<std::size_t>(last) + 1] >= floor) ++last;
  detection.valid = true;
  detection.intensity = peak_level;
  if (last - first + 1 >= kPhaseMinBins) {
    // The zero crossing of the mean offset between consecutive bins that have one, nearest the peak.
    double best = std::numeric_limits<double>::infinity();
    int previous = -1;
    for (int b = first; b <= last; ++b) {
      if (!std::isfinite(echo.mean_offset_u_rad[b])) continue;
      if (previous >= 0) {
        const double a0 = echo.mean_offset_u_rad[previous], a1 = echo.mean_offset_u_rad[b];
        if ((a0 > 0.0) != (a1 > 0.0) && a0 != a1) {
          const double r0 = spec.bin_centre_m(previous), r1 = spec.bin_centre_m(b);
          const double r = r0 + (r1 - r0) * a0 / (a0 - a1);
          if (std::abs(r - spec.bin_centre_m(peak)) < std::abs(best - spec.bin_centre_m(peak))) best = r;
        }
      }
      previous = b;
    }
    if (std::isfinite(best)) {
      detection.range_m = best;
      detection.by_phase = true;
      return detection;
    }
  }
  double sum = 0.0, sum_r = 0.0;
  for (int b = first; b <= last; ++b) {
    sum += echo.intensity[b];
    sum_r += echo.intensity[b] * spec.bin_centre_m(b);
  }
  detection.range_m = sum_r / sum;
  return detection;
}

}  // namespace hadal::render
