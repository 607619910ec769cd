#include "hadal/render/frame.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "hadal/core/units.h"
#include "hadal/geometry/segment_slab.h"
#include "hadal/render/camera_rays.h"
#include "hadal/render/forward_scatter.h"

namespace hadal::render {
namespace {

double backscatter_start_m(float near_clip) { return std::max(static_cast<double>(near_clip), 1e-3); }

double backscatter_end_m(const FrameLighting& lighting, float far_clip) {
  return std::isfinite(far_clip) ? static_cast<double>(far_clip) : lighting.max_backscatter_range_m;
}

}  // namespace

std::shared_ptr<const BackscatterTable> make_backscatter_table(const FrameLighting& lighting,
                                                               const std::vector<SpotLight>& lights_C, const Lens& lens,
                                                               float near_clip, float far_clip, const ParallelFor& parallel) {
  const double s0 = backscatter_start_m(near_clip), s_max = backscatter_end_m(lighting, far_clip);
  if (lights_C.empty() || !(lighting.water.scattering_per_m > 0.0).any() || !(s_max > s0)) return nullptr;
  return std::make_shared<const BackscatterTable>(lighting.water, lights_C, lens, Eigen::Isometry3d::Identity(), s0,
                                                  s_max, lighting.backscatter_samples, lighting.backscatter_grid_px,
                                                  parallel);
}

std::vector<SpotLight> lights_in_camera_frame(const std::vector<SpotLight>& lights_W, const Eigen::Isometry3d& X_WC) {
  std::vector<SpotLight> lights_C = lights_W;
  const Eigen::Isometry3d X_CW = X_WC.inverse();
  for (SpotLight& light : lights_C) {
    light.p_WL = X_CW * light.p_WL;
    light.axis_W = X_CW.linear() * light.axis_W;
  }
  return lights_C;
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
                                                                   float near_clip, float far_clip,
                                                                   const ParallelFor& parallel) {
  std::lock_guard<std::mutex> lock(mutex_);
  const WaterOptics& water = lighting.water;
  const bool same = valid_ && (water_.absorption_per_m == water.absorption_per_m).all() &&
                    (water_.scattering_per_m == water.scattering_per_m).all() && water_.phase_g == water.phase_g &&
                    samples_ == lighting.backscatter_samples && grid_px_ == lighting.backscatter_grid_px &&
                    max_range_ == lighting.max_backscatter_range_m && lens_ == lens && near_m_ == near_clip &&
                    far_m_ == far_clip && lights_C_.size() == lights_C.size() &&
                    std::equal(lights_C.begin(), lights_C.end(), lights_C_.begin(), same_light);
  if (same) return table_;
  table_ = make_backscatter_table(lighting, lights_C, *lens, near_clip, far_clip, parallel);
  valid_ = true;
  water_ = water;
  samples_ = lighting.backscatter_samples;
  grid_px_ = lighting.backscatter_grid_px;
  max_range_ = lighting.max_backscatter_range_m;
  lens_ = lens;
  near_m_ = near_clip;
  far_m_ = far_clip;
  lights_C_ = lights_C;
  ++made_;
  return table_;
}

std::size_t BackscatterTableCache::tables_made() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return made_;
}

AlbedoOfPoints per_point(AlbedoAt albedo_of) {
  return [albedo_of = std::move(albedo_of)](const SurfacePoints& points, float* r, float* g, float* b) {
    for (std::size_t i = 0; i < points.count; ++i) {
      if (points.body[i] == geometry::kNoHit) continue;  // a miss: not used
      const Rgb albedo = albedo_of(points.point(i));
      r[i] = static_cast<float>(albedo[0]);
      g[i] = static_cast<float>(albedo[1]);
      b[i] = static_cast<float>(albedo[2]);
    }
  };
}

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kInvPi = static_cast<float>(1.0 / 3.14159265358979323846);

// A spot light as the band passes use it: single precision, positioned relative to the camera's centre.
struct BandLight {
  float x = 0, y = 0, z = 0;     // position relative to the camera's centre, W axes [m]
  float ax = 0, ay = 0, az = 0;  // unit beam axis in W
  float cos_inner = 1, cos_outer = -1, outer_rad = 0, inv_edge_rad = 0;  // 1 / (outer - inner)
  float intensity[3] = {0, 0, 0};  // on the axis [W/sr]
};

BandLight band_light(const SpotLight& light, const Eigen::Vector3d& p_WC) {
  const LightBeam beam(light);
  BandLight out;
  const Eigen::Vector3d p = light.p_WL - p_WC;
  out.x = static_cast<float>(p.x());
  out.y = static_cast<float>(p.y());
  out.z = static_cast<float>(p.z());
  out.ax = static_cast<float>(light.axis_W.x());
  out.ay = static_cast<float>(light.axis_W.y());
  out.az = static_cast<float>(light.axis_W.z());
  out.cos_inner = static_cast<float>(beam.cos_inner);
  out.cos_outer = static_cast<float>(beam.cos_outer);
  out.outer_rad = static_cast<float>(light.outer_half_angle_rad);
  out.inv_edge_rad = static_cast<float>(1.0 / (light.outer_half_angle_rad - light.inner_half_angle_rad));
  for (int ch = 0; ch < 3; ++ch) out.intensity[ch] = static_cast<float>(light.intensity_W_per_sr[ch]);
  return out;
}

// A body's bounding box relative to the camera's centre (padded by EmbreeScene::body_bounds_W's 1 cm,
// far more than single precision's rounding here).
struct BandBox {
  float lo[3], hi[3];
};

// Whether the segment o + s d, s in [0, length], meets the box (geometry/segment_slab.h: written out
// axis by axis without branches, so that the loop calling it vectorizes).
inline bool segment_meets(const BandBox& box, float ox, float oy, float oz, float dx, float dy, float dz, float length) {
  float t0 = 0.0f, t1 = length;
  geometry::clip_to_slab(box.lo[0], box.hi[0], ox, dx, t0, t1);
  geometry::clip_to_slab(box.lo[1], box.hi[1], oy, dy, t0, t1);
  geometry::clip_to_slab(box.lo[2], box.hi[2], oz, dz, t0, t1);
  return t0 <= t1;
}

