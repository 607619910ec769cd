#include "hadal/render/frame.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "hadal/render/camera_rays.h"
#include "hadal/render/forward_scatter.h"

namespace hadal::render {
namespace {

constexpr std::size_t kSky = static_cast<std::size_t>(-1);  // a shadow ray towards the surface

geometry::RayHits cast(const geometry::EmbreeScene& scene, const geometry::RayBatch& batch) {
  geometry::RayHits hits;
  hits.resize(batch.size());
  if (batch.size() > 0) scene.intersect(batch, 0, batch.size(), geometry::QueryPath::kAuto, hits);
  return hits;
}

double backscatter_start_m(float near_m) { return std::max(static_cast<double>(near_m), 1e-3); }

// Shadow rays that need no Embree query (render/frame.h): from a point on a static height field of
// steepest slope L, a segment whose origin is above the field and which climbs faster than L stays
// above it all the way; if it also misses every body's bounding box (but the one it ignores) nothing
// can block it.
class ClearShadows {
 public:
  ClearShadows(const geometry::EmbreeScene& scene, std::int32_t ignore_body)
      : max_slope_(scene.static_height_field_max_slope()) {
    if (!max_slope_) return;
    for (const geometry::BodyBounds& bounds : scene.body_bounds_W()) {
      if (bounds.body != ignore_body) boxes_.push_back(bounds.box_W);
    }
  }

  // Whether the segment origin + t d, t in [0, length] (d unit), from a hit on body `body` with unit
  // normal n (turned towards the camera; the origin is the hit point moved along n) is clear. Margins:
  // the origin at least 0.1 of the shadow bias above the field, the slope 0.1 % + 1e-4 above L.
  bool clear(std::int32_t body, const Eigen::Vector3d& n, const Eigen::Vector3d& origin, const Eigen::Vector3d& d,
             double length) const {
    if (!max_slope_ || body != geometry::kStaticBody) return false;
    const double L = *max_slope_;
    if (!(n.z() - L * std::sqrt(n.x() * n.x() + n.y() * n.y()) >= 0.1)) return false;
    if (!(d.z() > (1.001 * L + 1e-4) * std::sqrt(d.x() * d.x() + d.y() * d.y()))) return false;
    for (const Eigen::AlignedBox3d& box : boxes_) {
      if (segment_meets(box, origin, d, length)) return false;
    }
    return true;
  }

 private:
  // Slab test: whether origin + t d meets the box for some t in [0, length].
  static bool segment_meets(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& d,
                            double length) {
    double t0 = 0.0, t1 = length;
    for (int k = 0; k < 3; ++k) {
      if (d[k] == 0.0) {
        if (origin[k] < box.min()[k] || origin[k] > box.max()[k]) return false;
        continue;
      }
      double a = (box.min()[k] - origin[k]) / d[k], b = (box.max()[k] - origin[k]) / d[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) return false;
    }
    return true;
  }

