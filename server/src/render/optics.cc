#include "hadal/render/optics.h"


#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hadal/core/units.h"
#include "hadal/core/validation_error.h"

namespace hadal::render {
namespace {

using validation::invalid;

bool finite_non_negative(const Rgb& x) { return x.allFinite() && (x >= 0.0).all(); }

}  // namespace

Rgb SpotLight::intensity_towards(const Eigen::Vector3d& u_W) const { return LightBeam(*this).intensity_towards(u_W); }

LightBeam::LightBeam(const SpotLight& spot)
    : light(spot), cos_inner(std::cos(spot.inner_half_angle_rad)), cos_outer(std::cos(spot.outer_half_angle_rad)) {}

Rgb LightBeam::intensity_towards(const Eigen::Vector3d& u_W) const {
  const double cos_angle = std::clamp(light.axis_W.dot(u_W), -1.0, 1.0);
  if (cos_angle >= cos_inner) return light.intensity_W_per_sr;
  if (cos_angle <= cos_outer) return Rgb::Zero();
  const double angle = std::acos(cos_angle);
  const double x = std::clamp((light.outer_half_angle_rad - angle) / (light.outer_half_angle_rad - light.inner_half_angle_rad), 0.0, 1.0);
  return light.intensity_W_per_sr * (x * x * (3.0 - 2.0 * x));
}

void validate(const WaterOptics& water) {
  if (!finite_non_negative(water.absorption_per_m)) invalid("absorption", "must be finite and >= 0 per channel [1/m]");
  if (!finite_non_negative(water.scattering_per_m)) invalid("scattering", "must be finite and >= 0 per channel [1/m]");
  if (!(std::abs(water.phase_g) < 1.0)) invalid("phase_g", "must be in (-1, 1)");
  if (!(water.forward_scatter_max_angle_rad >= 0.0 && water.forward_scatter_max_angle_rad <= kPi / 6.0)) {
    invalid("forward_scatter_max_angle", "must be in [0, 30] deg");
  }
}

void validate(const SpotLight& light) {
  if (!light.p_WL.allFinite()) invalid("position", "must be finite");
  if (!light.axis_W.allFinite() || std::abs(light.axis_W.norm() - 1.0) > 1e-6) invalid("axis", "must be a unit vector");
  if (!(light.inner_half_angle_rad >= 0.0 && light.inner_half_angle_rad < light.outer_half_angle_rad &&
        light.outer_half_angle_rad <= kPi)) {
    invalid("cone", "need 0 <= inner half angle < outer half angle <= 180 deg");
  }
  if (!finite_non_negative(light.intensity_W_per_sr)) invalid("intensity", "must be finite and >= 0 per channel [W/sr]");
}

Rgb Daylight::irradiance_at(double z_W) const {
  const double depth = std::max(0.0, surface_z_m - z_W);
  return surface_irradiance_W_per_m2 * transmittance(Kd_per_m, depth);
}

void validate(const Daylight& daylight) {
  if (!finite_non_negative(daylight.surface_irradiance_W_per_m2)) invalid("surface_irradiance", "must be finite and >= 0 per channel [W/m^2]");
  if (!finite_non_negative(daylight.Kd_per_m)) invalid("Kd", "must be finite and >= 0 per channel [1/m]");
  if (!std::isfinite(daylight.surface_z_m)) invalid("surface_z", "must be finite");
}

Rgb daylight_surface_radiance(const Rgb& albedo, const Daylight& daylight, const Eigen::Vector3d& p_W,
                              const Eigen::Vector3d& n_W, const Rgb& c_per_m, double d_camera_m) {
  const double sky_share = 0.5 * (1.0 + n_W.z());  // isotropic-sky tilt factor (header)
  if (!(sky_share > 0.0)) return Rgb::Zero();
  // E_d(z) exp(-c d_camera) = E0 exp(-(Kd depth + c d_camera)): one exp per channel.
  const double depth = std::max(0.0, daylight.surface_z_m - p_W.z());
  const Rgb optical_depth = daylight.Kd_per_m * depth + c_per_m * d_camera_m;
  return albedo / kPi * daylight.surface_irradiance_W_per_m2 * sky_share *
         exp3((-optical_depth).cast<float>()).cast<double>();
}

Rgb daylight_path_radiance(const WaterOptics& water, const Daylight& daylight, const Eigen::Vector3d& o_W,
                           const Eigen::Vector3d& d_W, double s0, double s1) {
  return daylight_path_radiance(water, daylight, daylight.irradiance_at(o_W.z()), o_W, d_W, s0, s1);
}

Rgb daylight_path_radiance(const WaterOptics& water, const Daylight& daylight, const Rgb& E_origin,
                           const Eigen::Vector3d& o_W, const Eigen::Vector3d& d_W, double s0, double s1) {
  if (!(s0 >= 0.0 && s1 > s0)) throw std::invalid_argument("daylight_path_radiance: need 0 <= s0 < s1");
  if ((water.scattering_per_m == 0.0).all()) return Rgb::Zero();
  // A ray going up leaves the water at the surface.
  if (d_W.z() > 0.0) s1 = std::min(s1, std::max(0.0, (daylight.surface_z_m - o_W.z()) / d_W.z()));
  if (!(s1 > s0)) return Rgb::Zero();
  const Rgb scale = water.scattering_per_m * henyey_greenstein(water.phase_g, d_W.z()) * E_origin;
  // k > 0 on every downward or level ray (c >= b > 0 where b > 0), and s1 is finite on an upward one.
  // The exponentials in single precision, as transmittance() (relative error ~1e-7).
  const Rgb k = water.attenuation_per_m() - daylight.Kd_per_m * d_W.z();
  const Eigen::Array3f near = exp3((-(k * s0)).cast<float>());
  const Eigen::Array3f far = std::isfinite(s1) ? exp3((-(k * s1)).cast<float>()) : Eigen::Array3f::Zero();
  Rgb integral;
  for (int ch = 0; ch < 3; ++ch) {
    integral[ch] = std::abs(k[ch]) * s1 < 1e-9 ? s1 - s0 : (static_cast<double>(near[ch]) - far[ch]) / k[ch];
  }
  return scale * integral;
}

namespace {

// Fresnel's unpolarised reflectance of the water-air interface for a ray making cos_w with the normal in the water
// (refractive index n) and cos_air in the air: the same whichever way the light goes.
double fresnel_reflectance(double n, double cos_w, double cos_air) {
  const double rs = (n * cos_w - cos_air) / (n * cos_w + cos_air);
  const double rp = (cos_w - n * cos_air) / (cos_w + n * cos_air);
  return 0.5 * (rs * rs + rp * rp);
}

}  // namespace

double water_to_air_reflectance(double n, double cos_w) {
  const double sin_air2 = n * n * (1.0 - cos_w * cos_w);
  if (sin_air2 >= 1.0) return 1.0;
  return fresnel_reflectance(n, cos_w, std::sqrt(1.0 - sin_air2));
}

Rgb surface_from_below_radiance(const WaterOptics& water, const Daylight& daylight, const Eigen::Vector3d& o_W,
                                const Eigen::Vector3d& d_W, double s_end) {
  const Eigen::Vector3d& m = daylight.surface_normal_W;
  const double cos_w = m.dot(d_W);
  const double height = (daylight.surface_z_m - o_W.z()) * m.z();  // m . (surface point - o_W), the point over o_W
  if (!(cos_w > 0.0) || !(height > 0.0)) return Rgb::Zero();
  const double s = height / cos_w;
  if (!(s <= s_end)) return Rgb::Zero();
  const double n = daylight.refractive_index, R = water_to_air_reflectance(n, cos_w);
  const Eigen::Vector3d mirrored = d_W - 2.0 * cos_w * m;
  const Rgb& E0 = daylight.surface_irradiance_W_per_m2;
  const Rgb c = water.attenuation_per_m();
  const Rgb upwelling = water.scattering_per_m * henyey_greenstein(water.phase_g, mirrored.z()) * E0 /
                        (c + daylight.Kd_per_m * std::max(0.0, -mirrored.z()));
  return ((1.0 - R) * n * n / kPi * E0 + R * upwelling) * (-c * s).exp();
}

Rgb surface_from_above_radiance(const WaterOptics& water, const Daylight& daylight, const Eigen::Vector3d& o_W,
                                const Eigen::Vector3d& d_W, double s_end) {
  const Eigen::Vector3d& m = daylight.surface_normal_W;
  const Rgb& E0 = daylight.surface_irradiance_W_per_m2;
  const double cos_d = m.dot(d_W);
  const double height = (daylight.surface_z_m - o_W.z()) * m.z();  // < 0 for a camera above the plane
  if (!(height < 0.0)) return Rgb::Zero();
  if (!(cos_d < 0.0)) return std::isinf(s_end) ? Rgb(E0 / kPi) : Rgb::Zero();
  const double s = height / cos_d;
  if (!(s <= s_end)) return Rgb::Zero();
  const double n = daylight.refractive_index, cos_i = -cos_d;
  const double cos_t = std::sqrt(1.0 - (1.0 - cos_i * cos_i) / (n * n));
  const double R = fresnel_reflectance(n, cos_t, cos_i);
  const Eigen::Vector3d refracted = d_W / n + (cos_i / n - cos_t) * m;
  const Rgb upwelling = water.scattering_per_m * henyey_greenstein(water.phase_g, refracted.z()) * E0 /
                        (water.attenuation_per_m() + daylight.Kd_per_m * std::max(0.0, -refracted.z()));
  return R * E0 / kPi + (1.0 - R) / (n * n) * upwelling;
}

double henyey_greenstein(double g, double cos_psi) {
  const double denominator = 1.0 + g * g - 2.0 * g * cos_psi;
  return (1.0 - g * g) / (4.0 * kPi * denominator * std::sqrt(denominator));
}

Rgb lambertian_radiance(const Rgb& albedo, const LightBeam& beam, const Eigen::Vector3d& p_W,
                        const Eigen::Vector3d& n_W, const Rgb& c_per_m, double d_camera_m) {
  const Eigen::Vector3d to_point = p_W - beam.light.p_WL;
  const double d_light = to_point.norm();
  if (!(d_light > 0.0)) return Rgb::Zero();
  const Eigen::Vector3d u = to_point / d_light;
  const double cos_incidence = -n_W.dot(u);
  if (!(cos_incidence > 0.0)) return Rgb::Zero();
  // Irradiance at the point, times the water's transmittance on the way to the camera.
  return albedo / kPi * beam.intensity_towards(u) * (cos_incidence / (d_light * d_light)) *
         transmittance(c_per_m, d_light + d_camera_m);
}

Rgb backscatter_from_light(const WaterOptics& water, const Rgb& c_per_m, const LightBeam& beam,
                           const Eigen::Vector3d& x_W, const Eigen::Vector3d& d_W) {
  const Eigen::Vector3d from_light = x_W - beam.light.p_WL;
  const double r = from_light.norm();
  if (!(r > 0.0)) return Rgb::Zero();
  const Eigen::Vector3d u = from_light / r;
  if (beam.light.axis_W.dot(u) <= beam.cos_outer) return Rgb::Zero();  // outside the beam
  const double p = henyey_greenstein(water.phase_g, -u.dot(d_W));  // scattered back along -d
  return water.scattering_per_m * p * beam.intensity_towards(u) / (r * r) * transmittance(c_per_m, r);
}

Rgb backscatter_radiance(const WaterOptics& water, const std::vector<SpotLight>& lights,
                         const Eigen::Vector3d& o_W, const Eigen::Vector3d& d_W, double s0, double s1,
                         int samples) {
  if (!(s0 > 0.0 && s1 > s0) || samples < 1) {
    throw std::invalid_argument("backscatter_radiance: need 0 < s0 < s1 and samples >= 1");
  }
  if ((water.scattering_per_m == 0.0).all() || lights.empty()) return Rgb::Zero();
  const Rgb c = water.attenuation_per_m();
  const std::vector<LightBeam> beams(lights.begin(), lights.end());
  const double log_ratio = std::log(s1 / s0);
  Rgb sum = Rgb::Zero();
  for (int k = 0; k < samples; ++k) {
    // Midpoint of the k-th interval in log s; ds = s dx.
    const double s = s0 * std::exp(log_ratio * (k + 0.5) / samples);
    const double ds = s * log_ratio / samples;
    const Eigen::Vector3d x = o_W + s * d_W;
    Rgb from_lights = Rgb::Zero();
    for (const LightBeam& beam : beams) from_lights += backscatter_from_light(water, c, beam, x, d_W);
    sum += from_lights * transmittance(c, s) * ds;
  }
  return sum;
}

}  // namespace hadal::render