// What every band of a frame shares.
struct FrameSetup {
  const geometry::EmbreeScene* scene = nullptr;
  const Lens* lens = nullptr;
  const AlbedoOfPoints* albedo_of = nullptr;
  const BackscatterTable* backscatter = nullptr;
  Eigen::Vector3d p_WC = Eigen::Vector3d::Zero();
  Eigen::Matrix3f R_WC = Eigen::Matrix3f::Identity();
  float near_clip = 0, far_clip = 0;
  std::int32_t ignore_body = geometry::kNoHit;
  float bias_m = 1e-3f;
  float c[3] = {0, 0, 0};  // attenuation [1/m]
  std::vector<BandLight> lights;
  std::vector<Eigen::Vector2d> light_xy_W;  // the lights' xy in W, for the band's shadow region
  std::vector<BandBox> boxes;  // of the bodies other than ignore_body
  bool height_field = false;   // the static world is one height field (shadow rays may be proved clear)
  // Daylight, heights relative to the camera's centre: sky rays from hits above floor_z (none: +inf).
  bool sky = false;
  float floor_z = kInf, surface_z = 0;
  float E0[3] = {0, 0, 0}, Kd[3] = {0, 0, 0};
  // The surface seen from below (Snell's window): its unit normal in W (tilted by waves) and water's refractive
  // index; `window` when the camera is under it with daylight above.
  bool window = false;
  float surface_n[3] = {0, 0, 1};
  float refractive_index = 1.34f;
  // A camera in the air (its centre above the surface's plane): the frame is rendered through clear air, and the
  // surface below it, where a ray reaches it first, is the sky reflected plus the water's upwelling light refracted
  // out (`water_*`: the water under it); rays that miss going up see the sky.
  bool above = false;
  float water_c[3] = {0, 0, 0}, water_b[3] = {0, 0, 0}, water_g = 0;
  // Scattered light along the rays.
  bool daylit_water = false;
  float s0 = 0;
  float b[3] = {0, 0, 0}, phase_g = 0, E_camera[3] = {0, 0, 0};
  bool forward = false;
  float forward_per_m[3] = {0, 0, 0};
  // Half the frame's negligible radiance per channel (FrameLighting): a band whose daylight bound is
  // below it in every channel leaves daylight out; `negligible_daylight` when any is above 0.
  double half_negligible[3] = {0, 0, 0};
  bool negligible_daylight = false;
};

// One band's per-pixel arrays (structure of arrays; the loops over them vectorize), and its rays.
// Each worker thread keeps one set from band to band (frame after frame): no allocation, no clearing
// but of the sums (every other array is written before it is read).
struct BandArrays {
  void resize(std::size_t n, std::size_t sources) {
    for (std::vector<float>* v : {&px, &py, &pz, &nx, &ny, &nz, &ar, &ag, &ab, &sr, &sg, &sb, &above, &cast, &sdx, &sdy,
                                  &sdz, &slen, &s_end}) {
      v->resize(n);
    }
    for (std::vector<float>* v : {&ar, &ag, &ab, &sr, &sg, &sb}) std::fill(v->begin(), v->end(), 0.0f);
    lit.resize(sources);
    for (std::vector<float>& v : lit) v.resize(n);
    contribution.resize(3 * sources);
    for (std::vector<float>& v : contribution) v.resize(n);
    primary.clear_rays();
    shadows.clear_rays();
    hits.resize(n);
    shadow_pixel.clear();
    shadow_source.clear();
  }
  std::vector<float> px, py, pz;  // hit point relative to the camera's centre, W axes (0 on a miss) [m]
  std::vector<float> nx, ny, nz;  // unit normal turned towards the camera (0 on a miss)
  std::vector<float> ar, ag, ab;  // albedo
  std::vector<float> sr, sg, sb;  // radiance at the camera [W/(m^2 sr)]
  std::vector<float> above;       // 1: the shadow origin is proved above the height field
  std::vector<float> cast;        // 1: the current light's shadow ray must be cast
  std::vector<float> sdx, sdy, sdz, slen;  // the current light's shadow ray: unit direction, length [m]
  std::vector<float> s_end;       // where the ray's water ends: the hit, or the far clip [m]
  std::vector<std::vector<float>> lit;  // per light, then the sky: 1 where it may light the point
  // Per source, R, G and B: its radiance at the camera from the surface, were nothing in its way (set
  // to 0 where a shadow ray is blocked).
  std::vector<std::vector<float>> contribution;
  geometry::RayBatch primary, shadows;
  geometry::RayHits hits;
  std::vector<std::uint32_t> shadow_pixel;   // per shadow ray cast: its pixel
  std::vector<std::uint16_t> shadow_source;  // and its light (the sky last)
  std::vector<std::uint8_t> blocked;
  std::vector<std::uint32_t> index;  // scratch: pixels whose shadow ray is cast
};

// Shadow-ray candidates of one source (a light, or the sky) whose rays are in a.sdx.. and a.cast: the
// clear ones are tested against the bodies' boxes, and those that must be cast are appended.
// Vectorized loops here and in render_band: every array element and constant is loaded into a local
// before any condition uses it (a load inside a branch keeps GCC from turning the branch into a select).
// `extent` bounds every segment of the source in the band (camera-relative): a box it misses is not
// tested pixel by pixel.
HADAL_VECTOR_KERNEL void gather_shadow_rays(const FrameSetup& f, BandArrays& a, const std::vector<float>& lit, std::size_t n,
                        std::uint16_t source, const Eigen::AlignedBox3f& extent, geometry::RayBatch& shadows,
                        std::vector<std::uint32_t>& pixel, std::vector<std::uint16_t>& source_of) {
  const float bias = f.bias_m;
  for (const BandBox& box : f.boxes) {
    if (!extent.intersects(Eigen::AlignedBox3f(Eigen::Vector3f(box.lo), Eigen::Vector3f(box.hi)))) continue;
    const BandBox b = box;
    const float* px = a.px.data();
    const float* py = a.py.data();
    const float* pz = a.pz.data();
    const float* nx = a.nx.data();
    const float* ny = a.ny.data();
    const float* nz = a.nz.data();
    const float* sdx = a.sdx.data();
    const float* sdy = a.sdy.data();
    const float* sdz = a.sdz.data();
    const float* slen = a.slen.data();
    const float* reach = lit.data();
    float* cast = a.cast.data();
#pragma GCC ivdep
    for (std::size_t i = 0; i < n; ++i) {
      const float ox = px[i] + bias * nx[i], oy = py[i] + bias * ny[i], oz = pz[i] + bias * nz[i];
      const float meets = segment_meets(b, ox, oy, oz, sdx[i], sdy[i], sdz[i], slen[i]) ? 1.0f : 0.0f;
      const float reaches = reach[i] != 0.0f ? 1.0f : 0.0f, was = cast[i];
      cast[i] = fast::max(was, reaches * meets);
    }
  }
  // The rays to cast, compacted without branches, then appended to the batch at once.
  std::vector<std::uint32_t>& index = a.index;
  index.resize(n);
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    index[count] = static_cast<std::uint32_t>(i);
    count += a.cast[i] != 0.0f ? 1 : 0;
  }
  const std::size_t first = shadows.size();
  for (std::vector<float>* v : {&shadows.p_WO_x, &shadows.p_WO_y, &shadows.p_WO_z, &shadows.d_W_x, &shadows.d_W_y,
                                &shadows.d_W_z, &shadows.t_near, &shadows.t_far}) {
    v->resize(first + count);
  }
  if (f.ignore_body != geometry::kNoHit) shadows.ignore_body.resize(first + count, f.ignore_body);
  pixel.resize(first + count);
  source_of.resize(first + count, source);
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t i = index[k];
    const std::size_t r = first + k;
    // The origin in W in double precision before rounding (as far from the world origin as need be).
    shadows.p_WO_x[r] = static_cast<float>(f.p_WC.x() + static_cast<double>(a.px[i] + bias * a.nx[i]));
    shadows.p_WO_y[r] = static_cast<float>(f.p_WC.y() + static_cast<double>(a.py[i] + bias * a.ny[i]));
    shadows.p_WO_z[r] = static_cast<float>(f.p_WC.z() + static_cast<double>(a.pz[i] + bias * a.nz[i]));
    shadows.d_W_x[r] = a.sdx[i];
    shadows.d_W_y[r] = a.sdy[i];
    shadows.d_W_z[r] = a.sdz[i];
    shadows.t_near[r] = 0.0f;
    shadows.t_far[r] = a.slen[i];
    pixel[r] = i;
  }
}

