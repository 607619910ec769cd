// Mesh import with assimp: GLB, glTF (+ .bin, embedded data URIs), OBJ, STL -> TriangleMesh.
//
// One pass over the scene graph: every node's meshes are transformed by the node's accumulated
// transform, scaled by `scale`, converted from the file's up axis to Hadal's z-up frame, and appended
// to flat arrays. Base-colour factors and base-colour textures (decoded with OpenCV) are kept.
// Bad input never crashes and never yields a silently empty mesh: missing file, unsupported extension,
// truncated/corrupt GLB, glTF with a missing .bin, NaN/Inf vertices, meshes with no triangles all
// come back as one error naming the file and the problem. Degenerate (zero-area) triangles are
// dropped and counted.
//
// Vertex p of a mesh held by node N (file frame F, Hadal world frame W):
//   p_W = R_WF * scale * X_FN * p_N,   X_FN = X_F,root * ... * X_parent,N (accumulated transforms)
//   R_WF = identity for UpAxis::kZ; for UpAxis::kY +90 deg about x: (x, y, z) -> (x, -z, y).
// Normals use the inverse transpose of the linear part and are renormalised (rotated, not scaled);
// a node transform with a negative determinant (mirror) has its triangles' winding reversed so
// normals stay outward. Meshes without normals get area-weighted vertex normals; when some meshes
// carry UVs, the others get (0, 0). The per-mesh material becomes a per-triangle index into the
// materials actually used (triangle_materials stays empty when only one is used).
// Degenerate: repeated vertex indices, or an exactly zero cross product e1 x e2 (computed in double
// from the float positions: coincident or exactly collinear corners).
//
// Speed: assimp reads with no post-processing (aiProcess_Triangulate only when a mesh holds
// polygons; never aiProcess_ValidateDataStructure: the conversion checks every index itself), and
// the conversion runs on up to hardware_concurrency() threads for large meshes. GLB headers and
// chunk lengths are validated before assimp sees the file; referenced files (.bin, .mtl) are opened
// only if they are regular files. Hadal never installs an assimp logger, so assimp stays silent
// (its default NullLogger) and nothing is printed to stdout.
#pragma once

#include "hadal/geometry/mesh_import_options.h"
#include "hadal/geometry/triangle_mesh.h"

#include <optional>
#include <string>
#include <vector>

namespace hadal::geometry {

struct ImportResult {
  std::optional<TriangleMesh> mesh;  // set on success
  std::string error;                 // "<file>: <problem>" on failure
  std::size_t degenerate_triangles_dropped = 0;
  double load_seconds = 0.0;         // wall time of the whole import
  std::vector<std::string> warnings;  // "<file>: <problem>", non-fatal (e.g. an OBJ's missing .mtl)

  bool ok() const { return mesh.has_value(); }
};

ImportResult import_mesh(const std::string& path, const ImportOptions& options = {});

// The extensions import_mesh accepts (lower case, with the dot), in the order errors list them.
const std::vector<std::string>& supported_mesh_extensions();

// Blocks until every scene handed to the background thread so far has been freed (benchmarks,
// memory measurements).
void wait_for_background_cleanup();

}  // namespace hadal::geometry
