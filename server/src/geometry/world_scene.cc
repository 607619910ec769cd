#include "hadal/geometry/world_scene.h"

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

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

RayBodies::RayBodies(const Model& model) {
  const std::size_t n = model.vehicles.size();
  for (std::size_t v = 0; v < n; ++v) vehicle_.push_back(static_cast<int>(v));
  for (std::size_t v = 0; v < n; ++v) {
    link_body_.push_back(link_bodies(model.vehicles[v].links));
    first_moving_.push_back(count());
    const std::vector<int>& body = link_body_.back();
    const int bodies = body.empty() ? 1 : *std::max_element(body.begin(), body.end()) + 1;
    vehicle_.insert(vehicle_.end(), static_cast<std::size_t>(bodies - 1), static_cast<int>(v));
  }
}

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
  const RayBodies bodies(model);
  for (std::size_t v = 0; v < model.vehicles.size(); ++v) {
    const VehicleSpec& vehicle = model.vehicles[v];
    if (!has_visual_geometry(vehicle.links)) continue;
    // The base body: the links rigidly on B (vehicle_visual_B leaves the moving links out).
    TriangleMesh mesh = vehicle_visual_B(vehicle);
    if (mesh.num_triangles() > 0) {
      scene.add_body_mesh(static_cast<int>(v), std::move(mesh), kVehicleMaterial, vehicle.name);
    }
    // Each moving body: its links in B at q = 0, named after the link whose joint starts it.
    std::map<int, std::vector<std::pair<int, Eigen::Isometry3d>>> moving;  // ray body -> (link, X_BL)
    for (std::size_t l = 0; l < vehicle.links.size(); ++l) {
      const int b = bodies.of_link(static_cast<int>(v), static_cast<int>(l));
      if (b != static_cast<int>(v)) moving[b].emplace_back(static_cast<int>(l), vehicle.links[l].X_BL);
    }
    for (const auto& [b, X_BL] : moving) {
      TriangleMesh body_mesh = links_visual_A(vehicle, X_BL);
      if (body_mesh.num_triangles() == 0) continue;
      const std::string& name = vehicle.links[static_cast<std::size_t>(X_BL.front().first)].name;
      scene.add_body_mesh(b, std::move(body_mesh), kVehicleMaterial, vehicle.name + "/" + name);
    }
  }
  return scene;
}

}  // namespace hadal::geometry