// Whether daylight adds less than f.half_negligible to every pixel of the band in every channel (frame.h,
// "Negligible daylight"): bounds from the band's highest and nearest hits, brightest albedo, steepest
// and shallowest rays and farthest s_end. Needs the hits, albedos and s_end of render_band.
HADAL_VECTOR_KERNEL bool daylight_negligible(const FrameSetup& f, const BandArrays& a, const float* t, const float* dz,
                                             std::size_t n) {
  if (!f.negligible_daylight) return false;
  // Sixteen lanes at a time (GCC's vector extension, as in forward_scatter.cc's convolve_row: GCC does
  // not vectorize a float max reduction by itself), then across the lanes and over the tail.
  typedef float Lanes __attribute__((vector_size(64)));
  typedef std::int32_t Mask __attribute__((vector_size(64)));
  constexpr std::size_t kLanes = 16;
  const Lanes inf = Lanes{} + kInf, zero = Lanes{};
  Lanes top_lanes = -inf, nearest_lanes = inf, dz_hi_lanes = -inf, dz_lo_lanes = inf, s_far_lanes = zero;
  Lanes albedo_r_lanes = zero, albedo_g_lanes = zero, albedo_b_lanes = zero;
  // (No helper functions: passing these vectors by value changes the ABI in the clones without them.)
  std::size_t i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    Lanes ti, z, pz, ar, ag, ab, s_end;
    std::memcpy(&ti, t + i, sizeof ti);
    std::memcpy(&z, dz + i, sizeof z);
    std::memcpy(&pz, a.pz.data() + i, sizeof pz);
    std::memcpy(&ar, a.ar.data() + i, sizeof ar);
    std::memcpy(&ag, a.ag.data() + i, sizeof ag);
    std::memcpy(&ab, a.ab.data() + i, sizeof ab);
    std::memcpy(&s_end, a.s_end.data() + i, sizeof s_end);
    const Mask hit = ti < inf;
    pz = hit ? pz : -inf;
    ar = hit ? ar : zero;
    ag = hit ? ag : zero;
    ab = hit ? ab : zero;
    top_lanes = top_lanes < pz ? pz : top_lanes;
    nearest_lanes = ti < nearest_lanes ? ti : nearest_lanes;
    albedo_r_lanes = albedo_r_lanes < ar ? ar : albedo_r_lanes;
    albedo_g_lanes = albedo_g_lanes < ag ? ag : albedo_g_lanes;
    albedo_b_lanes = albedo_b_lanes < ab ? ab : albedo_b_lanes;
    dz_hi_lanes = dz_hi_lanes < z ? z : dz_hi_lanes;
    dz_lo_lanes = z < dz_lo_lanes ? z : dz_lo_lanes;
    s_far_lanes = s_far_lanes < s_end ? s_end : s_far_lanes;
  }
  float top = -kInf, nearest = kInf, dz_hi = -kInf, dz_lo = kInf, s_far = 0.0f;
  float albedo_max[3] = {0.0f, 0.0f, 0.0f};
  for (std::size_t k = 0; k < kLanes; ++k) {
    top = fast::max(top, top_lanes[k]);
    nearest = fast::min(nearest, nearest_lanes[k]);
    albedo_max[0] = fast::max(albedo_max[0], albedo_r_lanes[k]);
    albedo_max[1] = fast::max(albedo_max[1], albedo_g_lanes[k]);
    albedo_max[2] = fast::max(albedo_max[2], albedo_b_lanes[k]);
    dz_hi = fast::max(dz_hi, dz_hi_lanes[k]);
    dz_lo = fast::min(dz_lo, dz_lo_lanes[k]);
    s_far = fast::max(s_far, s_far_lanes[k]);
  }
  for (; i < n; ++i) {
    const bool hit = t[i] < kInf;
    top = fast::max(top, hit ? a.pz[i] : -kInf);
    nearest = fast::min(nearest, t[i]);
    albedo_max[0] = fast::max(albedo_max[0], hit ? a.ar[i] : 0.0f);
    albedo_max[1] = fast::max(albedo_max[1], hit ? a.ag[i] : 0.0f);
    albedo_max[2] = fast::max(albedo_max[2], hit ? a.ab[i] : 0.0f);
    dz_hi = fast::max(dz_hi, dz[i]);
    dz_lo = fast::min(dz_lo, dz[i]);
    s_far = fast::max(s_far, a.s_end[i]);
  }
  const double g = f.phase_g;
  // p_HG(cos psi) with cos psi = d_z (the light travels straight down): largest at the highest d_z
  // when g >= 0, the lowest otherwise.
  const double phase = henyey_greenstein(g, g >= 0.0 ? dz_hi : dz_lo);
  for (int ch = 0; ch < 3; ++ch) {
    const double c = f.c[ch], Kd = f.Kd[ch];
    double bound = 0.0;
    if (f.sky && nearest < kInf) {
      const double below = std::max(0.0, static_cast<double>(f.surface_z) - top);
      const double at_hit = albedo_max[ch] * f.E0[ch] / kPi * std::exp(-Kd * below);
      const double forward = f.forward ? std::exp(-(c - f.forward_per_m[ch]) * nearest) : 0.0;
      bound += at_hit * (std::exp(-c * nearest) + forward);
    }
    if (f.daylit_water) {
      // int_0^S exp(-k s) ds, at least the integral over [s0, s1] of any of the band's rays.
      const double k = c - Kd * dz_hi, S = s_far;
      const double integral = k == 0.0 ? S : -std::expm1(-k * S) / k;
      bound += f.b[ch] * f.E_camera[ch] * phase * integral;
    }
    if (!(bound == 0.0 || bound < f.half_negligible[ch])) return false;  // (NaN: not negligible)
  }
  return true;
}

