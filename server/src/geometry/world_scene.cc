#include "hadal/geometry/world_scene.h"

#include "hadal/geometry/primitive_mesh.h"

namespace hadal::geometry {

namespace {

constexpr float kPlaneHalfSize = 100000.0f;  // [m]

TriangleMesh plane_square(double z) {
  TriangleMesh mesh;
  const float h = kPlaneHalfSize, zf = static_cast<float>(z);
  mesh.positions = {-h, -h, zf, h, -h, zf, h, h, zf, -h, h, zf};
  mesh.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise from above: normal +z
  return mesh;
}

}  // namespace

EmbreeScene build_world_scene(const Model& model, const std::string& device_config) {
  EmbreeScene scene(device_config, model.world.ray_kernels);
  const SeabedSpec& seabed = model.world.seabed;
  // Heightmaps and procedural seabeds are grids of heights (a height field); a mesh file may be anything.
  if (seabed.mesh) {
    scene.add_static_mesh(*seabed.mesh, kSeabedMaterial, "seabed",
                          seabed.type == SeabedType::kMesh ? StaticShape::kAny : StaticShape::kHeightField);
  } else {
    scene.add_static_mesh(plane_square(seabed.z), kSeabedMaterial, "seabed plane", StaticShape::kHeightField);
  }
  for (std::size_t v = 0; v < model.vehicles.size(); ++v) {
    const VehicleSpec& vehicle = model.vehicles[v];
    if (!has_visual_geometry(vehicle.links)) continue;
    // An articulated vehicle's moving links are not in its mesh: one whose geometry is all on them has none.
    TriangleMesh mesh = vehicle_visual_B(vehicle);
    if (mesh.num_triangles() == 0) continue;
    scene.add_body_mesh(static_cast<int>(v), std::move(mesh), kVehicleMaterial, vehicle.name);
  }
  return scene;
}

}  // namespace hadal::geometry
