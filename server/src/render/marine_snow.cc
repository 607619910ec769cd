#include "hadal/render/marine_snow.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hadal/core/units.h"

namespace hadal::render {
namespace {

// 64-bit mix of a cell index and the seed (the finaliser of MurmurHash3, applied per coordinate).
std::uint64_t mix(std::uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return h;
}

std::uint64_t cell_hash(std::uint64_t seed, std::int64_t i, std::int64_t j, std::int64_t k) {
  std::uint64_t h = mix(seed ^ 0x9e3779b97f4a7c15ULL);
  h = mix(h ^ static_cast<std::uint64_t>(i));
  h = mix(h ^ static_cast<std::uint64_t>(j));
  return mix(h ^ static_cast<std::uint64_t>(k));
}

// Uniform in [0, 1) from 53 bits of a hash.
double unit(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

}  // namespace

void validate(const MarineSnow& snow) {
  if (!(snow.density_per_m3 >= 0.0 && snow.density_per_m3 <= 1e5)) {
    throw std::invalid_argument("marine snow density: must be in [0, 1e5] per m^3");
  }
  if (!(snow.radius > 0.0) || !std::isfinite(snow.radius)) throw std::invalid_argument("marine snow radius: must be > 0 [m]");
  if (!(snow.max_range > 0.0) || !std::isfinite(snow.max_range)) {
    throw std::invalid_argument("marine snow range: must be > 0 [m]");
  }
  if (!(snow.albedo >= 0.0 && snow.albedo <= 1.0)) throw std::invalid_argument("marine snow albedo: must be in [0, 1]");
}

std::size_t add_marine_snow(const MarineSnow& snow, const Lens& lens, const Eigen::Isometry3d& X_WC,
                            const WaterOptics& water, const std::vector<SpotLight>& lights,
                            const std::vector<float>& depth_m, std::vector<Eigen::Array3f>& radiance,
                            const ParallelFor& parallel) {
  validate(snow);
  if (snow.density_per_m3 == 0.0 || lights.empty()) return 0;
  const int width = lens.width_px(), height = lens.height_px();
  const double cell = std::cbrt(1.0 / snow.density_per_m3);
  const Eigen::Vector3d p_WC = X_WC.translation();
  const Eigen::Isometry3d X_CW = X_WC.inverse();
  const Rgb c = water.attenuation_per_m();
  const std::vector<LightBeam> beams(lights.begin(), lights.end());
  // Cells of the cube of side 2 max_range around the camera (particles beyond the range are skipped).
  const auto lo = [&](int axis) { return static_cast<std::int64_t>(std::floor((p_WC[axis] - snow.max_range) / cell)); };
  const auto hi = [&](int axis) { return static_cast<std::int64_t>(std::floor((p_WC[axis] + snow.max_range) / cell)); };
  // A cell's particle lies within half a cell diagonal of its centre: cells whose centre is further
  // than the range plus that, or that far behind the camera's image plane, hold none to draw (most of
  // the cube: skipped before hashing).
  const double half_diagonal = 0.5 * std::sqrt(3.0) * cell;
  const double reach2 = (snow.max_range + half_diagonal) * (snow.max_range + half_diagonal);
  const Eigen::Vector3d z_C_in_W = X_WC.linear().col(2);  // the optical axis in W
  // Slabs of cells (one x index each) are tasks; each lists what it adds where, and the lists are
  // added in slab order afterwards: the same sums whatever the threads.
  struct Splat {
    std::size_t pixel;
    Eigen::Array3f radiance;
  };
  const std::int64_t first_slab = lo(0);
  const auto slabs = static_cast<std::size_t>(hi(0) - first_slab + 1);
  std::vector<std::vector<Splat>> splats(slabs);
  std::vector<std::size_t> drawn_in(slabs, 0);
  parallel(slabs, [&](std::size_t slab) {
    const std::int64_t i = first_slab + static_cast<std::int64_t>(slab);
    std::vector<Splat>& out = splats[slab];
    std::size_t& drawn = drawn_in[slab];
    for (std::int64_t j = lo(1); j <= hi(1); ++j) {
      // The column's cells within reach: centres with (z - p_z)^2 <= reach^2 - dx^2 - dy^2 (one cell
      // of margin each way; the test below is exact).
      const double dx = (static_cast<double>(i) + 0.5) * cell - p_WC.x(), dy = (static_cast<double>(j) + 0.5) * cell - p_WC.y();
      const double dz2 = reach2 - dx * dx - dy * dy;
      if (dz2 < 0.0) continue;
      const double dz = std::sqrt(dz2);
      const std::int64_t k0 = std::max(lo(2), static_cast<std::int64_t>(std::floor((p_WC.z() - dz) / cell)) - 1);
      const std::int64_t k1 = std::min(hi(2), static_cast<std::int64_t>(std::floor((p_WC.z() + dz) / cell)) + 1);
      for (std::int64_t k = k0; k <= k1; ++k) {
        const Eigen::Vector3d centre_C_W(dx, dy, (static_cast<double>(k) + 0.5) * cell - p_WC.z());
        if (centre_C_W.squaredNorm() > reach2 || centre_C_W.dot(z_C_in_W) < -half_diagonal) continue;
        const std::uint64_t h = cell_hash(snow.seed, i, j, k);
        const Eigen::Vector3d p_W((static_cast<double>(i) + unit(mix(h + 1))) * cell,
                                  (static_cast<double>(j) + unit(mix(h + 2))) * cell,
                                  (static_cast<double>(k) + unit(mix(h + 3))) * cell);
        const double d = (p_W - p_WC).norm();
        if (!(d <= snow.max_range)) continue;
        const Eigen::Vector3d p_C = X_CW * p_W;
        Eigen::Vector2d uv;
        if (!(p_C.z() > 0.0) || !project(lens.spec(), p_C, &uv)) continue;
        const long u = std::lround(uv.x()), v = std::lround(uv.y());
        if (u < 0 || v < 0 || u >= width || v >= height) continue;
        const std::size_t pixel = static_cast<std::size_t>(v) * width + static_cast<std::size_t>(u);
        if (std::isfinite(depth_m[pixel]) && depth_m[pixel] <= p_C.z()) continue;  // behind what the pixel sees
        Rgb irradiance = Rgb::Zero();
        for (const LightBeam& beam : beams) {
          const Eigen::Vector3d from_light = p_W - beam.light.p_WL;
          const double r = from_light.norm();
          if (!(r > 0.0)) continue;
          irradiance += beam.intensity_towards(from_light / r) / (r * r) * transmittance(c, r);
        }
        if ((irradiance == 0.0).all()) continue;
        const double radius = snow.radius * (0.5 + unit(mix(h + 4)));
        const double radius_px = radius * lens.spec().fx / p_C.z();
        const Rgb L = snow.albedo / kPi * irradiance * transmittance(c, d);
        if (radius_px <= 0.5) {
          out.push_back({pixel, (L * std::min(1.0, kPi * radius_px * radius_px)).cast<float>()});
        } else {
          const long reach = static_cast<long>(std::ceil(radius_px));
          for (long dv = -reach; dv <= reach; ++dv) {
            for (long du = -reach; du <= reach; ++du) {
              const long x = u + du, y = v + dv;
              if (x < 0 || y < 0 || x >= width || y >= height || du * du + dv * dv > radius_px * radius_px) continue;
              const std::size_t q = static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x);
              if (std::isfinite(depth_m[q]) && depth_m[q] <= p_C.z()) continue;
              out.push_back({q, L.cast<float>()});
            }
          }
        }
        ++drawn;
      }
    }
  });
  std::size_t drawn = 0;
  for (std::size_t slab = 0; slab < slabs; ++slab) {
    for (const Splat& splat : splats[slab]) radiance[splat.pixel] += splat.radiance;
    drawn += drawn_in[slab];
  }
  return drawn;
}

}  // namespace hadal::render