  std::optional<double> max_slope_;
  std::vector<Eigen::AlignedBox3d> boxes_;
};

double backscatter_end_m(const FrameLighting& lighting, float far_m) {
  return std::isfinite(far_m) ? static_cast<double>(far_m) : lighting.max_backscatter_range_m;
}

}  // namespace

std::shared_ptr<const BackscatterTable> make_backscatter_table(const FrameLighting& lighting,
                                                               const std::vector<SpotLight>& lights_C, const Lens& lens,
                                                               float near_m, float far_m, const ParallelFor& parallel) {
  const double s0 = backscatter_start_m(near_m), s_max = backscatter_end_m(lighting, far_m);
  if (lights_C.empty() || !(lighting.water.scattering_per_m > 0.0).any() || !(s_max > s0)) return nullptr;
  return std::make_shared<const BackscatterTable>(lighting.water, lights_C, lens, Eigen::Isometry3d::Identity(), s0,
                                                  s_max, lighting.backscatter_samples, lighting.backscatter_grid_px,
                                                  parallel);
}

namespace {

bool same_light(const SpotLight& a, const SpotLight& b) {
  return a.p_WL == b.p_WL && a.axis_W == b.axis_W && a.inner_half_angle_rad == b.inner_half_angle_rad &&
         a.outer_half_angle_rad == b.outer_half_angle_rad && (a.intensity_W_per_sr == b.intensity_W_per_sr).all();
}

}  // namespace

std::shared_ptr<const BackscatterTable> BackscatterTableCache::get(const FrameLighting& lighting,
                                                                   const std::vector<SpotLight>& lights_C,
                                                                   const std::shared_ptr<const Lens>& lens,
                                                                   float near_m, float far_m,
                                                                   const ParallelFor& parallel) {
  std::lock_guard<std::mutex> lock(mutex_);
  const WaterOptics& water = lighting.water;
  const bool same = valid_ && (water_.absorption_per_m == water.absorption_per_m).all() &&
                    (water_.scattering_per_m == water.scattering_per_m).all() && water_.phase_g == water.phase_g &&
                    samples_ == lighting.backscatter_samples && grid_px_ == lighting.backscatter_grid_px &&
                    max_range_m_ == lighting.max_backscatter_range_m && lens_ == lens && near_m_ == near_m &&
                    far_m_ == far_m && lights_C_.size() == lights_C.size() &&
                    std::equal(lights_C.begin(), lights_C.end(), lights_C_.begin(), same_light);
  if (same) return table_;
  table_ = make_backscatter_table(lighting, lights_C, *lens, near_m, far_m, parallel);
  valid_ = true;
  water_ = water;
  samples_ = lighting.backscatter_samples;
  grid_px_ = lighting.backscatter_grid_px;
  max_range_m_ = lighting.max_backscatter_range_m;
  lens_ = lens;
  near_m_ = near_m;
  far_m_ = far_m;
  lights_C_ = lights_C;
  ++made_;
  return table_;
}

std::size_t BackscatterTableCache::tables_made() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return made_;
}

