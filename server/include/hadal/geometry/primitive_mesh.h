// Closed triangle meshes of collision primitives (hadal::CollisionShape), for surface hydrodynamics
// of links that have no mesh file.
//
// Box: 12 triangles, exact. Sphere, cylinder and capsule are solids of revolution about G's z axis:
// a profile (rho_k, z_k) from the top pole to the bottom pole revolved at `segments` longitudes
// phi_j = 2 pi j / segments; the sphere's profile has segments / 2 arcs pole to pole, each capsule
// hemisphere segments / 4 (at least 1). All vertices lie on the smooth surface, so the mesh is
// inscribed: the band between two profile points is a frustum of a regular N-gon pyramid (N-gon
// area (N/2) rho^2 sin(2 pi / N)), so the enclosed volume is exactly
//   V = (N/2) sin(2 pi / N) sum_k (z_k - z_k+1) (rho_k^2 + rho_k rho_k+1 + rho_k+1^2) / 3,
// (revolved_polyhedron_volume), below the smooth volume by 1 - sin(2 pi/N) / (2 pi/N) (0.64 % at
// N = 32) for a cylinder, plus the meridian polygon's deficit for the round parts.
// Triangles are counter-clockwise seen from outside (outward normals), the mesh is closed
// (every edge shared by exactly two triangles in opposite directions). Units: m.
#pragma once

#include <Eigen/Geometry>

#include <utility>
#include <vector>

#include "hadal/core/model.h"
#include "hadal/geometry/triangle_mesh.h"

namespace hadal::geometry {

constexpr int kPrimitiveSegments = 32;

// The surface of `shape` in its own frame G (segments >= 3; round shapes only).
TriangleMesh tessellate(const CollisionShape& shape, int segments = kPrimitiveSegments);

// The profile (rho, z) tessellate() revolves for a sphere, cylinder or capsule (empty for a box).
std::vector<std::pair<double, double>> revolution_profile(const CollisionShape& shape, int segments);
// Exact enclosed volume of `profile` revolved at `segments` longitudes (formula above) [m^3].
double revolved_polyhedron_volume(const std::vector<std::pair<double, double>>& profile, int segments);

// Appends `mesh` (positions in frame M) to `out` with positions X_AM * p_M, its indices, and its
// texture coordinates when either has them ((0, 0) for the vertices of one without); normals and
// materials are not carried over.
void append_transformed(const TriangleMesh& mesh, const Eigen::Isometry3d& X_AM, TriangleMesh* out);

// A vehicle's surface in its body frame B, the hydrodynamic mesh of the surface fluid model: per link
// its mesh (in L) if it has one, else its collision primitives tessellated with `segments`, moved by
// X_BL (and X_LG). Parts are appended in link order, each primitive's triangles contiguous; nothing
// is merged. Empty if no link has a mesh or collision shapes. A triangle's material
// (`triangle_materials`) is link_material(k, m): link k, and m the material of the link mesh's own
// triangle (its glTF material; 0 for primitives), so that a ray's hit names the link and the material
// it hit. `materials` stays empty (the ids are a code, not indices). The link meshes' texture
// coordinates come along (append_transformed), so a hit's RayHits::tex_u, tex_v are the link mesh's.
TriangleMesh vehicle_surface_B(const VehicleSpec& spec, int segments = kPrimitiveSegments);
// What ray casts see of the vehicle, in B: vehicle_surface_B with each link's `visual` mesh, where it has
// one, in place of its surface (same material codes, the visual mesh's own materials). Links that move on
// joints are left out: the ray-cast world holds one rigid mesh per vehicle, the viewer's scene one more per
// moving body (links_visual_A; docs/ARCHITECTURE.md, "Articulated vehicles").
TriangleMesh vehicle_visual_B(const VehicleSpec& spec, int segments = kPrimitiveSegments);
// What vehicle_visual_B has of each of the given links (its visual mesh, else its surface), link l moved
// into a frame A by its X_AL instead of X_BL: a moving body's mesh in its frame K (with Articulation's X_KL).
TriangleMesh links_visual_A(const VehicleSpec& spec, const std::vector<std::pair<int, Eigen::Isometry3d>>& X_AL,
                            int segments = kPrimitiveSegments);

// The material code of vehicle_surface_B: link k's mesh material m (m < kLinkMaterialStride).
inline constexpr std::uint32_t kLinkMaterialStride = 1u << 16;
inline constexpr std::uint32_t link_material(std::size_t link, std::uint32_t mesh_material) {
  return static_cast<std::uint32_t>(link) * kLinkMaterialStride + mesh_material;
}
inline constexpr std::size_t link_of_material(std::uint32_t code) { return code / kLinkMaterialStride; }
inline constexpr std::uint32_t mesh_material_of(std::uint32_t code) { return code % kLinkMaterialStride; }
// Whether vehicle_surface_B of these links has any face: some link has a non-empty mesh or collision
// shapes.
bool has_surface_geometry(const std::vector<LinkSpec>& links);
// Whether vehicle_visual_B has any face (a surface, or a visual mesh).
bool has_visual_geometry(const std::vector<LinkSpec>& links);

}  // namespace hadal::geometry
