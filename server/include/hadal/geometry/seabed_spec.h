// The seabed a scenario describes (YAML `world.seabed`): an infinite plane, or a triangle-mesh surface
// built at load time from a mesh file, a heightmap image or seeded procedural bathymetry
// (geometry/terrain.h). Its keys are declared once in geometry::seabed_keys()
// (server/src/geometry/seabed_spec.cc); configs/REFERENCE.md shows them.
#pragma once

#include <Eigen/Geometry>

#include <memory>
#include <string>

#include "hadal/config/key_table_fwd.h"
#include "hadal/geometry/mesh_import_options.h"
#include "hadal/geometry/terrain_spec.h"

namespace hadal {

namespace config {
struct LoadContext;
}

enum class SeabedType { kPlane, kMesh, kHeightmap, kProcedural };

struct SeabedSpec {
  SeabedType type = SeabedType::kPlane;
  double z = -100.0;  // plane: its height in W; procedural: height of the sediment plain [m]
  // kMesh: the file (resolved relative to the scenario), its units and up axis, and the pose X_WM of
  // the file's frame in W.
  std::string file;
  geometry::ImportOptions import;
  Eigen::Isometry3d X_WM = Eigen::Isometry3d::Identity();
  geometry::HeightmapSpec heightmap;          // kHeightmap (file in heightmap.file)
  geometry::ProceduralSeabedSpec procedural;  // kProcedural (z_datum = z)
  // The surface in W for every type but kPlane, built by the reader; shared, never modified.
  std::shared_ptr<const geometry::TriangleMesh> mesh;
};

namespace geometry {
// The keys of `world.seabed`. Reading builds the surface (a procedural seabed's seed defaults to the
// world's).
const config::KeyTable<SeabedSpec, config::LoadContext>& seabed_keys();
}  // namespace geometry

}  // namespace hadal
