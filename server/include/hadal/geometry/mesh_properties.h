// Mesh properties computed once at load (structure of arrays, one entry per triangle).
//
// Per face: area A = |e1 x e2| / 2, unit normal n = (e1 x e2) / |e1 x e2|, centroid (a + b + c) / 3.
// Closed-mesh volume, centroid and inertia by the divergence theorem (exact for a closed, consistently
// oriented triangle mesh: signed tetrahedra from the origin, Mirtich / Eberly). A mesh is closed when
// every edge is shared by exactly two triangles with opposite orientation; for an open mesh the volume
// integrals are meaningless and `closed` is false (callers that need buoyancy warn).
#pragma once

#include "hadal/geometry/triangle_mesh.h"

#include <Eigen/Core>

#include <vector>

namespace hadal::geometry {

struct MeshProperties {
  std::vector<double> face_area;                          // [m^2]
  std::vector<double> normal_x, normal_y, normal_z;       // unit outward normals
  std::vector<double> centroid_x, centroid_y, centroid_z; // [m]
  double surface_area = 0.0;                              // [m^2]
  bool closed = false;
  std::size_t boundary_edges = 0;       // edges used by one triangle only
  std::size_t non_manifold_edges = 0;   // edges used by more than two, or twice in the same direction
  double volume = 0.0;                  // [m^3] (closed meshes; negative if oriented inward)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();            // of the enclosed volume [m]
  Eigen::Matrix3d inertia_unit_density = Eigen::Matrix3d::Zero(); // about `centroid`, for density 1 [m^5]
  Eigen::Vector3d bounds_min = Eigen::Vector3d::Zero(), bounds_max = Eigen::Vector3d::Zero();  // [m]
};

MeshProperties compute_mesh_properties(const TriangleMesh& mesh);

}  // namespace hadal::geometry
