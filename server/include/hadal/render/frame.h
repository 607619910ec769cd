// One camera frame's radiance and depth from the world (docs/ARCHITECTURE.md, "Cameras"): the lens's rays
// from X_WC cast into an Embree view, each hit lit by every spot light through the water (a shadow ray
// per light), plus single-scattering backscatter along the ray (render/optics.h). Surfaces are
// Lambertian and two-sided (a back face is lit as if its normal faced the camera).
//
// Per pixel (row-major, v * width + u):
//   radiance  [W/(m^2 sr)] per channel arriving at the camera: sum over lights of the Lambertian term
//             when the light sees the hit point (shadow ray from 'shadow_bias_m' off the surface to the
//             light; not cast when it provably reaches it: see below), daylight's Lambertian term when nothing is above the hit point (a shadow ray
//             straight up to the surface; none where daylight is below e^-87.3 of the surface's in
//             every channel), plus backscatter of the lights from near_clip to the hit
//             distance (to far_clip on a miss, or, with an infinite far clip, to
//             'max_backscatter_range_m'), looked up in the frame's BackscatterTable
//             (render/backscatter_table.h), and daylight's path radiance over the same range (closed
//             form, to infinity on a miss with an infinite far clip), plus, when the water's
//             forward_scatter_max_angle_rad is above 0, the surfaces' forward-scattered light spread
//             over the image (render/forward_scatter.h; backscatter and marine snow are not spread).
//   depth_m   metres along the optical axis, NaN on a miss (render/camera_rays.h).
// Shadow rays proved clear: when the static world is one height field of steepest slope L
// (EmbreeScene::static_height_field_max_slope), a shadow ray from a point on it whose origin lies above
// it (n_z - L |n_xy| >= 0.1 for the hit's unit normal n, with the 1 mm bias: 0.1 mm) and which climbs
// faster than L (d_z > (1.001 L + 1e-4) |d_xy|) stays above it all the way; if it also misses the
// bounding box of every body but the ignored one (EmbreeScene::body_bounds_W) nothing can block it,
// and it is not cast. The frame is the same bit for bit (frame_test.cc); shadow_rays counts the cast ones.
// Negligible daylight: deep down, daylight may add far less to a pixel than one count of the camera
// that sees it, and its shading, sky shadow rays and path radiance are then work for nothing. A band
// of rows leaves daylight out when, in every channel, B_surface + B_path < negligible / 2, with
//   B_surface = max albedo E0 / pi exp(-Kd (surface - highest hit)) (exp(-c d) + exp(-(c - b_f) d)),
//               d the nearest hit (the second term: its forward-scattered share, render/forward_scatter.h,
//               whose spread never raises a pixel above the brightest source pixel)
//   B_path    = b E_camera p_HG(d_z at the phase's peak over the band's rays) int_0^S exp(-k s) ds,
//               k = c - Kd max d_z, S the band's farthest s_end
// over the band's hits and rays: bounds on the terms render_band would add. A pixel changes by at
// most its own band's bound plus the brightest forward-scattered bound of another: less than
// 'negligible'.
// Work: the backscatter table's rows of nodes, then bands of kBandRows image rows (rays, shadow rays,
// shading), each a task of the ParallelFor given, then the forward-scatter spread (rows in tasks). Deterministic: a function of its inputs, the same
// whatever the threads (no random numbers; a band's rays are cast as one batch whatever thread casts
// it, and Embree's results are deterministic for the same rays and scene).
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "hadal/geometry/embree_scene.h"
#include "hadal/render/backscatter_table.h"
#include "hadal/render/lens.h"
#include "hadal/render/marine_snow.h"
#include "hadal/render/optics.h"

namespace hadal::render {

struct FrameLighting {
  WaterOptics water;
  std::vector<SpotLight> lights;
  Daylight daylight;  // none by default (the deep sea)
  // Midpoint samples per ray (render/optics.h). A light beside the camera puts a peak in the integrand
  // where the ray passes closest to it; 32 samples showed as horizontal banding in a 640x480 frame of
  // turbid water (b = 0.15 /m, lights 0.8 m off the axis), 128 did not.
  int backscatter_samples = 128;
  // Backscatter is integrated along the rays of every backscatter_grid_px-th pixel column and row and
  // interpolated between (render/backscatter_table.h); with 8 px and 128 samples it stays within 0.4 %
  // (60 deg lens) and 1.8 % (100 deg) of the frame's brightest backscatter from the exact integral
  // (backscatter_table_test.cc).
  int backscatter_grid_px = 8;
  float shadow_bias_m = 1e-3f;             // shadow rays start this far off the surface [m]
  double max_backscatter_range_m = 200.0;  // backscatter of a miss with an infinite far clip [m]
  MarineSnow marine_snow;  // none by default (density 0); drawn after the bands (render/marine_snow.h)
  // Radiance too faint to matter [W/(m^2 sr)] per channel (a camera's choice: image_sensor.h,
  // negligible_radiance): daylight is left out of a band of rows where a bound on what it adds there
  // is below half of this in every channel, so no pixel changes by as much as this (see "Negligible
  // daylight" above). Zero (the default): daylight is always computed.
  Rgb negligible_radiance_W_per_m2_sr = Rgb::Zero();
  // The frame's backscatter table if the caller already has it for these lights as this camera sees
  // them (BackscatterTableCache below); null: render_radiance makes one for the frame.
  std::shared_ptr<const BackscatterTable> backscatter;
};

using Rgbf = Eigen::Array3f;  // radiance of one pixel in single precision [W/(m^2 sr)]

struct RadianceFrame {
  int width_px = 0;
  int height_px = 0;
  std::vector<Rgbf> radiance;  // [W/(m^2 sr)]
  std::vector<float> depth_m;
  std::size_t shadow_rays = 0;  // shadow rays cast (lights and sky; not those proved clear), for statistics
  std::size_t snow_particles = 0;  // marine snow particles drawn
};

// The backscatter table render_radiance integrates for `lights_C`, the lights in the camera's optical
// frame C, with this lens and clip (the table depends only on where the lights are relative to the
// camera: the water is uniform). Null when nothing scatters (no lights, no scattering, or no range
// between the near clip and the far clip or max_backscatter_range_m). Throws as BackscatterTable does.
std::shared_ptr<const BackscatterTable> make_backscatter_table(const FrameLighting& lighting,
                                                               const std::vector<SpotLight>& lights_C, const Lens& lens,
                                                               float near_clip, float far_clip, const ParallelFor& parallel);

// Lights given in W (SpotLight's p_WL, axis_W) moved into the optical frame C of a camera posed at X_WC,
// as make_backscatter_table takes them (render_radiance does this when its lighting brings no table).
std::vector<SpotLight> lights_in_camera_frame(const std::vector<SpotLight>& lights_W, const Eigen::Isometry3d& X_WC);

// One camera's backscatter table, kept while its inputs stay the same: a camera whose lights ride on its
// own vehicle sees them in the same place in every frame, so their table (a fifth of a frame's work)
// is made once. get() compares the inputs (water, table settings, lens, clip and lights_C, exactly) with
// those of the kept table and makes a new one when any differs. Thread-safe.
class BackscatterTableCache {
 public:
  std::shared_ptr<const BackscatterTable> get(const FrameLighting& lighting, const std::vector<SpotLight>& lights_C,
                                              const std::shared_ptr<const Lens>& lens, float near_clip, float far_clip,
                                              const ParallelFor& parallel);
  std::size_t tables_made() const;  // how many get() has made (tests)

