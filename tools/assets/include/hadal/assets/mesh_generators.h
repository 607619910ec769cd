// Procedural test meshes (no files): closed solids with closed-form properties, vehicle hulls and
// seabed height fields. Everything is in Hadal's frame (z up, body x forward) and in metres;
// triangles are counter-clockwise seen from outside, so the right-hand-rule normal points outward.
//
// Closed solids are closed *by position*: vertices may be split where normals or texture
// coordinates change (flat box faces), but split copies are bitwise equal, so a position-welding
// edge check (compute_mesh_properties) sees every edge used exactly twice, in opposite directions.
//
// Closed forms for the tests (n = segments around the axis, k_n = (n / 2 pi) sin(2 pi / n) the
// area ratio of the inscribed regular n-gon to its circle):
//   box:       V = a b c, centroid = centre, I = V/12 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2)
//   cylinder:  an n-gon prism; see regular_polygon_area / regular_polygon_polar_moment
//   revolved:  (sphere, torpedo) between two rings at z_i, z_j the cross-section is a regular n-gon
//              whose circumradius is linear in z, so the volume is a sum of frustums (exact).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hadal::assets {

// A triangle mesh being generated (the same flat layout as hadal::geometry::TriangleMesh).
struct MeshData {
  std::string name;
  std::vector<float> positions;        // x y z per vertex [m]
  std::vector<float> normals;          // x y z per vertex (unit), or empty
  std::vector<float> uvs;              // u v per vertex, or empty
  std::vector<std::uint32_t> indices;  // 3 per triangle, counter-clockwise seen from outside

  std::size_t num_vertices() const { return positions.size() / 3; }
  std::size_t num_triangles() const { return indices.size() / 3; }
};

// Area-weighted vertex normals from the triangles (replaces `normals`).
void compute_vertex_normals(MeshData& mesh);

// Appends `other` to `mesh` (indices offset); both must carry the same attributes.
void append_mesh(MeshData& mesh, const MeshData& other);

// p <- R p + t for positions, n <- R n for normals; R must be a rotation (row-major 3x3).
void transform_mesh(MeshData& mesh, const double R[9], const double t[3]);

// Axis-aligned box with full extents size_{x,y,z} centred at center_{x,y,z}; 24 vertices (flat
// faces with normals and per-face UVs), 12 triangles.
MeshData make_box(double size_x, double size_y, double size_z, double center_x = 0.0,
                  double center_y = 0.0, double center_z = 0.0);

// UV sphere of radius r about the origin: `segments` >= 3 around z, `rings` >= 2 bands from pole
// to pole (single pole vertices, so no degenerate triangles); smooth normals, no UVs.
// Triangles: 2 * segments * (rings - 1).
MeshData make_uv_sphere(double radius, int segments, int rings);

// Closed cylinder of radius r and length `length` along z, centred at the origin: `segments` >= 3
// side quads, flat caps as triangle fans around a centre vertex. Triangles: 4 * segments.
MeshData make_cylinder(double radius, double length, int segments);

// Surface of revolution about z of a profile (z_k, r_k), k = 0..K-1, with z increasing and r_0 =
// r_{K-1} = 0 (the poles) and r_k > 0 in between. Closed; triangles 2 * segments * (K - 2).
MeshData make_revolved(const std::vector<double>& profile_z, const std::vector<double>& profile_r,
                       int segments);

// Torpedo-shaped AUV hull along body x (nose at +x): hemispherical nose, cylindrical body and an
// ogive (tangent circular-arc) tail of length 2.5 r ending in a point; total length `length` > 3.5
// r. `segments` around the axis, `profile_steps` points per curved section. Closed.
MeshData make_torpedo(double length, double radius, int segments, int profile_steps);
// The torpedo's profile before rotation (z along the axis, tail at -length/2), for closed forms.
void torpedo_profile(double length, double radius, int profile_steps,
                     std::vector<double>& profile_z, std::vector<double>& profile_r);

// Axis-aligned grid solid: cells between consecutive grid coordinates xs, ys, zs (strictly
// increasing) that `filled(i, j, k)` selects; the boundary between filled and empty cells becomes
// flat quads (own vertices per face, bitwise-shared positions). Closed; manifold when no two filled
// cells touch along an edge only (the frames below satisfy this).
struct GridSolid {
  std::vector<double> xs, ys, zs;
  std::vector<std::uint8_t> filled;  // (xs.size()-1) * (ys.size()-1) * (zs.size()-1), i fastest
  bool cell(int i, int j, int k) const;
  double volume() const;  // sum of filled cell volumes (closed form for the tests)
};
MeshData make_grid_solid(const GridSolid& solid, const std::string& name);

// ROV-like open frame: the 12 edges of a size_x * size_y * size_z box made of square bars of side
// `bar`, centred at the origin. One closed, manifold solid.
GridSolid box_frame_solid(double size_x, double size_y, double size_z, double bar);
// Lander: a box frame standing on four corner legs of length `leg_length` below it; the frame's
// bottom sits at z = leg_length, the feet at z = 0.
GridSolid lander_solid(double size_x, double size_y, double size_z, double bar, double leg_length);

// Seabed height field: (cells_x * cells_y) quads, 2 triangles each, over [-size_x/2, size_x/2] x
// [-size_y/2, size_y/2]; z = sum of `bumps` seeded Gaussian bumps of height up to `relief` [m].
// Normals from the analytic gradient, UVs in [0, 1]. Open: 2 (cells_x + cells_y) boundary edges.
struct SeabedSpec {
  int cells_x = 100, cells_y = 100;
  double size_x = 100.0, size_y = 100.0;  // [m]
  double relief = 5.0;                    // [m]
  int bumps = 24;
  std::uint64_t seed = 1;
};
MeshData make_seabed(const SeabedSpec& spec);
// Square grid whose triangle count is the closest to `triangles` (>= 2).
SeabedSpec seabed_for_triangles(std::int64_t triangles, double size, std::uint64_t seed);

// Regular n-gon with circumradius rho: area and polar second moment about its centre.
double regular_polygon_area(int n, double rho);
double regular_polygon_polar_moment(int n, double rho);

}  // namespace hadal::assets
