// Calibrated camera lenses: the intrinsics and distortion a real camera's calibration gives, the
// projection of a point in the camera's optical frame C to a pixel, and its exact inverse — the ray in C
// through a pixel — tabulated once per camera (docs/ARCHITECTURE.md, "Cameras").
//
// Frames and conventions (ROS REP 103/105, OpenCV):
//   C      optical frame: z forward along the optical axis, x right, y down; [m] or unitless directions.
//   pixel  (u, v) [px], u right and v down, the centre of pixel (i, j) at u = i, v = j (OpenCV's and
//          ROS CameraInfo's convention); the image spans u in [-0.5, width - 0.5].
//   normalized image coordinates (x, y) = (X/Z, Y/Z) of a point (X, Y, Z)_C; pixel = (fx x_d + cx,
//          fy y_d + cy) with (x_d, y_d) the distorted coordinates.
//
// Models (the paper's camera model, `render/lens` in its model map, with the fisheye added):
//   kPinhole          no distortion; reported as plumb_bob with D = 0.
//   kRadialTangential OpenCV's / ROS's plumb_bob, D = [k1, k2, p1, p2, k3]:
//                       r² = x² + y², radial = 1 + k1 r² + k2 r⁴ + k3 r⁶
//                       x_d = x radial + 2 p1 x y + p2 (r² + 2 x²)
//                       y_d = y radial + p1 (r² + 2 y²) + 2 p2 x y
//   kEquidistant      OpenCV's fisheye model, ROS's equidistant, D = [k1, k2, k3, k4]:
//                       θ = atan(r), θ_d = θ (1 + k1 θ² + k2 θ⁴ + k3 θ⁶ + k4 θ⁸), (x_d, y_d) = (θ_d / r)(x, y)
//                     Rays up to θ < π (behind the image plane) are representable; projection of such a
//                     ray uses θ = atan2(r, z).
// The inverse (pixel -> ray) is Newton's method on these equations from the distorted point, converged
// to a residual below 1e-9 px. A distortion that folds over inside the image (two directions on one
// pixel, as a strong barrel k1 does far from the centre) has no inverse there: make_lens() rejects it
// with the first pixel where that happens, so a ray table always describes a real, one-to-one lens.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/render/lens_model.h"

namespace hadal::render {



// "pinhole", "radial_tangential", "equidistant"; and back (false for an unknown name).
std::string_view to_string(LensModel model);
bool lens_model_from_string(std::string_view name, LensModel* model);

// A camera's calibration, as a calibration tool reports it. Distortion coefficients in the model's own
// order (above); unused entries are 0.
struct LensSpec {
  int width_px = 640;
  int height_px = 480;
  double fx = 500.0;  // focal length [px]
  double fy = 500.0;  // [px]
  double cx = 319.5;  // principal point [px]
  double cy = 239.5;  // [px]
  LensModel model = LensModel::kPinhole;
  std::array<double, 5> distortion{};  // plumb_bob: k1, k2, p1, p2, k3; equidistant: k1, k2, k3, k4, (0)
};

// The principal point in the centre of the image and square pixels with the given horizontal field of
// view [rad] (0 < hfov < π), for cameras configured by field of view instead of a calibration.
LensSpec lens_from_horizontal_fov(int width_px, int height_px, double hfov_rad);

// Distorted normalized coordinates of undistorted ones (pinhole and plumb_bob: (x, y) = (X/Z, Y/Z)).
Eigen::Vector2d distort(const LensSpec& lens, const Eigen::Vector2d& xy);

// The pixel (u, v) of a point p_C in the optical frame; false when the lens cannot see it (pinhole and
// plumb_bob: Z <= 0; equidistant: on or behind the camera's axis, θ >= π).
bool project(const LensSpec& lens, const Eigen::Vector3d& p_C, Eigen::Vector2d* uv_px);

// The ray camera tables, one unit direction in C per pixel, row-major (index v * width + u), through
// the pixel centres; computed once by make_lens().
class Lens {
 public:
  const LensSpec& spec() const { return spec_; }
  int width_px() const { return spec_.width_px; }
  int height_px() const { return spec_.height_px; }
  // Unit direction d_C through the centre of pixel (u, v); u in [0, width), v in [0, height).
  const Eigen::Vector3f& ray_C(int u, int v) const { return rays_C_[static_cast<std::size_t>(v) * spec_.width_px + u]; }
  const std::vector<Eigen::Vector3f>& rays_C() const { return rays_C_; }
  // Largest reprojection error of the table's rays (each ray projected back to its pixel) [px].
  double max_reprojection_error_px() const { return max_reprojection_error_px_; }

  // ROS sensor_msgs/CameraInfo as configured: distortion_model ("plumb_bob" or "equidistant"), D (5 or
  // 4 entries), K (3x3 row-major), R (identity: a monocular camera), P (3x4: K with a zero column).
  std::string distortion_model() const;
  std::vector<double> D() const;
  std::array<double, 9> K() const;
  std::array<double, 9> R() const;
  std::array<double, 12> P() const;

 private:
  friend Lens make_lens(const LensSpec& spec);
  LensSpec spec_;
  std::vector<Eigen::Vector3f> rays_C_;
  double max_reprojection_error_px_ = 0.0;
};

// Validates the calibration (image size 1..16384 px, fx, fy > 0 and finite, finite principal point and
// coefficients, the equidistant model's fifth coefficient 0) and tabulates the ray through every pixel
// centre; throws std::invalid_argument naming the offending field, or the first pixel where the
// distortion has no inverse.
Lens make_lens(const LensSpec& spec);

// The ray in C through an arbitrary pixel position (not only pixel centres), by the same inversion as
// the table: a unit vector, or false where the distortion has no inverse.
bool pixel_ray_C(const LensSpec& lens, const Eigen::Vector2d& uv_px, Eigen::Vector3d* d_C);

}  // namespace hadal::render