RadianceFrame render_radiance(const geometry::EmbreeScene& scene, const Lens& lens, const Eigen::Isometry3d& X_WC,
                              float near_m, float far_m, std::int32_t ignore_body, const FrameLighting& lighting,
                              const AlbedoAt& albedo_of, const ParallelFor& parallel) {
  validate(lighting.water);
  validate(lighting.daylight);
  for (const SpotLight& light : lighting.lights) validate(light);
  if (lighting.backscatter_samples < 1 || lighting.backscatter_grid_px < 1) {
    throw std::invalid_argument("backscatter: need samples >= 1 and grid >= 1 px");
  }
  {
    geometry::RayBatch none;  // checks the clip and the pose before any work
    add_camera_rays(lens, X_WC, near_m, far_m, ignore_body, 0, 0, none);
  }
  const std::size_t width = static_cast<std::size_t>(lens.width_px());
  const std::size_t n = width * static_cast<std::size_t>(lens.height_px());
  RadianceFrame frame;
  frame.width_px = lens.width_px();
  frame.height_px = lens.height_px();
  frame.radiance.assign(n, Rgb::Zero());
  frame.depth_m.assign(n, std::numeric_limits<float>::quiet_NaN());

  // Scattered light along the rays: the lights' backscatter (from the table, up to s_max at most) and
  // daylight's path radiance (closed form).
  const double s0 = backscatter_start_m(near_m);
  const bool scattering = (lighting.water.scattering_per_m > 0.0).any();
  const bool daylit_water = scattering && (lighting.daylight.surface_irradiance_W_per_m2 > 0.0).any();
  std::shared_ptr<const BackscatterTable> backscatter = lighting.backscatter;
  if (!backscatter) {
    std::vector<SpotLight> lights_C = lighting.lights;
    const Eigen::Isometry3d X_CW = X_WC.inverse();
    for (SpotLight& light : lights_C) {
      light.p_WL = X_CW * light.p_WL;
      light.axis_W = X_CW.linear() * light.axis_W;
    }
    backscatter = make_backscatter_table(lighting, lights_C, lens, near_m, far_m, parallel);
  }
  const std::vector<LightBeam> beams(lighting.lights.begin(), lighting.lights.end());
  const Rgb c = lighting.water.attenuation_per_m();
  // Below daylight_floor_z daylight is nothing in every channel (exp3 of Kd times the depth below
  // -87.3, ~1e-38 of the surface's): no sky rays there. -inf: daylight everywhere; +inf: none.
  double daylight_floor_z = std::numeric_limits<double>::infinity();
  for (int ch = 0; ch < 3; ++ch) {
    if (!(lighting.daylight.surface_irradiance_W_per_m2[ch] > 0.0)) continue;
    const double Kd = lighting.daylight.Kd_per_m[ch];
    daylight_floor_z = std::min(daylight_floor_z, Kd > 0.0 ? lighting.daylight.surface_z_m - 87.3 / Kd
                                                           : -std::numeric_limits<double>::infinity());
  }
  // Daylight's irradiance at the rays' common origin, the camera's centre (in single precision, as the
  // rays hold it).
  const Rgb E_camera = lighting.daylight.irradiance_at(static_cast<float>(X_WC.translation().z()));
  // Forward scatter (render/forward_scatter.h): each surface pixel's radiance times exp(b_f d) - 1,
  // spread over the image after the bands.
  const Rgb forward_per_m = forward_scattering_per_m(lighting.water);
  const bool forward = (forward_per_m > 0.0).any();
  std::vector<Rgb> forward_source;
  if (forward) forward_source.assign(n, Rgb::Zero());

  const ClearShadows clear_shadows(scene, ignore_body);
  const int bands = (lens.height_px() + kBandRows - 1) / kBandRows;
  std::vector<std::size_t> band_shadow_rays(static_cast<std::size_t>(bands), 0);
  parallel(static_cast<std::size_t>(bands), [&](std::size_t band) {
    const int row_begin = static_cast<int>(band) * kBandRows;
    const int row_end = std::min(row_begin + kBandRows, lens.height_px());
    const std::size_t first = static_cast<std::size_t>(row_begin) * width;  // pixel index of the band's ray 0
    geometry::RayBatch primary;
    primary.reserve(static_cast<std::size_t>(row_end - row_begin) * width);
    add_camera_rays(lens, X_WC, near_m, far_m, ignore_body, row_begin, row_end, primary);
    const geometry::RayHits hits = cast(scene, primary);
    const std::size_t m = primary.size();
    const auto origin_W = [&](std::size_t i) {
      return Eigen::Vector3d(primary.p_WO_x[i], primary.p_WO_y[i], primary.p_WO_z[i]);
    };
    const auto direction_W = [&](std::size_t i) {
      return Eigen::Vector3d(primary.d_W_x[i], primary.d_W_y[i], primary.d_W_z[i]);
    };

    // Hit points, normals turned towards the camera, albedos, and where shadow rays start
    // (shadow_bias_m off the surface).
    std::vector<Eigen::Vector3d> p_W(m), n_W(m), shadow_origin_W(m);
    std::vector<Rgb> albedo(m);
    for (std::size_t i = 0; i < m; ++i) {
      frame.depth_m[first + i] = depth_along_axis_m(hits.hit(i), hits.distance[i], lens.rays_C()[first + i].z());
      if (!hits.hit(i)) continue;
      const Eigen::Vector3d d = direction_W(i);
      p_W[i] = origin_W(i) + static_cast<double>(hits.distance[i]) * d;
      Eigen::Vector3d normal(hits.n_W_x[i], hits.n_W_y[i], hits.n_W_z[i]);
      if (normal.dot(d) > 0.0) normal = -normal;
      n_W[i] = normal;
      shadow_origin_W[i] = p_W[i] + lighting.shadow_bias_m * normal;
      albedo[i] = albedo_of(SurfacePoint{hits.material[i], hits.body[i], p_W[i], hits.tex_u[i], hits.tex_v[i]});
    }
    // One shadow ray per (hit, light) that the light's beam reaches, then daylight's straight up to the
    // surface (light index kSky); those ClearShadows proves clear are not cast (cast[k] = kNotCast).
    // Light by light, so that neighbouring rays run in similar directions (coherent for Embree).
    constexpr std::size_t kNotCast = static_cast<std::size_t>(-1);
    geometry::RayBatch shadows;
    shadows.coherence = geometry::RayCoherence::kCoherent;
    shadows.reserve(m * (beams.size() + 1));
    std::vector<std::size_t> shadow_pixel, shadow_light, cast;
    const auto add_shadow = [&](std::size_t i, std::size_t light, const Eigen::Vector3d& d, float length) {
      shadow_pixel.push_back(i);
      shadow_light.push_back(light);
      if (clear_shadows.clear(hits.body[i], n_W[i], shadow_origin_W[i], d, length)) {
        cast.push_back(kNotCast);
        return;
      }
      cast.push_back(shadows.size());
      shadows.add_ray(shadow_origin_W[i].cast<float>(), d.cast<float>(), 0.0f, length, ignore_body);
    };
    for (std::size_t l = 0; l < beams.size(); ++l) {
      for (std::size_t i = 0; i < m; ++i) {
        if (!hits.hit(i)) continue;
        const Eigen::Vector3d to_light = beams[l].light.p_WL - shadow_origin_W[i];
        const double distance = to_light.norm();
        if (!(distance > lighting.shadow_bias_m) || n_W[i].dot(to_light) <= 0.0) continue;  // light behind the surface
        if (-beams[l].light.axis_W.dot(to_light) <= beams[l].cos_outer * distance) continue;  // outside the beam
        add_shadow(i, l, to_light / distance, static_cast<float>(distance) - lighting.shadow_bias_m);
      }
    }
    for (std::size_t i = 0; i < m; ++i) {
      if (!hits.hit(i) || !(n_W[i].z() > -1.0) || !(p_W[i].z() > daylight_floor_z)) continue;
      const double sky = lighting.daylight.surface_z_m - p_W[i].z();
      add_shadow(i, kSky, Eigen::Vector3d::UnitZ(), sky > 0.0 ? static_cast<float>(sky) : 0.0f);
    }
    std::vector<std::uint8_t> blocked(shadows.size());
    if (shadows.size() > 0) scene.occluded(shadows, 0, shadows.size(), blocked);
    band_shadow_rays[band] = shadows.size();
    for (std::size_t k = 0; k < shadow_pixel.size(); ++k) {
      if (cast[k] != kNotCast && blocked[cast[k]] != 0) continue;
      const std::size_t i = shadow_pixel[k];
      const double d_camera = static_cast<double>(hits.distance[i]);
      const Rgb surface = shadow_light[k] == kSky
                              ? daylight_surface_radiance(albedo[i], lighting.daylight, p_W[i], n_W[i], c, d_camera)
                              : lambertian_radiance(albedo[i], beams[shadow_light[k]], p_W[i], n_W[i], c, d_camera);
      frame.radiance[first + i] += surface;
      if (forward) forward_source[first + i] += surface;
    }
    if (forward) {
      for (std::size_t i = 0; i < m; ++i) {
        if (!hits.hit(i)) continue;
        const Eigen::Array3f bd = (forward_per_m * static_cast<double>(hits.distance[i])).cast<float>();
        forward_source[first + i] *= (exp3(bd) - 1.0f).cast<double>();
      }
    }
    if (!backscatter && !daylit_water) return;
    for (std::size_t i = 0; i < m; ++i) {
      const double s_end = hits.hit(i) ? static_cast<double>(hits.distance[i]) : static_cast<double>(far_m);
      if (!(s_end > s0)) continue;
      if (backscatter) {
        const int v = row_begin + static_cast<int>(i / width), u = static_cast<int>(i % width);
        frame.radiance[first + i] += backscatter->at(u, v, s_end);
      }
      if (daylit_water) {
        frame.radiance[first + i] +=
            daylight_path_radiance(lighting.water, lighting.daylight, E_camera, origin_W(i), direction_W(i), s0, s_end);
      }
    }
  });
  for (std::size_t count : band_shadow_rays) frame.shadow_rays += count;
  if (forward) {
    add_forward_scatter(*forward_scatter_kernel(lighting.water, lens.spec().fx, lens.spec().fy), frame.width_px,
                        frame.height_px, forward_source, frame.radiance, parallel);
  }
  frame.snow_particles = add_marine_snow(lighting.marine_snow, lens, X_WC, lighting.water, lighting.lights,
                                         frame.depth_m, frame.radiance);
  return frame;
}

}  // namespace hadal::render
