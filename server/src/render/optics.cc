#include "hadal/render/optics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hadal/core/units.h"

namespace hadal::render {
namespace {

[[noreturn]] void invalid(const std::string& field, const std::string& what) {
  throw std::invalid_argument(field + ": " + what);
}

bool finite_non_negative(const Rgb& x) { return x.allFinite() && (x >= 0.0).all(); }

}  // namespace

Rgb SpotLight::intensity_towards(const Eigen::Vector3d& u_W) const {
  const double angle = std::acos(std::clamp(axis_W.dot(u_W), -1.0, 1.0));
  if (angle <= inner_half_angle_rad) return intensity_W_per_sr;
  if (angle >= outer_half_angle_rad) return Rgb::Zero();
  const double x = (outer_half_angle_rad - angle) / (outer_half_angle_rad - inner_half_angle_rad);
  return intensity_W_per_sr * (x * x * (3.0 - 2.0 * x));
}

void validate(const WaterOptics& water) {
  if (!finite_non_negative(water.absorption_per_m)) invalid("absorption", "must be finite and >= 0 per channel [1/m]");
  if (!finite_non_negative(water.scattering_per_m)) invalid("scattering", "must be finite and >= 0 per channel [1/m]");
  if (!(std::abs(water.phase_g) < 1.0)) invalid("phase_g", "must be in (-1, 1)");
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

double henyey_greenstein(double g, double cos_psi) {
  const double denominator = 1.0 + g * g - 2.0 * g * cos_psi;
  return (1.0 - g * g) / (4.0 * kPi * denominator * std::sqrt(denominator));
}

Rgb lambertian_radiance(const Rgb& albedo, const SpotLight& light, const Eigen::Vector3d& p_W,
                        const Eigen::Vector3d& n_W, const Rgb& c_per_m, double d_camera_m) {
  const Eigen::Vector3d to_point = p_W - light.p_WL;
  const double d_light = to_point.norm();
  if (!(d_light > 0.0)) return Rgb::Zero();
  const Eigen::Vector3d u = to_point / d_light;
  const double cos_incidence = -n_W.dot(u);
  if (!(cos_incidence > 0.0)) return Rgb::Zero();
  const Rgb irradiance = light.intensity_towards(u) * (cos_incidence / (d_light * d_light)) * (-c_per_m * d_light).exp();
  return albedo / kPi * irradiance * (-c_per_m * d_camera_m).exp();
}

Rgb backscatter_radiance(const WaterOptics& water, const std::vector<SpotLight>& lights,
                         const Eigen::Vector3d& o_W, const Eigen::Vector3d& d_W, double s0, double s1,
                         int samples) {
  if (!(s0 > 0.0 && s1 > s0) || samples < 1) {
    throw std::invalid_argument("backscatter_radiance: need 0 < s0 < s1 and samples >= 1");
  }
  const Rgb& b = water.scattering_per_m;
  if ((b == 0.0).all() || lights.empty()) return Rgb::Zero();
  const Rgb c = water.attenuation_per_m();
  const double log_ratio = std::log(s1 / s0);
  Rgb sum = Rgb::Zero();
  for (int k = 0; k < samples; ++k) {
    // Midpoint of the k-th interval in log s; ds = s dx.
    const double s = s0 * std::exp(log_ratio * (k + 0.5) / samples);
    const double ds = s * log_ratio / samples;
    const Eigen::Vector3d x = o_W + s * d_W;
    const Rgb towards_camera = (-c * s).exp();
    for (const SpotLight& light : lights) {
      const Eigen::Vector3d from_light = x - light.p_WL;
      const double r = from_light.norm();
      if (!(r > 0.0)) continue;
      const Eigen::Vector3d u = from_light / r;
      const double p = henyey_greenstein(water.phase_g, -u.dot(d_W));  // scattered back along -d
      sum += b * p * light.intensity_towards(u) / (r * r) * (-c * r).exp() * towards_camera * ds;
    }
  }
  return sum;
}

}  // namespace hadal::render
