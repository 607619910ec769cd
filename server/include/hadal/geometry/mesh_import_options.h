// How a mesh file is read (geometry/mesh_import.h reads it): its units and up axis. A spec holding a
// mesh file's options (a link's, the seabed's) includes this, not the importer, and holds what the
// importer made by shared_ptr to the TriangleMesh declared here (defined in geometry/triangle_mesh.h).
#pragma once

namespace hadal::geometry {

struct TriangleMesh;

enum class UpAxis { kZ, kY };  // the file's up axis; kY (glTF's convention) is rotated +90 deg about x

struct ImportOptions {
  double scale = 1.0;  // file units -> metres, > 0
  UpAxis up_axis = UpAxis::kZ;
  bool load_textures = true;
  // Free assimp's scene on a background thread once its data has been copied out (assimp allocates
  // every face separately: ~20 ms per million triangles the caller need not wait for; only scenes
  // of 64k faces or more are handed over). false: freed before import_mesh returns.
  bool background_cleanup = true;
};

}  // namespace hadal::geometry