// Fresnel's unpolarised reflectance of the water-air interface for a ray making cos_w with the normal in the water
// (refractive index n) and cos_air in the air, either way (render/optics.h, water_to_air_reflectance).
inline float fresnel_reflectance(float n, float cos_w, float cos_air) {
  const float rs = (n * cos_w - cos_air) / (n * cos_w + cos_air);
  const float rp = (cos_w - n * cos_air) / (cos_w + n * cos_air);
  return 0.5f * (rs * rs + rp * rp);
}

// The sea surface seen from below, for the rays that leave the water before they hit anything (render/frame.h):
// inside Snell's window (the angle theta from the surface's normal below asin(1 / n)) the sky's radiance E0 / pi
// refracted in, T(theta) n^2 E0 / pi (Fresnel's unpolarised transmittance; n^2: radiance crowds into the narrower
// cone), plus the reflected share R(theta) of the water's upwelling path radiance under the surface; outside it total
// internal reflection, that upwelling radiance alone. Both attenuated by exp(-c s) over the ray's path s to the
// surface. The upwelling radiance is daylight's single scattering below the surface along the mirrored ray, b p(d)
// E0 / (c + Kd |d_z|) (render/optics.h): no seabed or vehicle is reflected.
void add_surface_from_below(const FrameSetup& f, const float* dx, const float* dy, const float* dz, const float* t,
                            std::size_t n, BandArrays& a) {
  const float mx = f.surface_n[0], my = f.surface_n[1], mz = f.surface_n[2];
  const float h = f.surface_z * mz;  // the plane m . p = h through (0, 0, surface_z), camera-relative
  const float n_w = f.refractive_index, sky_scale = n_w * n_w / 3.14159265358979f;
  const float g = f.phase_g, hg_scale = (1.0f - g * g) / (4.0f * 3.14159265358979f);
  for (std::size_t i = 0; i < n; ++i) {
    const float cos_w = mx * dx[i] + my * dy[i] + mz * dz[i];  // cos theta, the ray against the normal
    if (!(cos_w > 0.0f)) continue;
    const float s = h / cos_w;  // the path to the surface
    if (!(s < f.far_clip) || t[i] < s) continue;
    // Fresnel, water (n_w) to air (1): sin theta_air = n_w sin theta.
    const float sin_air2 = n_w * n_w * (1.0f - cos_w * cos_w);
    float reflectance = 1.0f;
    if (sin_air2 < 1.0f) reflectance = fresnel_reflectance(n_w, cos_w, std::sqrt(1.0f - sin_air2));
    // The mirrored ray's z in W (for the upwelling path radiance): d - 2 (d . m) m.
    const float z_down = dz[i] - 2.0f * cos_w * mz;
    const float up_z = z_down < 0.0f ? -z_down : 0.0f;
    const float denominator = 1.0f + g * g - 2.0f * g * z_down;
    const float phase = hg_scale / (denominator * std::sqrt(denominator));
    float* out[3] = {&a.sr[i], &a.sg[i], &a.sb[i]};
    for (int ch = 0; ch < 3; ++ch) {
      const float upwelling = f.b[ch] * phase * f.E0[ch] / (f.c[ch] + f.Kd[ch] * up_z);
      const float below = (1.0f - reflectance) * sky_scale * f.E0[ch] + reflectance * upwelling;
      *out[ch] += below * std::exp(-f.c[ch] * s);
    }
  }
}

// The sea surface seen from above (render/optics.h surface_from_above_radiance), for a camera in the air: a ray that
// reaches the surface's plane before it hits anything sees there the sky's radiance E0 / pi reflected, R(theta) of
// it (Fresnel, air to water), and the water's upwelling single-scattered daylight under the surface along the
// refracted ray, transmitted out, T / n^2 of it (n^2: the radiance of a widened cone); whatever the ray would have
// hit beyond is not seen (the water is not rendered from above) and its depth is the surface's (within the far clip;
// the sea itself goes on to the horizon). The surface is one plane, the waves' tangent plane under the camera: they
// tilt it, their crests and troughs are not drawn. A ray that misses going up sees the sky, E0 / pi.
void add_surface_from_above(const FrameSetup& f, const float* ray_C, const float* dx, const float* dy,
                            const float* dz, const float* t, std::size_t n, float* depth, BandArrays& a) {
  const float mx = f.surface_n[0], my = f.surface_n[1], mz = f.surface_n[2];
  const float h = f.surface_z * mz;  // the plane m . p = h through (0, 0, surface_z), camera-relative (h < 0)
  const float n_w = f.refractive_index, inv_pi = 1.0f / 3.14159265358979f;
  const float g = f.water_g, hg_scale = (1.0f - g * g) / (4.0f * 3.14159265358979f);
  for (std::size_t i = 0; i < n; ++i) {
    const float cos_d = mx * dx[i] + my * dy[i] + mz * dz[i];
    float* out[3] = {&a.sr[i], &a.sg[i], &a.sb[i]};
    if (!(cos_d < 0.0f)) {  // rising from the surface's plane: the sky where nothing is in the way
      if (!(t[i] < kInf)) {
        for (int ch = 0; ch < 3; ++ch) *out[ch] += f.E0[ch] * inv_pi;
      }
      continue;
    }
    const float s = h / cos_d;
    if (t[i] < s) continue;
    // Fresnel from air (1) into water (n_w): cos_i = -cos_d, sin theta_t = sin theta_i / n_w.
    const float cos_i = -cos_d, sin_t2 = (1.0f - cos_i * cos_i) / (n_w * n_w), cos_t = std::sqrt(1.0f - sin_t2);
    const float reflectance = fresnel_reflectance(n_w, cos_t, cos_i);
    // The refracted ray's z in W: d_t = d / n + (cos_i / n - cos_t) m.
    const float z_t = dz[i] / n_w + (cos_i / n_w - cos_t) * mz;
    const float down = z_t < 0.0f ? -z_t : 0.0f;
    const float denominator = 1.0f + g * g - 2.0f * g * z_t;
    const float phase = hg_scale / (denominator * std::sqrt(denominator));
    for (int ch = 0; ch < 3; ++ch) {
      const float upwelling = f.water_b[ch] * phase * f.E0[ch] / (f.water_c[ch] + f.Kd[ch] * down);
      *out[ch] = reflectance * f.E0[ch] * inv_pi + (1.0f - reflectance) / (n_w * n_w) * upwelling;
    }
    if (s < f.far_clip) depth[i] = s * ray_C[3 * i + 2];  // the sea goes on beyond the far clip, undepthed
  }
}

