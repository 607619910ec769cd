#include "hadal/physics/ocean_fluid.h"

#include <algorithm>

namespace hadal::physics {

double OceanFluid::gauge_pressure(double z_W) const {
  const double depth = ocean_.depth(z_W);
  return depth > 0.0 ? ocean_.pressure(depth) - ocean_.atmospheric_pressure() : 0.0;
}

void OceanFluid::sample(const Eigen::Vector3d& origin_W, std::size_t n, const float* dx,
                        const float* dy, const float* dz, const FluidSamples& out) const {
  // Constant-density water: rho and p_g = rho g max(d, 0) in closed form, in one branch-free loop
  // (the general path below dispatches on the density model per point).
  const bool constant = ocean_.spec().density_model == DensityModel::kConstant;
  const double rho_constant = ocean_.spec().density;
  const double rho_g = rho_constant * ocean_.gravity();
  const double depth_origin = ocean_.depth(origin_W.z());
  const double p_origin = constant ? rho_g * std::max(depth_origin, 0.0) : gauge_pressure(origin_W.z());
  float x[SurfaceHydrodynamics::kBlock], y[SurfaceHydrodynamics::kBlock],
      z[SurfaceHydrodynamics::kBlock];
  for (std::size_t begin = 0; begin < n; begin += SurfaceHydrodynamics::kBlock) {
    const std::size_t count = std::min(n - begin, SurfaceHydrodynamics::kBlock);
    if (constant) {
      for (std::size_t k = 0; k < count; ++k) {
        const std::size_t i = begin + k;
        out.rho[i] = static_cast<float>(rho_constant);
        out.dp[i] = static_cast<float>(rho_g * std::max(depth_origin - dz[i], 0.0) - p_origin);
      }
    } else {
      for (std::size_t k = 0; k < count; ++k) {
        const std::size_t i = begin + k;
        const double z_W = origin_W.z() + dz[i];
        out.rho[i] = static_cast<float>(ocean_.density(std::max(ocean_.depth(z_W), 0.0)));
        out.dp[i] = static_cast<float>(gauge_pressure(z_W) - p_origin);
      }
    }
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t i = begin + k;
      x[k] = static_cast<float>(origin_W.x() + dx[i]);
      y[k] = static_cast<float>(origin_W.y() + dy[i]);
      z[k] = static_cast<float>(origin_W.z() + dz[i]);
    }
    ocean_.sample_current(x, y, z, count, time_, out.u_x + begin, out.u_y + begin, out.u_z + begin);
  }
}

}  // namespace hadal::physics
