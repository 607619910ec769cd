#include "hadal/physics/ocean.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>
#include <shared_mutex>
#include <stdexcept>
#include <string_view>

#include "hadal/physics/seawater.h"
#include "hadal/core/units.h"
#include "hadal/core/value_noise.h"

namespace hadal::physics {

namespace {

constexpr double kPascalPerDbar = 1e4;

}  // namespace

// Lazily generated Gauss-Markov samples on the grid t_k = k * step (see ocean.h). Chunks are appended in
// order under the unique lock; readers hold the shared lock. Chunk storage never moves once created.
struct Ocean::GaussMarkovTrack {
  static constexpr std::size_t kChunk = 4096;
  using Chunk = std::array<Eigen::Vector3d, kChunk>;

  GaussMarkovTrack(const Eigen::Vector3d& sigma_in, double tau, std::uint64_t seed)
      : sigma(sigma_in),
        step(tau / 64.0),
        phi(std::exp(-1.0 / 64.0)),
        innovation(std::sqrt(1.0 - phi * phi)),
        rng(splitmix64(seed ^ fnv1a("ocean_current"))) {}

  // Standard normal by Box-Muller from 53-bit uniforms (portable, unlike std::normal_distribution).
  double normal() {
    if (has_spare) {
      has_spare = false;
      return spare;
    }
    const double u1 = (static_cast<double>(rng() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
    const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare = r * std::sin(2.0 * kPi * u2);
    has_spare = true;
    return r * std::cos(2.0 * kPi * u2);
  }

  // Appends chunks until sample `index` exists (caller holds the unique lock).
  void extend_to(std::size_t index) {
    while (chunks.size() * kChunk <= index) {
      auto chunk = std::make_unique<Chunk>();
      for (std::size_t i = 0; i < kChunk; ++i) {
        Eigen::Vector3d w(normal(), normal(), normal());
        if (chunks.empty() && i == 0) {
          (*chunk)[i] = sigma.cwiseProduct(w);  // stationary start
        } else {
          const Eigen::Vector3d& previous = i == 0 ? chunks.back()->back() : (*chunk)[i - 1];
          (*chunk)[i] = phi * previous + innovation * sigma.cwiseProduct(w);
        }
      }
      chunks.push_back(std::move(chunk));
    }
  }

  Eigen::Vector3d sample(std::size_t index) const { return (*chunks[index / kChunk])[index % kChunk]; }

  Eigen::Vector3d at(double t) {
    const double s = std::max(t, 0.0) / step;
    const double floor_s = std::floor(s);
    // Beyond ~1e15 steps the grid index is meaningless; such times do not occur in a simulation.
    const auto k = static_cast<std::size_t>(floor_s);
    const double u = s - floor_s;
    {
      std::shared_lock lock(mutex);
      if (chunks.size() * kChunk > k + 1) return (1.0 - u) * sample(k) + u * sample(k + 1);
    }
    std::unique_lock lock(mutex);
    extend_to(k + 1);
    return (1.0 - u) * sample(k) + u * sample(k + 1);
  }

  const Eigen::Vector3d sigma;
  const double step;
  const double phi;
  const double innovation;
  std::shared_mutex mutex;
  std::mt19937_64 rng;
  bool has_spare = false;
  double spare = 0.0;
  std::vector<std::unique_ptr<Chunk>> chunks;
};

Ocean::Ocean(const WorldSpec& world)
    : Ocean(world.water, world.gravity_W.norm() > 0.0 ? world.gravity_W.norm() : 9.80665, world.seed) {
  waves_ = Waves(world.waves, water_.surface_z, water_.density, gravity_, world.seed);
}

Ocean::Ocean(const WaterSpec& water, double gravity, std::uint64_t seed) : water_(water), gravity_(gravity) {
  if (water_.density_model == DensityModel::kCtd) {
    // The loader guarantees these; a hand-built spec that breaks them is a programming error.
    if (water_.ctd.size() < 2) throw std::invalid_argument("Ocean: a CTD profile needs at least 2 rows");
    for (std::size_t i = 1; i < water_.ctd.size(); ++i) {
      if (!(water_.ctd[i].depth > water_.ctd[i - 1].depth)) {
        throw std::invalid_argument("Ocean: CTD depths must increase strictly");
      }
    }
    build_ctd_table();
  }
  const CurrentSpec& current = water_.current;
  if (current.gauss_markov_sigma_W.cwiseAbs().maxCoeff() > 0.0) {
    gauss_markov_ =
        std::make_unique<GaussMarkovTrack>(current.gauss_markov_sigma_W, current.gauss_markov_time_constant, seed);
  }
}

Ocean::~Ocean() = default;

void Ocean::surface_tangent(double x, double y, double t, double* height, Eigen::Vector2d* slope) const {
  *height = water_.surface_z;
  slope->setZero();
  if (!waves_.enabled()) return;
  double eta = 0.0;
  waves_.surface(x, y, t, &eta, slope);
  *height = waves_.surface_z() + eta;
}

double Ocean::range_to_surface(const Eigen::Vector3d& p_W, const Eigen::Vector3d& d_W, double t) const {
  double height = 0.0;
  Eigen::Vector2d slope;
  surface_tangent(p_W.x(), p_W.y(), t, &height, &slope);
  // The plane z = height + slope . (x - x_p): with the normal m = (-s_x, -s_y, 1), m . (p_W + s d_W - q) = 0.
  const double below = height - p_W.z();
  const double rise = d_W.z() - slope.x() * d_W.x() - slope.y() * d_W.y();
  if (!(below >= 0.0) || !(rise > 0.0)) return std::numeric_limits<double>::infinity();
  return below / rise;
}

double Ocean::pressure_at(const Eigen::Vector3d& p_W, double t) const {
  if (!waves_.enabled()) return pressure(std::max(depth(p_W.z()), 0.0));
  const WaveKinematics waves = waves_.kinematics(p_W, t);  // the surface over p_W and p_d there, in one pass
  if (!waves.wet) return water_.atmospheric_pressure;
  return signed_pressure(depth(p_W.z())) + waves.dynamic_pressure;
}

Ocean::Ocean(Ocean&&) noexcept = default;
Ocean& Ocean::operator=(Ocean&&) noexcept = default;

void Ocean::ctd_at(double depth, double* temperature, double* salinity) const {
  const std::vector<CtdSample>& ctd = water_.ctd;
  if (depth <= ctd.front().depth) {
    *temperature = ctd.front().temperature;
    *salinity = ctd.front().salinity;
    return;
  }
  if (depth >= ctd.back().depth) {
    *temperature = ctd.back().temperature;
    *salinity = ctd.back().salinity;
    return;
  }
  const auto upper = std::upper_bound(ctd.begin(), ctd.end(), depth,
                                      [](double d, const CtdSample& row) { return d < row.depth; });
  const CtdSample& b = *upper;
  const CtdSample& a = *(upper - 1);
  const double u = (depth - a.depth) / (b.depth - a.depth);
  *temperature = a.temperature + u * (b.temperature - a.temperature);
  *salinity = a.salinity + u * (b.salinity - a.salinity);
}

void Ocean::build_ctd_table() {
  const auto nodes = static_cast<std::size_t>(std::lround(kTableDepth / kTableStep)) + 1;
  table_pressure_.resize(nodes);
  table_density_.resize(nodes);
  const double p_atm = water_.atmospheric_pressure;
  const auto rho_at = [&](double d, double p) {
    double t = 0.0, s = 0.0;
    ctd_at(d, &t, &s);
    return density_eos80(s, its90_to_ipts68(t), (p - p_atm) / kPascalPerDbar);
  };
  const double h = kTableStep;
  double p = p_atm;
  for (std::size_t k = 0; k < nodes; ++k) {
    const double d = static_cast<double>(k) * h;
    const double rho = rho_at(d, p);
    table_pressure_[k] = p;
    table_density_[k] = rho;
    if (k + 1 == nodes) break;
    // Classic RK4 on dp/dd = g rho(d, p).
    const double k1 = gravity_ * rho;
    const double k2 = gravity_ * rho_at(d + 0.5 * h, p + 0.5 * h * k1);
    const double k3 = gravity_ * rho_at(d + 0.5 * h, p + 0.5 * h * k2);
    const double k4 = gravity_ * rho_at(d + h, p + h * k3);
    p += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
}

double Ocean::density(double depth) const {
  const double d = std::max(depth, 0.0);
  switch (water_.density_model) {
    case DensityModel::kConstant:
      return water_.density;
    case DensityModel::kRamp:
      return water_.rho0 +
             water_.pycnocline_density_increase * std::min(d, water_.pycnocline_depth) / water_.pycnocline_depth;
    case DensityModel::kCtd:
      break;
  }
  const double s = d / kTableStep;
  const std::size_t last = table_density_.size() - 1;
  if (s >= static_cast<double>(last)) return table_density_[last];
  const auto k = static_cast<std::size_t>(s);
  const double u = s - static_cast<double>(k);
  return (1.0 - u) * table_density_[k] + u * table_density_[k + 1];
}

double Ocean::pressure(double depth) const {
  const double d = std::max(depth, 0.0);
  const double g = gravity_;
  const double p_atm = water_.atmospheric_pressure;
  switch (water_.density_model) {
    case DensityModel::kConstant:
      return p_atm + water_.density * g * d;
    case DensityModel::kRamp: {
      const double rho0 = water_.rho0;
      const double drho = water_.pycnocline_density_increase;
      const double d_pyc = water_.pycnocline_depth;
      if (d <= d_pyc) return p_atm + g * d * (rho0 + drho * d / (2.0 * d_pyc));
      return p_atm + g * d_pyc * (rho0 + 0.5 * drho) + g * (rho0 + drho) * (d - d_pyc);
    }
    case DensityModel::kCtd:
      break;
  }
  const std::size_t last = table_pressure_.size() - 1;
  const double s = d / kTableStep;
  if (s >= static_cast<double>(last)) {
    return table_pressure_[last] + g * table_density_[last] * (d - static_cast<double>(last) * kTableStep);
  }
  // Cubic Hermite on [k, k+1] with slopes dp/dd = g rho at the nodes.
  const auto k = static_cast<std::size_t>(s);
  const double u = s - static_cast<double>(k);
  const double p0 = table_pressure_[k], p1 = table_pressure_[k + 1];
  const double m0 = g * table_density_[k] * kTableStep, m1 = g * table_density_[k + 1] * kTableStep;
  const double u2 = u * u, u3 = u2 * u;
  return (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 + (u3 - u2) * m1;
}

double Ocean::temperature(double depth) const {
  if (water_.density_model != DensityModel::kCtd) return water_.temperature;
  double t = 0.0, s = 0.0;
  ctd_at(depth, &t, &s);
  return t;
}

double Ocean::salinity(double depth) const {
  if (water_.density_model != DensityModel::kCtd) return water_.salinity;
  double t = 0.0, s = 0.0;
  ctd_at(depth, &t, &s);
  return s;
}

double Ocean::sound_speed(double depth) const {
  const double sea_pressure_dbar = (pressure(depth) - water_.atmospheric_pressure) / kPascalPerDbar;
  return sound_speed_unesco(salinity(depth), its90_to_ipts68(temperature(depth)), sea_pressure_dbar);
}

double Ocean::sound_absorption_db_per_m(double depth, double frequency_hz) const {
  const double d = std::max(depth, 0.0);
  return absorption_francois_garrison_db_per_km(frequency_hz, temperature(d), salinity(d), d, water_.ph) / 1000.0;
}

double Ocean::kappa(double depth) const { return 1.0 - pressure(depth) / water_.bulk_modulus; }

Eigen::Vector3d Ocean::gauss_markov_current_W(double t) const {
  return gauss_markov_ ? gauss_markov_->at(t) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d Ocean::current_W(const Eigen::Vector3d& p_W, double t) const {
  const CurrentSpec& current = water_.current;
  const double d = std::max(depth(p_W.z()), 0.0);
  return current.uniform_W + current.shear_surface_W * std::exp(-d / current.shear_decay_depth) +
         gauss_markov_current_W(t);
}

void Ocean::sample(const float* z_W, std::size_t n, float* rho, float* pressure_out,
                   double pressure_offset) const {
  for (std::size_t i = 0; i < n; ++i) {
    const double d = depth(static_cast<double>(z_W[i]));
    if (rho) rho[i] = static_cast<float>(density(d));
    if (pressure_out) pressure_out[i] = static_cast<float>(pressure(d) - pressure_offset);
  }
}

bool Ocean::current_varies_in_space() const { return water_.current.shear_surface_W.cwiseAbs().maxCoeff() > 0.0; }

void Ocean::sample_current(const float* /*x_W*/, const float* /*y_W*/, const float* z_W, std::size_t n,
                           double t, float* vx_W, float* vy_W, float* vz_W) const {
  // The current varies with depth and time only; x and y are part of the interface for later fields.
  const CurrentSpec& current = water_.current;
  const Eigen::Vector3d base_W = current.uniform_W + gauss_markov_current_W(t);
  if (!current_varies_in_space()) {
    std::fill_n(vx_W, n, static_cast<float>(base_W.x()));
    std::fill_n(vy_W, n, static_cast<float>(base_W.y()));
    std::fill_n(vz_W, n, static_cast<float>(base_W.z()));
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double d = std::max(depth(static_cast<double>(z_W[i])), 0.0);
    const Eigen::Vector3d v_W = base_W + current.shear_surface_W * std::exp(-d / current.shear_decay_depth);
    vx_W[i] = static_cast<float>(v_W.x());
    vy_W[i] = static_cast<float>(v_W.y());
    vz_W[i] = static_cast<float>(v_W.z());
  }
}

}  // namespace hadal::physics