// The band of image rows [row_begin, row_end): its rays, shadow rays and shading. Writes the band's
// pixels of frame.radiance and frame.depth_m (and of forward_source when the water scatters forward);
// returns the number of shadow rays cast.
HADAL_VECTOR_KERNEL std::size_t render_band(const FrameSetup& f, int row_begin, int row_end, RadianceFrame& frame,
                        std::array<std::vector<float>, 3>* forward_source) {
  const Lens& lens = *f.lens;
  const std::size_t width = static_cast<std::size_t>(lens.width_px());
  const std::size_t first = static_cast<std::size_t>(row_begin) * width;
  const std::size_t n = static_cast<std::size_t>(row_end - row_begin) * width;
  const float* ray_C = lens.rays_C()[first].data();  // x, y, z per pixel (Eigen::Vector3f is 3 floats)
  const float far_clip = f.far_clip, bias = f.bias_m;
  const float c0 = f.c[0], c1 = f.c[1], c2 = f.c[2];

  const std::size_t sources = f.lights.size() + (f.sky ? 1 : 0);
  thread_local BandArrays a;
  a.resize(n, sources);
  // Primary rays: the lens's rays rotated into W, from the camera's centre.
  geometry::RayBatch& primary = a.primary;
  primary.coherence = geometry::RayCoherence::kCoherent;
  primary.p_WO_x.assign(n, static_cast<float>(f.p_WC.x()));
  primary.p_WO_y.assign(n, static_cast<float>(f.p_WC.y()));
  primary.p_WO_z.assign(n, static_cast<float>(f.p_WC.z()));
  primary.t_near.assign(n, f.near_clip);
  primary.t_far.assign(n, far_clip);
  if (f.ignore_body != geometry::kNoHit) primary.ignore_body.assign(n, f.ignore_body);
  primary.d_W_x.resize(n);
  primary.d_W_y.resize(n);
  primary.d_W_z.resize(n);
  float* dx = primary.d_W_x.data();
  float* dy = primary.d_W_y.data();
  float* dz = primary.d_W_z.data();
  {
    const Eigen::Matrix3f R = f.R_WC;
    const float r00 = R(0, 0), r01 = R(0, 1), r02 = R(0, 2), r10 = R(1, 0), r11 = R(1, 1), r12 = R(1, 2);
    const float r20 = R(2, 0), r21 = R(2, 1), r22 = R(2, 2);
#pragma GCC ivdep
    // The lens's rays are unit (to single precision) and R_WC a rotation: no need to normalize again
    // (RayBatch asks |d|^2 within 1e-5 of 1; this is within ~1e-6).
    for (std::size_t i = 0; i < n; ++i) {
      const float x = ray_C[3 * i], y = ray_C[3 * i + 1], z = ray_C[3 * i + 2];
      dx[i] = r00 * x + r01 * y + r02 * z;
      dy[i] = r10 * x + r11 * y + r12 * z;
      dz[i] = r20 * x + r21 * y + r22 * z;
    }
  }
  const geometry::RayHits& hits = a.hits;
  if (n > 0) f.scene->intersect(primary, 0, n, geometry::QueryPath::kAuto, a.hits);
  const float* t = hits.distance.data();

  // Hit points, normals turned towards the camera, depth along the optical axis.
  float* depth = frame.depth_m.data() + first;
  const float nan = std::numeric_limits<float>::quiet_NaN();
#pragma GCC ivdep
  for (std::size_t i = 0; i < n; ++i) {
    const float ti = t[i], x = dx[i], y = dy[i], z = dz[i], ray_z = ray_C[3 * i + 2];
    const float nx = hits.n_W_x[i], ny = hits.n_W_y[i], nz = hits.n_W_z[i];
    const bool hit = ti < kInf;
    const float d = hit ? ti : 0.0f;
    a.px[i] = d * x;
    a.py[i] = d * y;
    a.pz[i] = d * z;
    const float sign = nx * x + ny * y + nz * z > 0.0f ? -1.0f : 1.0f;
    a.nx[i] = sign * nx;
    a.ny[i] = sign * ny;
    a.nz[i] = sign * nz;
    const float along_axis = d * ray_z;
    depth[i] = hit & (along_axis > 0.0f) ? along_axis : nan;
    a.s_end[i] = hit ? ti : far_clip;
  }
  const SurfacePoints points{n,
                             f.p_WC,
                             a.px.data(),
                             a.py.data(),
                             a.pz.data(),
                             hits.material.data(),
                             hits.body.data(),
                             hits.tex_u.data(),
                             hits.tex_v.data()};
  (*f.albedo_of)(points, a.ar.data(), a.ag.data(), a.ab.data());
  // Daylight in this band: on the surfaces (the sky, the last source) and along the rays.
  const bool daylight = (f.sky || f.daylit_water) && !daylight_negligible(f, a, t, dz, n);
  const bool sky = f.sky && daylight, daylit_water = f.daylit_water && daylight;

  // Shadow rays proved clear (frame.h): the steepest slope of the ground under the band's shadow rays,
  // which run between its hit points and the lights (or straight up from the hit points).
  // The band's hit points (camera-relative) bound its shadow rays' origins, with the bias.
  Eigen::AlignedBox3f hit_box;
  for (std::size_t i = 0; i < n; ++i) {
    if (t[i] < kInf) hit_box.extend(Eigen::Vector3f(a.px[i], a.py[i], a.pz[i]));
  }
  if (!hit_box.isEmpty()) {
    hit_box.min() -= Eigen::Vector3f::Constant(0.01f + bias);
    hit_box.max() += Eigen::Vector3f::Constant(0.01f + bias);
  }
  float climb = kInf;  // a shadow ray climbing faster than this is clear (when also above the ground)
  float slope = 0.0f;
  bool field = false;
  if (f.height_field && (!f.lights.empty() || sky) && !hit_box.isEmpty()) {
    Eigen::AlignedBox2d region(hit_box.min().head<2>().cast<double>() + f.p_WC.head<2>(),
                               hit_box.max().head<2>().cast<double>() + f.p_WC.head<2>());
    {
      for (const Eigen::Vector2d& xy : f.light_xy_W) region.extend(xy);
      const double L = f.scene->static_height_field_max_slope(region).value_or(kInf);
      field = std::isfinite(L);
      slope = static_cast<float>(L);
      climb = static_cast<float>(1.001 * L + 1e-4);
    }
  }
  {
    const std::int32_t* body = hits.body.data();
#pragma GCC ivdep
    for (std::size_t i = 0; i < n; ++i) {
      const float nx = a.nx[i], ny = a.ny[i], nz = a.nz[i];
      const bool on_field = body[i] == geometry::kStaticBody;
      a.above[i] = field & on_field & (nz - slope * __builtin_sqrtf(nx * nx + ny * ny) >= 0.1f) ? 1.0f : 0.0f;
    }
  }

  // Where each light (then the sky) reaches the point, and the shadow rays that must be cast.
  geometry::RayBatch& shadows = a.shadows;  // occluded() only: traced incoherent whatever its coherence says
  std::vector<std::uint32_t>& shadow_pixel = a.shadow_pixel;
  std::vector<std::uint16_t>& shadow_source = a.shadow_source;
  // Each light: where it may light the point (in its beam, before the surface), the Lambertian term it
  // would give (render/optics.h), seen through the water over d_light + d_camera, and the shadow rays
  // to cast (from bias_m off the surface; none where the term is 0).
  for (std::size_t l = 0; l < f.lights.size(); ++l) {
    const BandLight L = f.lights[l];
    const float i0 = L.intensity[0] * kInvPi, i1 = L.intensity[1] * kInvPi, i2 = L.intensity[2] * kInvPi;
    float* lit = a.lit[l].data();
    float* out_r = a.contribution[3 * l].data();
    float* out_g = a.contribution[3 * l + 1].data();
    float* out_b = a.contribution[3 * l + 2].data();
#pragma GCC ivdep
    for (std::size_t i = 0; i < n; ++i) {
      const float px = a.px[i], py = a.py[i], pz = a.pz[i], nx = a.nx[i], ny = a.ny[i], nz = a.nz[i];
      const float ti = t[i], above = a.above[i], ar = a.ar[i], ag = a.ag[i], ab = a.ab[i];
      // From the shadow origin (bias_m off the surface) to the light.
      const float tx = L.x - (px + bias * nx), ty = L.y - (py + bias * ny), tz = L.z - (pz + bias * nz);
      const float distance = __builtin_sqrtf(tx * tx + ty * ty + tz * tz);
      const bool front = nx * tx + ny * ty + nz * tz > 0.0f;  // the light before the surface
      const bool in_beam = -(L.ax * tx + L.ay * ty + L.az * tz) > L.cos_outer * distance;
      const bool candidate = (ti < kInf) & (distance > bias) & front & in_beam;
      const float inv = 1.0f / distance;
      const float sx = tx * inv, sy = ty * inv, sz = tz * inv;
      a.sdx[i] = sx;
      a.sdy[i] = sy;
      a.sdz[i] = sz;
      a.slen[i] = distance - bias;
      // The Lambertian term at the hit point itself (from the light to the point).
      const float qx = px - L.x, qy = py - L.y, qz = pz - L.z;
      const float d2 = qx * qx + qy * qy + qz * qz;
      const float d_light = __builtin_sqrtf(d2);
      const float inv_d = 1.0f / d_light;
      const float ux = qx * inv_d, uy = qy * inv_d, uz = qz * inv_d;
      const float cos_incidence = -(nx * ux + ny * uy + nz * uz);
      const float cos_axis = fast::max(-1.0f, fast::min(1.0f, L.ax * ux + L.ay * uy + L.az * uz));
      const float edge = fast::max(0.0f, fast::min(1.0f, (L.outer_rad - fast::acos(cos_axis)) * L.inv_edge_rad));
      const float smooth = edge * edge * (3.0f - 2.0f * edge);
      const float beam = cos_axis >= L.cos_inner ? 1.0f : (cos_axis <= L.cos_outer ? 0.0f : smooth);
      const bool shade = candidate & (cos_incidence > 0.0f) & (d_light > 0.0f);
      const float irradiance = beam * cos_incidence / d2;
      const float g = shade ? irradiance : 0.0f;
      const float path = d_light + (ti < kInf ? ti : 0.0f);  // finite on a miss (g is 0 there)
      out_r[i] = g * ar * i0 * fast::exp(-c0 * path);
      out_g[i] = g * ag * i1 * fast::exp(-c1 * path);
      out_b[i] = g * ab * i2 * fast::exp(-c2 * path);
      // (Masks as 0/1 floats: GCC turns `lights & !clear ? ..` into branches, this into selects.)
      const float clear = (above != 0.0f) & (sz > climb * __builtin_sqrtf(sx * sx + sy * sy)) ? 1.0f : 0.0f;
      const float lights = g > 0.0f ? 1.0f : 0.0f;
      lit[i] = lights;
      a.cast[i] = lights * (1.0f - clear);
    }
    Eigen::AlignedBox3f extent = hit_box;
    extent.extend(Eigen::Vector3f(L.x, L.y, L.z));
    gather_shadow_rays(f, a, a.lit[l], n, static_cast<std::uint16_t>(l), extent, shadows, shadow_pixel, shadow_source);
  }
  // Daylight on the surface (render/optics.h daylight_surface_radiance): E0 exp(-(Kd depth + c d_camera))
  // times the sky's share (1 + n_z) / 2, where the hit sees up to the surface (a shadow ray straight up).
  const float floor_z = f.floor_z, surface_z = f.surface_z;
  const float Kd0 = f.Kd[0], Kd1 = f.Kd[1], Kd2 = f.Kd[2];
  if (sky) {
    const float e0 = f.E0[0] * kInvPi, e1 = f.E0[1] * kInvPi, e2 = f.E0[2] * kInvPi;
    float* lit = a.lit.back().data();
    float* out_r = a.contribution[3 * (sources - 1)].data();
    float* out_g = a.contribution[3 * (sources - 1) + 1].data();
    float* out_b = a.contribution[3 * (sources - 1) + 2].data();
#pragma GCC ivdep
    for (std::size_t i = 0; i < n; ++i) {
      const float ti = t[i], nz = a.nz[i], pz = a.pz[i], above = a.above[i], ar = a.ar[i], ag = a.ag[i], ab = a.ab[i];
      const float candidate = (ti < kInf) & (nz > -1.0f) & (pz > floor_z) ? 1.0f : 0.0f;
      a.sdx[i] = 0.0f;
      a.sdy[i] = 0.0f;
      a.sdz[i] = 1.0f;
      a.slen[i] = fast::max(0.0f, surface_z - pz);
      lit[i] = candidate;
      a.cast[i] = candidate * (1.0f - above);  // straight up climbs faster than any slope
      const float tilt = 0.5f * (1.0f + nz);
      const float share = candidate != 0.0f ? tilt : 0.0f;
      const float below = fast::max(0.0f, surface_z - pz);  // depth of the point [m]
      const float d = ti < kInf ? ti : 0.0f;
      out_r[i] = share * ar * e0 * fast::exp(-(Kd0 * below + c0 * d));
      out_g[i] = share * ag * e1 * fast::exp(-(Kd1 * below + c1 * d));
      out_b[i] = share * ab * e2 * fast::exp(-(Kd2 * below + c2 * d));
    }
    Eigen::AlignedBox3f extent = hit_box;  // and up to the surface
    if (!extent.isEmpty()) extent.max().z() = std::max(extent.max().z(), surface_z);
    gather_shadow_rays(f, a, a.lit.back(), n, static_cast<std::uint16_t>(sources - 1), extent, shadows, shadow_pixel,
                       shadow_source);
  }
  if (shadows.size() > 0) {
    std::vector<std::uint8_t>& blocked = a.blocked;
    blocked.resize(shadows.size());
    f.scene->occluded(shadows, 0, shadows.size(), blocked);
    for (std::size_t k = 0; k < blocked.size(); ++k) {
      if (blocked[k] == 0) continue;
      for (int ch = 0; ch < 3; ++ch) a.contribution[3 * std::size_t{shadow_source[k]} + static_cast<std::size_t>(ch)][shadow_pixel[k]] = 0.0f;
    }
  }
  // The surfaces' radiance at the camera: the sources' terms that reach it.
  for (std::size_t source = 0; source < f.lights.size() + (sky ? 1 : 0); ++source) {
    const float* in_r = a.contribution[3 * source].data();
    const float* in_g = a.contribution[3 * source + 1].data();
    const float* in_b = a.contribution[3 * source + 2].data();
#pragma GCC ivdep
    for (std::size_t i = 0; i < n; ++i) {
      a.sr[i] += in_r[i];
      a.sg[i] += in_g[i];
      a.sb[i] += in_b[i];
    }
  }
  // Forward scatter's source: the surfaces' radiance times exp(b_f d) - 1 (render/forward_scatter.h).
  if (f.forward) {
    float* source_r = (*forward_source)[0].data() + first;
    float* source_g = (*forward_source)[1].data() + first;
    float* source_b = (*forward_source)[2].data() + first;
    const float bf0 = f.forward_per_m[0], bf1 = f.forward_per_m[1], bf2 = f.forward_per_m[2];
    if (bf0 == bf1 && bf1 == bf2) {  // grey scattering (the default scenario's): one exponential, same bits
#pragma GCC ivdep
      for (std::size_t i = 0; i < n; ++i) {
        const float ti = t[i];
        const float d = ti < kInf ? ti : 0.0f;
        const float share = fast::exp(bf0 * d) - 1.0f;
        source_r[i] = a.sr[i] * share;
        source_g[i] = a.sg[i] * share;
        source_b[i] = a.sb[i] * share;
      }
    } else {
#pragma GCC ivdep
      for (std::size_t i = 0; i < n; ++i) {
        const float ti = t[i];
        const float d = ti < kInf ? ti : 0.0f;
        source_r[i] = a.sr[i] * (fast::exp(bf0 * d) - 1.0f);
        source_g[i] = a.sg[i] * (fast::exp(bf1 * d) - 1.0f);
        source_b[i] = a.sb[i] * (fast::exp(bf2 * d) - 1.0f);
      }
    }
  }
  // Backscatter of the lights, from the frame's table, along [s0, s_end].
  if (f.backscatter != nullptr) {
    for (int v = row_begin; v < row_end; ++v) {
      const std::size_t o = static_cast<std::size_t>(v - row_begin) * width;
      f.backscatter->add_row(v, a.s_end.data() + o, a.sr.data() + o, a.sg.data() + o, a.sb.data() + o);
    }
  }
  // Daylight's path radiance along [s0, s_end] (render/optics.h daylight_path_radiance): with k = c -
  // Kd d_z, b p(d_z) E_camera (exp(-k s0) - exp(-k s1)) / k; an upward ray ends at the surface.
  if (daylit_water) {
    const float g = f.phase_g;
    const float hg_scale = (1.0f - g * g) / (4.0f * 3.14159265358979f);
    const float s0 = f.s0;
    const float w0 = f.b[0] * f.E_camera[0], w1 = f.b[1] * f.E_camera[1], w2 = f.b[2] * f.E_camera[2];
    const auto integral = [s0](float k, float s1, bool bounded) {
      const float near = fast::exp(-k * s0);
      const float far_end = fast::exp(-k * s1);
      const float far = bounded ? far_end : 0.0f;
      const float magnitude = k < 0.0f ? -k : k;
      return magnitude * s1 < 1e-4f ? s1 - s0 : (near - far) / k;
    };
#pragma GCC ivdep
    for (std::size_t i = 0; i < n; ++i) {
      const float z = dz[i], s_end = a.s_end[i];
      const float up_end = fast::max(0.0f, surface_z / z);  // where an upward ray leaves the water
      const float s1 = z > 0.0f ? fast::min(s_end, up_end) : s_end;
      const float denominator = 1.0f + g * g - 2.0f * g * z;
      const float phase = hg_scale / (denominator * __builtin_sqrtf(denominator));
      const float weight = (s_end > s0) & (s1 > s0) ? phase : 0.0f;
      const bool bounded = s1 < kInf;
      a.sr[i] += weight * w0 * integral(c0 - Kd0 * z, s1, bounded);
      a.sg[i] += weight * w1 * integral(c1 - Kd1 * z, s1, bounded);
      a.sb[i] += weight * w2 * integral(c2 - Kd2 * z, s1, bounded);
    }
  }
  if (f.window) add_surface_from_below(f, dx, dy, dz, t, n, a);
  if (f.above) add_surface_from_above(f, ray_C, dx, dy, dz, t, n, depth, a);
  Rgbf* radiance = frame.radiance.data() + first;
  for (std::size_t i = 0; i < n; ++i) radiance[i] = Rgbf(a.sr[i], a.sg[i], a.sb[i]);
  return shadows.size();
}

}  // namespace

