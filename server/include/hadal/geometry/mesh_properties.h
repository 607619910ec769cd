// Mesh properties computed once at load (structure of arrays, one entry per triangle).
//
// Per face: area A = |e1 x e2| / 2, unit normal n = (e1 x e2) / |e1 x e2| (zero for a zero-area
// face), centroid (a + b + c) / 3, with e1 = b - a, e2 = c - a.
// Closed-mesh volume, centroid and inertia by the divergence theorem (exact for a closed, consistently
// oriented triangle mesh): signed tetrahedra (r, a, b, c) from a reference point r, the bounds'
// centre (keeps the sums well conditioned far from the origin); with a' = a - r etc., s = a' + b' + c':
//   V = sum v_f,                          v_f = a' . (b' x c') / 6
//   int (x - r) dV = sum v_f s / 4
//   int (x - r)(x - r)^T dV = sum v_f / 20 (a' a'^T + b' b'^T + c' c'^T + s s^T)
// then the centroid p_c and, with C = int (x - p_c)(x - p_c)^T dV, I = tr(C) 1 - C (unit density).
// Inward-oriented meshes give a negative volume and a negated inertia (the integrals are signed).
//
// Closedness: vertices are identified by exact position (bitwise-equal floats, -0 == +0), so meshes
// split at normal/UV seams and STL/OBJ (one vertex per corner) count like indexed ones. A mesh is
// closed when every edge is shared by exactly two triangles with opposite orientation; an edge used
// once is a boundary edge, anything else (three or more uses, or twice in the same direction) is
// non-manifold. The edge map is sort-based, no hashing into heap nodes: welding radix-sorts position
// hashes, edges are counting-sorted by their lower vertex into one flat array (4 bytes per directed
// edge); O(triangles). Meshes with 2^31 or more vertices are reported open without the check. For
// an open mesh the volume integrals are meaningless and `closed` is false (callers that need
// buoyancy warn). Large meshes use up to hardware_concurrency() threads; sums are reduced in a
// fixed order, so results do not depend on the thread count.
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

// Throws std::invalid_argument if positions or indices are not whole triples or an index is out of
// range (import_mesh never produces such a mesh).
MeshProperties compute_mesh_properties(const TriangleMesh& mesh);

// Second area moment of triangle (a, b, c) about its centroid m, per unit area:
// C = (1/A) int (x - m)(x - m)^T dA = (1/12) sum_k d_k d_k^T with d_k = vertex_k - m [m^2].
inline Eigen::Matrix3d triangle_second_moment(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                              const Eigen::Vector3d& c) {
  const Eigen::Vector3d m = (a + b + c) / 3.0;
  const Eigen::Vector3d da = a - m, db = b - m, dc = c - m;
  return (da * da.transpose() + db * db.transpose() + dc * dc.transpose()) / 12.0;
}

}  // namespace hadal::geometry