 private:
  mutable std::mutex mutex_;
  bool valid_ = false;
  WaterOptics water_;
  int samples_ = 0, grid_px_ = 0;
  double max_range_ = 0.0;
  std::shared_ptr<const Lens> lens_;
  float near_m_ = 0.0f, far_m_ = 0.0f;
  std::vector<SpotLight> lights_C_;
  std::shared_ptr<const BackscatterTable> table_;
  std::size_t made_ = 0;
};

// A surface point a camera ray hit, as the albedo function sees it (geometry::RayHits's fields).
struct SurfacePoint {
  std::uint32_t material = 0;  // RayHits::material
  std::int32_t body = 0;       // RayHits::body
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // the hit point in W [m] (for patterns)
  float tex_u = 0.0f, tex_v = 0.0f;  // RayHits::tex_u, tex_v: texture coordinates, NaN without
};

// The albedo (0..1 per channel) of a surface point. Called from several threads at once: a pure function.
using AlbedoAt = std::function<Rgb(const SurfacePoint& hit)>;

// The points a band of camera rays hit, as structure of arrays over `count` pixels (RayHits's fields and
// the hit points). A miss has material geometry::kInvalidIndex and body geometry::kNoHit; its albedo is
// not used.
struct SurfacePoints {
  std::size_t count = 0;
  Eigen::Vector3d origin_W = Eigen::Vector3d::Zero();  // the camera's centre in W [m]
  const float* x = nullptr;  // the hit point relative to origin_W, W axes: p_W = origin_W + (x, y, z) [m]
  const float* y = nullptr;
  const float* z = nullptr;
  const std::uint32_t* material = nullptr;
  const std::int32_t* body = nullptr;
  const float* tex_u = nullptr;
  const float* tex_v = nullptr;
  SurfacePoint point(std::size_t i) const {
    return SurfacePoint{material[i], body[i], origin_W + Eigen::Vector3d(x[i], y[i], z[i]), tex_u[i], tex_v[i]};
  }
};

// The albedo of every point of a band into r[i], g[i], b[i] (count floats each). Called from several
// threads at once, each with its own band.
using AlbedoOfPoints = std::function<void(const SurfacePoints& points, float* r, float* g, float* b)>;

// A per-point albedo function called for each point of a band.
AlbedoOfPoints per_point(AlbedoAt albedo_of);

// Image rows per rendering task: a band's per-pixel arrays (~50 values a pixel: ~0.5 MB at 640 px) stay
// well within a server core's L2 cache (1 MB here) with room for the other data a band touches, and
// 120 tasks for a 480-row frame keep two workers evenly busy to the end (docs/benchmarks.md, cameras:
// 16 rows were ~8 % slower than 8 on 2 workers, and 8 rows ~10 % slower than 4 in alternating runs;
// 2 rows gained nothing more).
constexpr int kBandRows = 4;

// Renders with `scene` as posed now (EmbreeScene::set_body_poses); `ignore_body` (the camera's own
// vehicle, or geometry::kNoHit) is passed through by camera and shadow rays alike. Throws
// std::invalid_argument for invalid water, lights or clip (validate(), add_camera_rays()) and
// backscatter_samples or backscatter_grid_px below 1.
RadianceFrame render_radiance(const geometry::EmbreeScene& scene, const Lens& lens, const Eigen::Isometry3d& X_WC,
                              float near_clip, float far_clip, std::int32_t ignore_body, const FrameLighting& lighting,
                              const AlbedoOfPoints& albedo_of, const ParallelFor& parallel = serial_for);
// The same with a per-point albedo function (per_point()).
RadianceFrame render_radiance(const geometry::EmbreeScene& scene, const Lens& lens, const Eigen::Isometry3d& X_WC,
                              float near_clip, float far_clip, std::int32_t ignore_body, const FrameLighting& lighting,
                              const AlbedoAt& albedo_of, const ParallelFor& parallel = serial_for);

}  // namespace hadal::render