RadianceFrame render_radiance(const geometry::EmbreeScene& scene, const Lens& lens, const Eigen::Isometry3d& X_WC,
                              float near_clip, float far_clip, std::int32_t ignore_body, const FrameLighting& lighting,
                              const AlbedoAt& albedo_of, const ParallelFor& parallel) {
  return render_radiance(scene, lens, X_WC, near_clip, far_clip, ignore_body, lighting, per_point(albedo_of), parallel);
}

RadianceFrame render_radiance(const geometry::EmbreeScene& scene, const Lens& lens, const Eigen::Isometry3d& X_WC,
                              float near_clip, float far_clip, std::int32_t ignore_body, const FrameLighting& lighting,
                              const AlbedoOfPoints& albedo_of, const ParallelFor& parallel) {
  validate(lighting.water);
  validate(lighting.daylight);
  for (const SpotLight& light : lighting.lights) validate(light);
  if (lighting.backscatter_samples < 1 || lighting.backscatter_grid_px < 1) {
    throw std::invalid_argument("backscatter: need samples >= 1 and grid >= 1 px");
  }
  {
    geometry::RayBatch none;  // checks the clip and the pose before any work
    add_camera_rays(lens, X_WC, near_clip, far_clip, ignore_body, 0, 0, none);
  }
  if (lighting.lights.size() >= 0xffff) throw std::invalid_argument("lights: at most 65534 per frame");
  // A camera in the air (above the surface's plane) sees through clear air: no attenuation, scattering, backscatter
  // or marine snow; the surface below it is drawn from above (add_surface_from_above) with the water's optics.
  const bool above = lighting.daylight.surface_normal_W.z() * (X_WC.translation().z() - lighting.daylight.surface_z_m) > 0.0;
  FrameLighting air;
  if (above) {
    air = lighting;
    air.water.absorption_per_m = Rgb::Zero();
    air.water.scattering_per_m = Rgb::Zero();
    air.backscatter = nullptr;
    air.marine_snow.density_per_m3 = 0.0;
  }
  const FrameLighting& lit = above ? air : lighting;
  const std::size_t n = static_cast<std::size_t>(lens.width_px()) * static_cast<std::size_t>(lens.height_px());
  RadianceFrame frame;
  frame.width_px = lens.width_px();
  frame.height_px = lens.height_px();
  frame.radiance.resize(n);
  frame.depth_m.resize(n);

  FrameSetup f;
  f.scene = &scene;
  f.lens = &lens;
  f.albedo_of = &albedo_of;
  f.p_WC = X_WC.translation();
  f.R_WC = X_WC.linear().cast<float>();
  f.near_clip = near_clip;
  f.far_clip = far_clip;
  f.ignore_body = ignore_body;
  f.bias_m = lit.shadow_bias_m;
  const Rgb c = lit.water.attenuation_per_m();
  for (int ch = 0; ch < 3; ++ch) f.c[ch] = static_cast<float>(c[ch]);
  for (const SpotLight& light : lit.lights) {
    f.lights.push_back(band_light(light, f.p_WC));
    f.light_xy_W.push_back(light.p_WL.head<2>());
  }
  f.height_field = scene.static_height_field_max_slope().has_value();
  if (f.height_field) {
    for (const geometry::BodyBounds& bounds : scene.body_bounds_W()) {
      if (bounds.body == ignore_body) continue;
      BandBox box;
      for (int k = 0; k < 3; ++k) {
        box.lo[k] = static_cast<float>(bounds.box_W.min()[k] - f.p_WC[k]);
        box.hi[k] = static_cast<float>(bounds.box_W.max()[k] - f.p_WC[k]);
      }
      f.boxes.push_back(box);
    }
  }

  // Daylight: sky rays only above the depth where it falls below e^-87.3 of the surface's in every
  // channel (below floor_z; -inf: daylight everywhere).
  const Daylight& daylight = lit.daylight;
  double daylight_floor_z = std::numeric_limits<double>::infinity();
  for (int ch = 0; ch < 3; ++ch) {
    if (!(daylight.surface_irradiance_W_per_m2[ch] > 0.0)) continue;
    const double Kd = daylight.Kd_per_m[ch];
    daylight_floor_z = std::min(daylight_floor_z, Kd > 0.0 ? daylight.surface_z_m - 87.3 / Kd
                                                           : -std::numeric_limits<double>::infinity());
  }
  f.sky = std::isfinite(daylight_floor_z) || daylight_floor_z < 0.0;
  f.floor_z = static_cast<float>(daylight_floor_z - f.p_WC.z());
  f.surface_z = static_cast<float>(daylight.surface_z_m - f.p_WC.z());
  f.window = f.sky && f.surface_z > 0.0f;
  f.above = above;
  const Rgb water_c = lighting.water.attenuation_per_m();
  for (int ch = 0; ch < 3; ++ch) {
    f.water_c[ch] = static_cast<float>(water_c[ch]);
    f.water_b[ch] = static_cast<float>(lighting.water.scattering_per_m[ch]);
  }
  f.water_g = static_cast<float>(lighting.water.phase_g);
  for (int k = 0; k < 3; ++k) f.surface_n[k] = static_cast<float>(daylight.surface_normal_W[k]);
  f.refractive_index = static_cast<float>(daylight.refractive_index);
  for (int ch = 0; ch < 3; ++ch) {
    f.E0[ch] = static_cast<float>(daylight.surface_irradiance_W_per_m2[ch]);
    f.Kd[ch] = static_cast<float>(daylight.Kd_per_m[ch]);
  }

  // Scattered light along the rays: the lights' backscatter (from the table, up to s_max at most) and
  // daylight's path radiance (closed form).
  const double s0 = backscatter_start_m(near_clip);
  f.s0 = static_cast<float>(s0);
  const bool scattering = (lit.water.scattering_per_m > 0.0).any();
  f.daylit_water = scattering && (daylight.surface_irradiance_W_per_m2 > 0.0).any();
  const Rgb& negligible = lit.negligible_radiance_W_per_m2_sr;
  if (!negligible.allFinite() || (negligible < 0.0).any()) {
    throw std::invalid_argument("negligible radiance: need finite values >= 0");
  }
  for (int ch = 0; ch < 3; ++ch) f.half_negligible[ch] = 0.5 * negligible[ch];
  f.negligible_daylight = (negligible > 0.0).any();
  f.phase_g = static_cast<float>(lit.water.phase_g);
  // Daylight's irradiance at the rays' common origin, the camera's centre (in single precision, as the
  // rays hold it).
  const Rgb E_camera = daylight.irradiance_at(static_cast<float>(f.p_WC.z()));
  for (int ch = 0; ch < 3; ++ch) {
    f.b[ch] = static_cast<float>(lit.water.scattering_per_m[ch]);
    f.E_camera[ch] = static_cast<float>(E_camera[ch]);
  }
  std::shared_ptr<const BackscatterTable> backscatter = lit.backscatter;
  if (!backscatter) {
    backscatter = make_backscatter_table(lighting, lights_in_camera_frame(lit.lights, X_WC), lens, near_clip, far_clip,
                                         parallel);
  }
  f.backscatter = backscatter.get();
  // Forward scatter (render/forward_scatter.h): each surface pixel's radiance times exp(b_f d) - 1,
  // spread over the image after the bands.
  const Rgb forward_per_m = forward_scattering_per_m(lit.water);
  f.forward = (forward_per_m > 0.0).any();
  for (int ch = 0; ch < 3; ++ch) f.forward_per_m[ch] = static_cast<float>(forward_per_m[ch]);
  // R, G, B planes, every pixel written by the bands: kept by the thread that runs frames (a camera's
  // every frame), so that neither allocating nor zeroing ~4 MB (640x480) waits before the bands.
  // (A local reference: the bands' tasks, on other threads, must see this thread's planes, not their own.)
  thread_local std::array<std::vector<float>, 3> kept_forward_source;
  std::array<std::vector<float>, 3>& forward_source = kept_forward_source;
  if (f.forward) {
    for (std::vector<float>& plane : forward_source) plane.resize(n);
  }

  const int bands = (lens.height_px() + kBandRows - 1) / kBandRows;
  std::vector<std::size_t> band_shadow_rays(static_cast<std::size_t>(bands), 0);
  parallel(static_cast<std::size_t>(bands), [&](std::size_t band) {
    const int row_begin = static_cast<int>(band) * kBandRows;
    band_shadow_rays[band] =
        render_band(f, row_begin, std::min(row_begin + kBandRows, lens.height_px()), frame, &forward_source);
  });
  for (std::size_t count : band_shadow_rays) frame.shadow_rays += count;
  if (f.forward) {
    add_forward_scatter(*forward_scatter_kernel(lit.water, lens.spec().fx, lens.spec().fy), frame.width_px,
                        frame.height_px, forward_source, frame.radiance, parallel);
  }
  frame.snow_particles = add_marine_snow(lit.marine_snow, lens, X_WC, lit.water, lit.lights,
                                         frame.depth_m, frame.radiance, parallel);
  return frame;
}

}  // namespace hadal::render
