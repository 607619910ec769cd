// Deep-sea image formation, the per-ray physics (docs/ARCHITECTURE.md, "Cameras"): water as absorption
// and scattering per colour channel, spot lights with a smooth beam edge, Lambertian reflection of a
// light seen through the water, and single-scattering backscatter along a camera ray with a
// Henyey–Greenstein phase function. The paper leaves this to an external renderer; these are the
// building blocks of Hadal's own renderer on Embree (issue 11).
//
// Units: lengths [m]; coefficients [1/m]; radiant intensity [W/sr]; irradiance [W/m^2]; radiance
// [W/(m^2 sr)]; all per channel (R, G, B) as Rgb. Frames: everything in the world frame W.
// Model:
//   beam attenuation        c = a + b;  light over a path of length d is multiplied by exp(-c d)
//   Lambertian surface      L = (albedo / pi) E,  E = I(u) max(0, n . -u) / d_l^2 exp(-c d_l)
//                           (u the unit direction from the light to the point, d_l their distance),
//                           seen by the camera as L exp(-c d_cam)
//   phase function          Henyey–Greenstein, p(psi) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos psi)^1.5)
//                           [1/sr], psi the angle between the light's travel and the scattered ray;
//                           g = 0.924 by default, the mean cosine of Petzold's average particle phase
//                           function (a forward-peaked, "Petzold-like" fit)
//   backscatter             L_b = sum over lights of  integral_{s0}^{s1} b p(psi(s)) I(u(s)) / r(s)^2
//                           exp(-c r(s)) exp(-c s) ds  along the camera ray x(s) = o + s d, r(s) the
//                           distance from the light; single scattering, no shadowing of the water
//                           volume. Evaluated by the midpoint rule on a geometric grid in s (the
//                           integrand of a light beside the camera falls as 1/s^2; on a log grid it is
//                           smooth), error below 0.1 % with 64 samples over three decades.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "hadal/render/fast_math.h"
#include "hadal/render/optics_spec.h"

namespace hadal::render {

// A spot light: full radiant intensity inside inner_half_angle of its axis, none beyond
// outer_half_angle, a smoothstep in the angle between (a soft beam edge).
struct SpotLight {
  Eigen::Vector3d p_WL = Eigen::Vector3d::Zero();  // position in W [m]
  Eigen::Vector3d axis_W = Eigen::Vector3d::UnitX();  // unit beam axis in W
  double inner_half_angle_rad = 0.4;
  double outer_half_angle_rad = 0.6;
  Rgb intensity_W_per_sr = Rgb::Constant(100.0);  // on the axis

