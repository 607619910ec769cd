// Moving a TriangleMesh into another frame: p_A = X_AM p_M for every vertex, n_A = R_AM n_M for every
// vertex normal (float storage, the pose rounded to float once).
#pragma once

#include "hadal/geometry/triangle_mesh.h"

#include <Eigen/Geometry>

namespace hadal::geometry {

inline void transform_mesh(const Eigen::Isometry3d& X_AM, TriangleMesh* mesh) {
  const Eigen::Matrix3f R_AM = X_AM.linear().cast<float>();
  const Eigen::Vector3f p_AM = X_AM.translation().cast<float>();
  for (std::size_t v = 0; v < mesh->num_vertices(); ++v) {
    Eigen::Map<Eigen::Vector3f> p(&mesh->positions[3 * v]);
    p = R_AM * p + p_AM;
  }
  for (std::size_t k = 0; k + 2 < mesh->normals.size(); k += 3) {
    Eigen::Map<Eigen::Vector3f> n(&mesh->normals[k]);
    n = R_AM * n;
  }
}

}  // namespace hadal::geometry
