#include "hadal/geometry/world_scene.h"

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

// The link mesh (vertices in L) expressed in B.
TriangleMesh in_body_frame(const TriangleMesh& mesh_L, const Eigen::Isometry3d& X_BL) {
  TriangleMesh mesh_B = mesh_L;
  const Eigen::Matrix3f R = X_BL.linear().cast<float>();
  const Eigen::Vector3f t = X_BL.translation().cast<float>();
  for (std::size_t v = 0; v < mesh_B.num_vertices(); ++v) {
    Eigen::Map<Eigen::Vector3f> p(&mesh_B.positions[3 * v]);
    p = R * p + t;
  }
  for (std::size_t k = 0; k + 2 < mesh_B.normals.size(); k += 3) {
    Eigen::Map<Eigen::Vector3f> n(&mesh_B.normals[k]);
    n = R * n;
  }
  return mesh_B;
}

}  // namespace

EmbreeScene build_world_scene(const Model& model, const std::string& device_config) {
  EmbreeScene scene(device_config);
  const SeabedSpec& seabed = model.world.seabed;
  if (seabed.mesh) {
    scene.add_static_mesh(*seabed.mesh, kSeabedMaterial, "seabed");
  } else {
    scene.add_static_mesh(plane_square(seabed.z), kSeabedMaterial, "seabed plane");
  }
  for (std::size_t v = 0; v < model.vehicles.size(); ++v) {
    const VehicleSpec& vehicle = model.vehicles[v];
    for (const LinkSpec& link : vehicle.links) {
      if (!link.mesh || !link.mesh->mesh) continue;
      scene.add_body_mesh(static_cast<int>(v), in_body_frame(*link.mesh->mesh, link.X_BL), kVehicleMaterial,
                          vehicle.name + "/" + link.name);
    }
  }
  return scene;
}

}  // namespace hadal::geometry
