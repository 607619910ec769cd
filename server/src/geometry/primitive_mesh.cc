#include "hadal/geometry/primitive_mesh.h"
#include "hadal/core/units.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace hadal::geometry {
namespace {


void add_vertex(const Eigen::Vector3d& p, TriangleMesh* mesh) {
  mesh->positions.push_back(static_cast<float>(p.x()));
  mesh->positions.push_back(static_cast<float>(p.y()));
  mesh->positions.push_back(static_cast<float>(p.z()));
}

void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, TriangleMesh* mesh) {
  mesh->indices.insert(mesh->indices.end(), {a, b, c});
}

TriangleMesh box_mesh(const Eigen::Vector3d& size) {
  TriangleMesh mesh;
  const Eigen::Vector3d h = 0.5 * size;
  for (int i = 0; i < 8; ++i) {
    add_vertex(Eigen::Vector3d((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z()),
               &mesh);
  }
  // Per face (axis a, side s): corners (b-, c-), (b+, c-), (b+, c+), (b-, c+) in the other two axes;
  // that cycle is counter-clockwise seen from +a for s = +1 when (a, b, c) is cyclic, so it is
  // reversed for the other side.
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int s : {-1, 1}) {
      std::uint32_t corner[4];
      const int bc[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int k = 0; k < 4; ++k) {
        corner[k] = static_cast<std::uint32_t>((s > 0 ? 1 << a : 0) | (bc[k][0] << b) | (bc[k][1] << c));
      }
      if (s < 0) std::swap(corner[1], corner[3]);
      add_triangle(corner[0], corner[1], corner[2], &mesh);
      add_triangle(corner[0], corner[2], corner[3], &mesh);
    }
  }
  return mesh;
}

// Profile points on the arc of radius r centred at (0, z_c), polar angles theta_0 .. theta_1 in
// `arcs` steps (both ends included).
void add_arc(double r, double z_c, double theta_0, double theta_1, int arcs,
             std::vector<std::pair<double, double>>* profile) {
  for (int k = 0; k <= arcs; ++k) {
    const double theta = theta_0 + (theta_1 - theta_0) * k / arcs;
    // sin(pi) is 1.2e-16, not 0: the poles are set exactly so they stay single vertices.
    const bool pole = (theta_0 == 0.0 && k == 0) || (theta_1 == kPi && k == arcs);
    profile->emplace_back(pole ? 0.0 : r * std::sin(theta), z_c + r * std::cos(theta));
  }
}

}  // namespace

std::vector<std::pair<double, double>> revolution_profile(const CollisionShape& shape, int segments) {
  std::vector<std::pair<double, double>> profile;
  const double r = shape.radius, h = 0.5 * shape.length;
  switch (shape.type) {
    case CollisionShapeType::kBox:
      break;
    case CollisionShapeType::kSphere:
      add_arc(r, 0.0, 0.0, kPi, std::max(segments / 2, 2), &profile);
      break;
    case CollisionShapeType::kCylinder:
      profile = {{0.0, h}, {r, h}, {r, -h}, {0.0, -h}};
      break;
    case CollisionShapeType::kCapsule: {
      const int arcs = std::max(segments / 4, 1);
      add_arc(r, h, 0.0, 0.5 * kPi, arcs, &profile);
      add_arc(r, -h, 0.5 * kPi, kPi, arcs, &profile);
      // A zero-length capsule (a sphere) would repeat the equator point.
      if (!(shape.length > 0.0)) profile.erase(profile.begin() + arcs + 1);
      break;
    }
  }
  return profile;
}

double revolved_polyhedron_volume(const std::vector<std::pair<double, double>>& profile, int segments) {
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < profile.size(); ++k) {
    const auto [r0, z0] = profile[k];
    const auto [r1, z1] = profile[k + 1];
    sum += (z0 - z1) * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0;
  }
  return 0.5 * segments * std::sin(2.0 * kPi / segments) * sum;
}

TriangleMesh tessellate(const CollisionShape& shape, int segments) {
  if (shape.type == CollisionShapeType::kBox) return box_mesh(shape.box_size);
  if (segments < 3) throw std::invalid_argument("tessellate: segments must be >= 3");
  const auto profile = revolution_profile(shape, segments);
  TriangleMesh mesh;
  // First vertex of each profile point: poles (rho = 0) are one vertex, other points a ring.
  std::vector<std::uint32_t> first;
  for (const auto& [rho, z] : profile) {
    first.push_back(static_cast<std::uint32_t>(mesh.num_vertices()));
    const int count = rho == 0.0 ? 1 : segments;
    for (int j = 0; j < count; ++j) {
      const double phi = 2.0 * kPi * j / segments;
      add_vertex(Eigen::Vector3d(rho * std::cos(phi), rho * std::sin(phi), z), &mesh);
    }
  }
  const auto n = static_cast<std::uint32_t>(segments);
  for (std::size_t k = 0; k + 1 < profile.size(); ++k) {
    const bool top_pole = profile[k].first == 0.0, bottom_pole = profile[k + 1].first == 0.0;
    const std::uint32_t a = first[k], b = first[k + 1];  // upper and lower ring
    for (std::uint32_t j = 0; j < n; ++j) {
      const std::uint32_t j1 = (j + 1) % n;
      // Seen from outside, lower ring -> next longitude -> upper ring is counter-clockwise.
      if (top_pole && bottom_pole) break;  // a degenerate profile segment along the axis
      if (top_pole) {
        add_triangle(b + j, b + j1, a, &mesh);
      } else if (bottom_pole) {
        add_triangle(b, a + j1, a + j, &mesh);
      } else {
        add_triangle(b + j, b + j1, a + j1, &mesh);
        add_triangle(b + j, a + j1, a + j, &mesh);
      }
    }
  }
  return mesh;
}

