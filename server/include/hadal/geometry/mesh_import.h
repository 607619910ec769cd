// Mesh import with assimp: GLB, glTF (+ .bin, embedded data URIs), OBJ, STL -> TriangleMesh.
//
// One pass over the scene graph: every node's meshes are transformed by the node's accumulated
// transform, scaled by `scale`, converted from the file's up axis to Hadal's z-up frame, and appended
// to flat arrays. Base-colour factors and base-colour textures (decoded with OpenCV) are kept.
// Bad input never crashes and never yields a silently empty mesh: missing file, unsupported extension,
// truncated/corrupt GLB, glTF with a missing .bin, NaN/Inf vertices, meshes with no triangles all
// come back as one error naming the file and the problem. Degenerate (zero-area) triangles are
// dropped and counted.
#pragma once

#include "hadal/geometry/triangle_mesh.h"

#include <optional>
#include <string>

namespace hadal::geometry {

enum class UpAxis { kZ, kY };  // the file's up axis; kY (glTF's convention) is rotated +90 deg about x

struct ImportOptions {
  double scale = 1.0;  // file units -> metres, > 0
  UpAxis up_axis = UpAxis::kZ;
  bool load_textures = true;
};

struct ImportResult {
  std::optional<TriangleMesh> mesh;  // set on success
  std::string error;                 // "<file>: <problem>" on failure
  std::size_t degenerate_triangles_dropped = 0;
  double load_seconds = 0.0;         // wall time of the whole import
};

ImportResult import_mesh(const std::string& path, const ImportOptions& options = {});

}  // namespace hadal::geometry
