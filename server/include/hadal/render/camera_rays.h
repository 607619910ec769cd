// A camera's rays into the world and its depth image (docs/ARCHITECTURE.md, "Cameras").
//
// Frames (DESIGN: S sensor, like the body x forward, y left, z up; C the optical frame, z forward,
// x right, y down, as ROS REP 103 and OpenCV): a camera is mounted like every sensor, at X_BS on its
// link, and looks along x_S; its optical frame is X_SC = (R_SC, 0) with
//   z_C = x_S (forward),  x_C = -y_S (right),  y_C = -z_S (down).
// The pose of the optical frame in the world is X_WC = X_WB X_BS X_SC.
//
// Rays: one per pixel, row-major (index v * width + u), from the optical centre along the lens's ray
// table rotated into W, clipped to [near_clip, far_clip] measured along each ray (a range clip, which also
// holds for a fisheye's rays beyond 90 deg).
// Depth: metres along the optical axis (the z_C of the hit point, sensor_msgs/Image 32FC1 as ROS depth
// cameras publish it), NaN where the ray hits nothing within the clip or the hit is not in front of
// the camera (z_C <= 0, only a fisheye sees there).
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "hadal/geometry/ray_batch.h"
#include "hadal/render/lens.h"

namespace hadal::render {

// The rotation part of X_SC above (translation zero).
Eigen::Isometry3d X_SC();

// Appends the lens's width x height rays from the optical frame's pose X_WC to `batch` (coherent), each
// ignoring `ignore_body` (the camera's own vehicle, or geometry::kNoHit). Throws std::invalid_argument
// unless 0 <= near_clip < far_clip (far_clip may be +inf) and X_WC is finite.
void add_camera_rays(const Lens& lens, const Eigen::Isometry3d& X_WC, float near_clip, float far_clip,
                     std::int32_t ignore_body, geometry::RayBatch& batch);
// The same for the image rows [row_begin, row_end) only (0 <= row_begin <= row_end <= height).
void add_camera_rays(const Lens& lens, const Eigen::Isometry3d& X_WC, float near_clip, float far_clip,
                     std::int32_t ignore_body, int row_begin, int row_end, geometry::RayBatch& batch);

// Depth [m] of one ray: distance along the ray times the z of its unit direction in C, NaN for a miss
// or a point not in front of the camera.
inline float depth_along_axis_m(bool hit, float distance_m, float ray_C_z) {
  const float z = distance_m * ray_C_z;
  return hit && z > 0.0f ? z : std::numeric_limits<float>::quiet_NaN();
}

// The depth image [m] of the rays add_camera_rays() appended at index `first` of the batch whose hits
// these are: width x height floats, row-major.
std::vector<float> depth_image_m(const Lens& lens, const geometry::RayHits& hits, std::size_t first);

}  // namespace hadal::render
