#include "hadal/physics/ocean_fluid.h"

#include <algorithm>
#include <cstdint>

#include "hadal/core/vector_kernel.h"

// The density/pressure loops (HADAL_VECTOR_KERNEL) are compiled for AVX-512, AVX2 and the baseline, and the loader
// picks one at run time, as for the face kernel (src/physics/face_kernel.h); without FMA contraction
// (server/CMakeLists.txt) they all give the same bits.

namespace hadal::physics {

namespace {

constexpr std::size_t kBlock = SurfaceHydrodynamics::kBlock;

// Every loop below evaluates rho(d_i) and the pressure p(d_i) in double at the depth
// d_i = d_origin - dz_i and rounds rho and dp_i = p(d_i) - p_origin to float once; p_origin is the
// same function at d_origin, so dp at the origin is 0 up to double rounding. p is gauge for constant and ramp
// water, absolute for CTD water (same difference).
// Above the surface (d < 0) the water is that at d = 0: rho(0) and gauge pressure 0. Branch-free, so
// the loops vectorise.

// Constant: rho, p_g = rho g max(d, 0).
HADAL_VECTOR_KERNEL
void constant_block(double rho, double rho_g, double d_origin, double p_origin, const float* __restrict dz,
                    std::size_t n, float* __restrict rho_out, float* __restrict dp_out) {
  for (std::size_t i = 0; i < n; ++i) {
    rho_out[i] = static_cast<float>(rho);
    dp_out[i] = static_cast<float>(rho_g * std::max(d_origin - dz[i], 0.0) - p_origin);
  }
}

// Ramp (ocean.h), closed form. With w = max(d, 0) and m = min(w, d_pyc):
//   rho = rho0 + (drho / d_pyc) m
//   p_g = g integral_0^w rho = g (rho0 w + drho (w - m) + drho m^2 / (2 d_pyc))
// which is Ocean::pressure's two branches in one (m = w above the pycnocline, m = d_pyc below). All
// terms are positive, so p_g carries a few double roundings, ~1e-15 relative.
struct Ramp {
  double rho0, drho, d_pyc, slope, half_slope, g;  // slope = drho / d_pyc
};

inline void ramp_at(const Ramp& r, double d, double& rho, double& p_g) {
  const double w = std::max(d, 0.0);
  const double m = std::min(w, r.d_pyc);
  rho = r.rho0 + r.slope * m;
  p_g = r.g * (r.rho0 * w + r.drho * (w - m) + r.half_slope * m * m);
}

HADAL_VECTOR_KERNEL
void ramp_block(const Ramp& r, double d_origin, double p_origin, const float* __restrict dz, std::size_t n,
                float* __restrict rho_out, float* __restrict dp_out) {
  for (std::size_t i = 0; i < n; ++i) {
    double rho, p_g;
    ramp_at(r, d_origin - dz[i], rho, p_g);
    rho_out[i] = static_cast<float>(rho);
    dp_out[i] = static_cast<float>(p_g - p_origin);
  }
}

// CTD: a direct lookup in the Ocean's table (Ocean::table_pressure / table_density, nodes k h,
// h = kTableStep, k = 0 .. N), evaluating the interpolants of Ocean::pressure and Ocean::density. With
// s = max(d, 0) / h, its part inside the table s_in = min(s, N), segment k = min(floor(s_in), N - 1),
// w = s_in - k in [0, 1], v = 1 - w and e = s - s_in (> 0 only below the table):
//   rho = r0 + w (r1 - r0)
//   p   = p0 + (p1 - p0) w^2 (3 - 2 w) + g h [w v (r0 v - r1 w) + r1 e]
// i.e. the cubic Hermite p0 H00 + p1 H01 + m0 H10 + m1 H11 with node slopes m = g rho h (H00 = 1 - H01),
// continued linearly below the table (p_N + g rho_N (d - N h)). The same nodes and interpolants as
// Ocean's in another arrangement: they agree to a few double roundings of the absolute pressure
// (~1e-16 relative). Only the two nodes around d are read (four gathered loads per point). A NaN depth
// reads segment 0 (max(0, NaN) is 0), never out of bounds. (Clamping w = min(u, 1) after the floor
// instead leaves a branch that GCC 12 does not if-convert, and the loop is not vectorised.)
struct Ctd {
  const double* p;    // absolute pressure at the nodes [Pa]
  const double* rho;  // density at the nodes [kg/m^3]
  double gh;          // g h [m^2/s^2]
  double last_node;   // N
};

inline void ctd_at(const Ctd& t, double d, double& rho, double& p) {
  const double s = std::max(0.0, d * (1.0 / Ocean::kTableStep));  // = d / h exactly: h is 2^-1
  const double s_in = std::min(t.last_node, s);
  const auto last_segment = static_cast<std::int32_t>(t.last_node) - 1;
  const auto k = std::min(static_cast<std::int32_t>(s_in), last_segment);  // s_in >= 0: truncation is floor
  const double w = s_in - static_cast<double>(k), v = 1.0 - w, e = s - s_in;
  const double p0 = t.p[k], p1 = t.p[k + 1], r0 = t.rho[k], r1 = t.rho[k + 1];
  rho = r0 + w * (r1 - r0);
  p = p0 + (p1 - p0) * (w * w * (3.0 - 2.0 * w)) + t.gh * (w * v * (r0 * v - r1 * w) + r1 * e);
}

HADAL_VECTOR_KERNEL
void ctd_block(const Ctd& t, double d_origin, double p_origin, const float* __restrict dz, std::size_t n,
               float* __restrict rho_out, float* __restrict dp_out) {
  for (std::size_t i = 0; i < n; ++i) {
    double rho, p;
    ctd_at(t, d_origin - dz[i], rho, p);
    rho_out[i] = static_cast<float>(rho);
    dp_out[i] = static_cast<float>(p - p_origin);
  }
}

}  // namespace

FluidSampler::SurfacePlane OceanFluid::surface_plane(const Eigen::Vector3d& p_W) const {
  SurfacePlane plane;
  Eigen::Vector2d slope;
  ocean_.surface_tangent(p_W.x(), p_W.y(), time_, &plane.height, &slope);
  plane.slope_x = slope.x();
  plane.slope_y = slope.y();
  return plane;
}

const OceanFluid::WavesAbout& OceanFluid::waves_about(const Eigen::Vector3d& origin_W) const {
  if (origin_W == about_.origin_W) return about_;
  const Waves& waves = ocean_.waves();
  about_.origin_W = origin_W;
  // Expanded about the origin, or, when it is above the surface (a vessel's centre of mass often is), about the
  // surface under it, and carried linearly up to the origin: the faces under the surface then see the water's
  // pressure and motion, not the air's zero.
  WaveKinematics k = waves.kinematics(origin_W, time_);
  Eigen::Vector3d from = origin_W;
  if (!k.wet) {
    from.z() = k.surface_height;
    k = waves.kinematics(from, time_);
  }
  about_.grad_p_d = k.pressure_gradient_W;
  about_.p_d = k.dynamic_pressure + k.pressure_gradient_W.dot(origin_W - from);
  about_.v_orbital_W = k.velocity_W;
  about_.a_orbital_W = k.acceleration_W;
  return about_;
}

FluidSampler::WavesNear OceanFluid::waves_near(const Eigen::Vector3d& origin_W) const {
  if (!ocean_.waves().enabled()) return {};
  const WavesAbout& about = waves_about(origin_W);
  return {about.v_orbital_W, about.a_orbital_W, about.grad_p_d, ocean_.waves().density()};
}

std::optional<FluidSampler::Uniform> OceanFluid::uniform() const {
  if (ocean_.waves().enabled() || ocean_.spec().density_model != DensityModel::kConstant ||
      ocean_.current_varies_in_space()) {
    return std::nullopt;
  }
  return Uniform{ocean_.spec().density, ocean_.current_W(Eigen::Vector3d::Zero(), time_)};
}

double OceanFluid::gauge_pressure_at(const Eigen::Vector3d& p_W) const {
  if (!ocean_.waves().enabled()) return gauge_pressure(p_W.z());
  return ocean_.signed_pressure(ocean_.depth(p_W.z())) - ocean_.atmospheric_pressure() + waves_about(p_W).p_d;
}

double OceanFluid::gauge_pressure(double z_W) const {
  const double depth = ocean_.depth(z_W);
  return depth > 0.0 ? ocean_.pressure(depth) - ocean_.atmospheric_pressure() : 0.0;
}

void OceanFluid::sample_currents(const Eigen::Vector3d& origin_W, std::size_t n, const float* dx, const float* dy,
                                 const float* dz, const FluidSamples& out) const {
  if (!ocean_.current_varies_in_space()) {  // the same everywhere: filled in once
    ocean_.sample_current(nullptr, nullptr, nullptr, n, time_, out.u_x, out.u_y, out.u_z);
    return;
  }
  float x[kBlock], y[kBlock], z[kBlock];
  for (std::size_t begin = 0; begin < n; begin += kBlock) {
    const std::size_t count = std::min(n - begin, kBlock);
    for (std::size_t k = 0; k < count; ++k) {
      x[k] = static_cast<float>(origin_W.x() + dx[begin + k]);
      y[k] = static_cast<float>(origin_W.y() + dy[begin + k]);
      z[k] = static_cast<float>(origin_W.z() + dz[begin + k]);
    }
    ocean_.sample_current(x, y, z, count, time_, out.u_x + begin, out.u_y + begin, out.u_z + begin);
  }
}

void OceanFluid::sample(const Eigen::Vector3d& origin_W, std::size_t n, const float* dx,
                        const float* dy, const float* dz, const FluidSamples& out) const {
  const double d_origin = ocean_.depth(origin_W.z());
  if (ocean_.waves().enabled()) {  // the waves, linear about the origin (the header): per point, in double
    const WavesAbout& about = waves_about(origin_W);
    const double p_origin_signed = ocean_.signed_pressure(d_origin);
    for (std::size_t i = 0; i < n; ++i) {
      const double d = d_origin - dz[i];
      out.rho[i] = static_cast<float>(ocean_.density(std::max(d, 0.0)));
      out.dp[i] = static_cast<float>(ocean_.signed_pressure(d) - p_origin_signed +
                                     about.grad_p_d.dot(Eigen::Vector3d(dx[i], dy[i], dz[i])));
    }
    sample_currents(origin_W, n, dx, dy, dz, out);
    for (std::size_t i = 0; i < n; ++i) {  // currents and waves add
      out.u_x[i] += static_cast<float>(about.v_orbital_W.x());
      out.u_y[i] += static_cast<float>(about.v_orbital_W.y());
      out.u_z[i] += static_cast<float>(about.v_orbital_W.z());
    }
    return;
  }
  const WaterSpec& water = ocean_.spec();
  const DensityModel model = water.density_model;
  const double g = ocean_.gravity();
  const double rho_g = water.density * g;
  Ramp ramp{};
  Ctd ctd{};
  double p_origin = 0.0, unused = 0.0;
  switch (model) {
    case DensityModel::kConstant:
      p_origin = rho_g * std::max(d_origin, 0.0);
      break;
    case DensityModel::kRamp: {
      const double slope = water.pycnocline_density_increase / water.pycnocline_depth;
      ramp = Ramp{water.rho0, water.pycnocline_density_increase, water.pycnocline_depth, slope, 0.5 * slope,
                  g};
      ramp_at(ramp, d_origin, unused, p_origin);
      break;
    }
    case DensityModel::kCtd: {
      const std::vector<double>& table_p = ocean_.table_pressure();
      ctd = Ctd{table_p.data(), ocean_.table_density().data(), g * Ocean::kTableStep,
                static_cast<double>(table_p.size() - 1)};  // the Ocean builds >= 2 nodes for CTD water
      ctd_at(ctd, d_origin, unused, p_origin);
      break;
    }
  }
  for (std::size_t begin = 0; begin < n; begin += kBlock) {
    const std::size_t count = std::min(n - begin, kBlock);
    switch (model) {
      case DensityModel::kConstant:
        constant_block(water.density, rho_g, d_origin, p_origin, dz + begin, count, out.rho + begin,
                       out.dp + begin);
        break;
      case DensityModel::kRamp:
        ramp_block(ramp, d_origin, p_origin, dz + begin, count, out.rho + begin, out.dp + begin);
        break;
      case DensityModel::kCtd:
        ctd_block(ctd, d_origin, p_origin, dz + begin, count, out.rho + begin, out.dp + begin);
        break;
    }
  }
  sample_currents(origin_W, n, dx, dy, dz, out);
}

}  // namespace hadal::physics