void append_transformed(const TriangleMesh& mesh, const Eigen::Isometry3d& X_AM, TriangleMesh* out) {
  const auto offset = static_cast<std::uint32_t>(out->num_vertices());
  // Texture coordinates go along when either mesh has them (0, 0 for the vertices of one without).
  if (!mesh.uvs.empty() || !out->uvs.empty()) {
    out->uvs.resize(2 * static_cast<std::size_t>(offset), 0.0f);
    if (mesh.uvs.size() == 2 * mesh.num_vertices()) {
      out->uvs.insert(out->uvs.end(), mesh.uvs.begin(), mesh.uvs.end());
    } else {
      out->uvs.resize(2 * (static_cast<std::size_t>(offset) + mesh.num_vertices()), 0.0f);
    }
  }
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d p_M(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
    add_vertex(X_AM * p_M, out);
  }
  for (std::uint32_t index : mesh.indices) out->indices.push_back(index + offset);
}

namespace {

// Link k's surface (or with `seen` its seen_mesh()) moved by X_AL, appended to mesh_A.
void append_link(const LinkSpec& link, std::size_t k, const Eigen::Isometry3d& X_AL, int segments, bool seen,
                 TriangleMesh& mesh_A) {
  const std::size_t first = mesh_A.num_triangles();
  const LinkMesh* own = seen ? link.seen_mesh() : (link.mesh && link.mesh->mesh ? &*link.mesh : nullptr);
  if (own) {
    const TriangleMesh& mesh_L = *own->mesh;
    append_transformed(mesh_L, X_AL, &mesh_A);
    // The link's triangles name the link and their own material (header).
    mesh_A.triangle_materials.resize(mesh_A.num_triangles(), link_material(k, 0));
    if (mesh_L.triangle_materials.size() == mesh_L.num_triangles()) {
      for (std::size_t t = 0; t < mesh_L.num_triangles(); ++t) {
        mesh_A.triangle_materials[first + t] =
            link_material(k, std::min(mesh_L.triangle_materials[t], kLinkMaterialStride - 1));
      }
    }
  } else {
    for (const CollisionShape& shape : link.collisions) {
      append_transformed(tessellate(shape, segments), X_AL * shape.X_LG, &mesh_A);
    }
    mesh_A.triangle_materials.resize(mesh_A.num_triangles(), link_material(k, 0));
  }
}

// vehicle_surface_B, or with `seen` each link's seen_mesh() in place of its own mesh.
TriangleMesh vehicle_mesh_B(const VehicleSpec& spec, int segments, bool seen) {
  TriangleMesh mesh_B;
  for (std::size_t k = 0; k < spec.links.size(); ++k) {
    if (seen && link_moves(spec.links, static_cast<int>(k))) continue;  // not drawn at q = 0 (header)
    append_link(spec.links[k], k, spec.links[k].X_BL, segments, seen, mesh_B);
  }
  return mesh_B;
}

}  // namespace

TriangleMesh vehicle_surface_B(const VehicleSpec& spec, int segments) { return vehicle_mesh_B(spec, segments, false); }

TriangleMesh vehicle_visual_B(const VehicleSpec& spec, int segments) { return vehicle_mesh_B(spec, segments, true); }

TriangleMesh links_visual_A(const VehicleSpec& spec, const std::vector<std::pair<int, Eigen::Isometry3d>>& X_AL,
                            int segments) {
  TriangleMesh mesh_A;
  for (const auto& [link, X] : X_AL) {
    append_link(spec.links.at(static_cast<std::size_t>(link)), static_cast<std::size_t>(link), X, segments, true,
                mesh_A);
  }
  return mesh_A;
}

bool has_visual_geometry(const std::vector<LinkSpec>& links) {
  return has_surface_geometry(links) || std::any_of(links.begin(), links.end(), [](const LinkSpec& link) {
           return link.visual && link.visual->mesh && link.visual->mesh->num_triangles() > 0;
         });
}

bool has_surface_geometry(const std::vector<LinkSpec>& links) {
  return std::any_of(links.begin(), links.end(), [](const LinkSpec& link) {
    return (link.mesh && link.mesh->mesh && link.mesh->mesh->num_triangles() > 0) || !link.collisions.empty();
  });
}

}  // namespace hadal::geometry
