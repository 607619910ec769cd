#include "hadal/render/camera_rays.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hadal::render {

Eigen::Isometry3d X_SC() {
  Eigen::Matrix3d R_SC;
  // Columns: the optical frame's axes x_C, y_C, z_C expressed in S.
  R_SC << 0.0, 0.0, 1.0,
         -1.0, 0.0, 0.0,
          0.0, -1.0, 0.0;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R_SC;
  return X;
}

void add_camera_rays(const Lens& lens, const Eigen::Isometry3d& X_WC, float near_clip, float far_clip,
                     std::int32_t ignore_body, geometry::RayBatch& batch) {
  add_camera_rays(lens, X_WC, near_clip, far_clip, ignore_body, 0, lens.height_px(), batch);
}

void add_camera_rays(const Lens& lens, const Eigen::Isometry3d& X_WC, float near_clip, float far_clip,
                     std::int32_t ignore_body, int row_begin, int row_end, geometry::RayBatch& batch) {
  if (!(0 <= row_begin && row_begin <= row_end && row_end <= lens.height_px())) {
    throw std::invalid_argument("camera rays: rows [" + std::to_string(row_begin) + ", " + std::to_string(row_end) +
                                ") outside the image's " + std::to_string(lens.height_px()));
  }
  if (!(near_clip >= 0.0f) || !(far_clip > near_clip)) {
    throw std::invalid_argument("camera clip: need 0 <= near < far (got near " + std::to_string(near_clip) +
                                " m, far " + std::to_string(far_clip) + " m)");
  }
  if (!X_WC.matrix().allFinite()) throw std::invalid_argument("camera pose X_WC is not finite");
  const Eigen::Matrix3f R_WC = X_WC.linear().cast<float>();
  const Eigen::Vector3f p_WC = X_WC.translation().cast<float>();
  batch.coherence = geometry::RayCoherence::kCoherent;
  const std::size_t width = static_cast<std::size_t>(lens.width_px());
  for (std::size_t i = static_cast<std::size_t>(row_begin) * width; i < static_cast<std::size_t>(row_end) * width; ++i) {
    batch.add_ray(p_WC, (R_WC * lens.rays_C()[i]).normalized(), near_clip, far_clip, ignore_body);
  }
}

std::vector<float> depth_image_m(const Lens& lens, const geometry::RayHits& hits, std::size_t first) {
  const std::size_t n = lens.rays_C().size();
  if (first + n > hits.size()) throw std::out_of_range("depth_image_m: the hits hold fewer rays than the camera's");
  std::vector<float> depth(n);
  for (std::size_t i = 0; i < n; ++i) {
    depth[i] = depth_along_axis_m(hits.hit(first + i), hits.distance[first + i], lens.rays_C()[i].z());
  }
  return depth;
}

}  // namespace hadal::render
