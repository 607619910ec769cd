#include "hadal/render/frame.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hadal/render/camera_rays.h"

namespace hadal::render {
namespace {

constexpr std::size_t kSky = static_cast<std::size_t>(-1);  // a shadow ray towards the surface

geometry::RayHits cast(const geometry::EmbreeScene& scene, const geometry::RayBatch& batch) {
  geometry::RayHits hits;
  hits.resize(batch.size());
  if (batch.size() > 0) scene.intersect(batch, 0, batch.size(), geometry::QueryPath::kAuto, hits);
  return hits;
}

}  // namespace

RadianceFrame render_radiance(const geometry::EmbreeScene& scene, const Lens& lens, const Eigen::Isometry3d& X_WC,
                              float near_m, float far_m, std::int32_t ignore_body, const FrameLighting& lighting,
                              const AlbedoOfMaterial& albedo_of) {
  validate(lighting.water);
  validate(lighting.daylight);
  for (const SpotLight& light : lighting.lights) validate(light);

  geometry::RayBatch primary;
  add_camera_rays(lens, X_WC, near_m, far_m, ignore_body, primary);
  const geometry::RayHits hits = cast(scene, primary);
  const std::size_t n = primary.size();

  RadianceFrame frame;
  frame.width_px = lens.width_px();
  frame.height_px = lens.height_px();
  frame.depth_m = depth_image_m(lens, hits, 0);
  frame.radiance.assign(n, Rgb::Zero());

  const auto origin_W = [&](std::size_t i) {
    return Eigen::Vector3d(primary.p_WO_x[i], primary.p_WO_y[i], primary.p_WO_z[i]);
  };
  const auto direction_W = [&](std::size_t i) {
    return Eigen::Vector3d(primary.d_W_x[i], primary.d_W_y[i], primary.d_W_z[i]);
  };

  // Hit points, normals turned towards the camera, albedos, and one shadow ray per (hit, light).
  std::vector<Eigen::Vector3d> p_W(n), n_W(n);
  std::vector<Rgb> albedo(n);
  geometry::RayBatch shadows;
  std::vector<std::size_t> shadow_pixel;
  std::vector<std::size_t> shadow_light;
  for (std::size_t i = 0; i < n; ++i) {
    if (!hits.hit(i)) continue;
    const Eigen::Vector3d d = direction_W(i);
    p_W[i] = origin_W(i) + static_cast<double>(hits.distance[i]) * d;
    Eigen::Vector3d normal(hits.n_W_x[i], hits.n_W_y[i], hits.n_W_z[i]);
    if (normal.dot(d) > 0.0) normal = -normal;
    n_W[i] = normal;
    albedo[i] = albedo_of(hits.material[i]);
    const Eigen::Vector3d origin = p_W[i] + lighting.shadow_bias_m * normal;  // shadow rays start here
    for (std::size_t l = 0; l < lighting.lights.size(); ++l) {
      const Eigen::Vector3d to_light = lighting.lights[l].p_WL - origin;
      const double distance = to_light.norm();
      if (!(distance > lighting.shadow_bias_m) || normal.dot(to_light) <= 0.0) continue;  // light behind the surface
      shadows.add_ray(origin.cast<float>(), (to_light / distance).cast<float>(), 0.0f,
                      static_cast<float>(distance) - lighting.shadow_bias_m, ignore_body);
      shadow_pixel.push_back(i);
      shadow_light.push_back(l);
    }
    // Daylight: a ray straight up to the surface (index kSky in shadow_light).
    const double sky = lighting.daylight.surface_z_m - p_W[i].z();
    if (normal.z() > 0.0 && (lighting.daylight.irradiance_at(p_W[i].z()) > 0.0).any()) {
      shadows.add_ray(origin.cast<float>(), Eigen::Vector3f::UnitZ(), 0.0f,
                      sky > 0.0 ? static_cast<float>(sky) : 0.0f, ignore_body);
      shadow_pixel.push_back(i);
      shadow_light.push_back(kSky);
    }
  }
  const geometry::RayHits blocked = cast(scene, shadows);
  const Rgb c = lighting.water.attenuation_per_m();
  for (std::size_t k = 0; k < shadows.size(); ++k) {
    if (blocked.hit(k)) continue;
    const std::size_t i = shadow_pixel[k];
    if (shadow_light[k] == kSky) {
      frame.radiance[i] += daylight_surface_radiance(albedo[i], lighting.daylight, p_W[i], n_W[i], c,
                                                     static_cast<double>(hits.distance[i]));
      continue;
    }
    frame.radiance[i] += lambertian_radiance(albedo[i], lighting.lights[shadow_light[k]], p_W[i],
                                             n_W[i], c, static_cast<double>(hits.distance[i]));
  }

  // Scattered light along every ray, up to what it hit: the lights' backscatter and daylight's path
  // radiance.
  const bool lit_water = !lighting.lights.empty() && (lighting.water.scattering_per_m > 0.0).any();
  const bool daylit_water = (lighting.water.scattering_per_m > 0.0).any() &&
                            (lighting.daylight.surface_irradiance_W_per_m2 > 0.0).any();
  if (lit_water || daylit_water) {
    for (std::size_t i = 0; i < n; ++i) {
      const double s0 = std::max(static_cast<double>(near_m), 1e-3);
      const double s_end = hits.hit(i) ? static_cast<double>(hits.distance[i]) : static_cast<double>(far_m);
      if (!(s_end > s0)) continue;
      const Eigen::Vector3d o = origin_W(i), d = direction_W(i);
      if (lit_water) {
        const double s1 = std::isfinite(s_end) ? s_end : lighting.max_backscatter_range_m;
        if (s1 > s0) {
          frame.radiance[i] += backscatter_radiance(lighting.water, lighting.lights, o, d, s0, s1, lighting.backscatter_samples);
        }
      }
      if (daylit_water) frame.radiance[i] += daylight_path_radiance(lighting.water, lighting.daylight, o, d, s0, s_end);
    }
  }
  return frame;
}

}  // namespace hadal::render