  // Radiant intensity towards the unit direction u_W (from the light) [W/sr] (LightBeam's).
  Rgb intensity_towards(const Eigen::Vector3d& u_W) const;
};

// A spot light with the cosines of its beam edges computed once, for loops that evaluate the beam many
// times a frame. The beam: full intensity where cos(angle off the axis) >= cos(inner), none where it is
// <= cos(outer), between them the smoothstep in the angle (one acos).
struct LightBeam {
  explicit LightBeam(const SpotLight& light);
  SpotLight light;
  double cos_inner = 1.0;
  double cos_outer = -1.0;
  Rgb intensity_towards(const Eigen::Vector3d& u_W) const;  // [W/sr]
};

// Throws std::invalid_argument naming the field: negative or non-finite coefficients, |g| >= 1; a
// light's axis not unit (within 1e-6), 0 <= inner < outer <= pi, negative or non-finite intensity.
void validate(const WaterOptics& water);
void validate(const SpotLight& light);

void validate(const Daylight& daylight);

// Radiance reaching the camera from a Lambertian point lit by daylight: albedo / pi E_d(z) (1 + n_z) / 2
// exp(-c d_camera), E_d the irradiance on a level surface and (1 + n_z) / 2 the share of a uniformly
// bright upper hemisphere a surface tilted to normal n sees (the isotropic-sky tilt factor: 1 facing up,
// 1/2 vertical, 0 facing down); the caller decides whether the sky is occluded.
Rgb daylight_surface_radiance(const Rgb& albedo, const Daylight& daylight, const Eigen::Vector3d& p_W,
                              const Eigen::Vector3d& n_W, const Rgb& c_per_m, double d_camera_m);

// In-water path radiance of daylight scattered into the camera ray o_W + s d_W over [s0, s1] (s1 may
// be +inf; an upward ray ends at the surface), single scattering. With the light coming straight down,
// cos psi = d_z and E_d(z(s)) = E_d(z_o) exp(Kd d_z s), so the integral has the closed form
//   b p(d_z) E_d(z_o) (exp(-k s0) - exp(-k s1)) / k,  k = c - Kd d_z (> 0 on level and downward rays, as c >= b > 0),
// and b p(d_z) E_d(z_o) (s1 - s0) in the limit k -> 0.
Rgb daylight_path_radiance(const WaterOptics& water, const Daylight& daylight, const Eigen::Vector3d& o_W,
                           const Eigen::Vector3d& d_W, double s0, double s1);
// Fresnel's reflectance of unpolarised light going from water (refractive index n) into air at incidence cos_w (the
// ray's cosine with the surface's normal, > 0): ((rs^2 + rp^2) / 2, with sin theta_air = n sin theta_w); 1 beyond
// the critical angle asin(1 / n) (total internal reflection).
double water_to_air_reflectance(double n, double cos_w);

// The sea surface seen from below along the camera ray o_W + s d_W, when the ray reaches it (the plane through
// (x, y, daylight.surface_z_m) with normal daylight.surface_normal_W) before s_end (the hit or the far clip):
//   (T n^2 E0 / pi + R b p(d'_z) E0 / (c + Kd |d'_z|)) exp(-c s_surface),  T = 1 - R = 1 - water_to_air_reflectance
// the sky's radiance E0 / pi (a uniform sky that gives the surface E0) refracted into Snell's window (n^2: the
// radiance of a narrowed cone), and the upwelling single-scattered daylight under the surface along the mirrored ray
// d' reflected (all of it outside the window); zero otherwise. render/frame.h adds it to rays leaving the water.
Rgb surface_from_below_radiance(const WaterOptics& water, const Daylight& daylight, const Eigen::Vector3d& o_W,
                                const Eigen::Vector3d& d_W, double s_end);

// The sea surface seen from above along the ray o_W + s d_W of a camera in the air, when the ray goes down to the
// surface's plane before s_end: R E0 / pi + (1 - R) / n^2 b p(d_t,z) E0 / (c + Kd |d_t,z|), R the air-to-water
// Fresnel reflectance at its incidence and d_t the refracted ray (the sky reflected and the water's upwelling
// daylight transmitted out, render/frame.h); E0 / pi (the sky) on a ray that rises from the plane and hits nothing
// (s_end infinite); zero otherwise. `water` is the water under the surface.
Rgb surface_from_above_radiance(const WaterOptics& water, const Daylight& daylight, const Eigen::Vector3d& o_W,
                                const Eigen::Vector3d& d_W, double s_end);

// The same with E_d(z_o) = daylight.irradiance_at(o_W.z()) given (a camera's rays share their origin).
Rgb daylight_path_radiance(const WaterOptics& water, const Daylight& daylight, const Rgb& E_origin,
                           const Eigen::Vector3d& o_W, const Eigen::Vector3d& d_W, double s0, double s1);

// e^x of three channels in single precision: render/fast_math.h's fast::exp (Cephes' expf, within 2 ulp
// for x in [-87.3, 88], the same bits on every x86-64 CPU, no libm) per channel; x below -87.3 gives
// e^-87.3 ~ 1.2e-38 instead of a denormal or 0, a transmittance far below any image's noise.
inline Eigen::Array3f exp3(const Eigen::Array3f& x) {
  return Eigen::Array3f(fast::exp(x[0]), fast::exp(x[1]), fast::exp(x[2]));
}

// Beam transmittance exp(-c d) per channel over a path of d metres. Evaluated in single precision
// (relative error ~1e-7, far below any image's noise) by exp3: the renderer takes ~10 of them per pixel.
inline Rgb transmittance(const Rgb& c_per_m, double d_m) {
  return exp3((-(c_per_m * d_m)).cast<float>()).cast<double>();
}

// Henyey–Greenstein phase function p(cos psi) [1/sr] (header formula); integrates to 1 over the sphere.
double henyey_greenstein(double g, double cos_psi);

// Radiance reaching the camera from a Lambertian surface point p_W with unit normal n_W and `albedo`,
// lit by `light` through water of attenuation c, the camera being d_camera_m away (header formula).
// Zero for a point the light's beam or the surface's front side does not face.
Rgb lambertian_radiance(const Rgb& albedo, const LightBeam& beam, const Eigen::Vector3d& p_W,
                        const Eigen::Vector3d& n_W, const Rgb& c_per_m, double d_camera_m);
inline Rgb lambertian_radiance(const Rgb& albedo, const SpotLight& light, const Eigen::Vector3d& p_W,
                               const Eigen::Vector3d& n_W, const Rgb& c_per_m, double d_camera_m) {
  return lambertian_radiance(albedo, LightBeam(light), p_W, n_W, c_per_m, d_camera_m);
}

// One light's share of backscatter_radiance's integrand at the point x_W of a camera ray of unit
// direction d_W, before the camera-side factor exp(-c s) ds: b p(psi) I(u) / r^2 exp(-c r) per channel
// (zero outside the beam or at the light itself). c = water.attenuation_per_m(), passed in.
Rgb backscatter_from_light(const WaterOptics& water, const Rgb& c_per_m, const LightBeam& beam,
                           const Eigen::Vector3d& x_W, const Eigen::Vector3d& d_W);

// Single-scattering backscatter radiance along the camera ray o_W + s d_W (d_W unit) for s in
// [s0, s1] (0 < s0 < s1, typically the camera's near clip and the hit distance or its far clip), from
// every light, with `samples` midpoint samples on a geometric grid (header).
Rgb backscatter_radiance(const WaterOptics& water, const std::vector<SpotLight>& lights,
                         const Eigen::Vector3d& o_W, const Eigen::Vector3d& d_W, double s0, double s1,
                         int samples = 64);

}  // namespace hadal::render
