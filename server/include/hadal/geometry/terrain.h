// Seabed terrain as a triangle mesh in the world frame W (z up, metres): from a regular height field
// (a 16-bit or 8-bit heightmap image, or procedural seeded bathymetry). Mesh files go through
// import_mesh (mesh_import.h).
//
// Height field: samples h[j][i] at p = (x0 + i dx, y0 + j dy), i in [0, nx), j in [0, ny); each cell
// becomes two triangles, counter-clockwise seen from above (normals point up, +z).
//
// Procedural bathymetry (all lengths in m, deterministic for a given seed):
//   h(x, y) = z_datum + tan(slope) (p . u) + w(r) [relief fbm(p / 120 m) + ridge_height ridged(p / 70 m)]
// with u a seeded horizontal direction, fbm 5-octave value noise in [-1, 1] (persistence 1/2),
// ridged(q) = (1 - |fbm(q)|)^2 in [0, 1], r = |p| and w(r) = smoothstep(plain_radius, 2 plain_radius, r):
// a flat sediment plain of radius plain_radius around the origin, rising into ridged, rougher terrain.
#pragma once

#include "hadal/geometry/terrain_spec.h"
#include "hadal/geometry/triangle_mesh.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hadal::geometry {

struct HeightField {
  int nx = 0, ny = 0;         // samples along x and y (>= 2 each)
  double dx = 1.0, dy = 1.0;  // sample spacing [m]
  double x0 = 0.0, y0 = 0.0;  // position of sample (0, 0) in W [m]
  std::vector<float> heights; // z in W [m], row-major: heights[j * nx + i]

  double height(int i, int j) const { return heights[static_cast<std::size_t>(j) * nx + i]; }
};

// Two triangles per cell; single material "seabed".
TriangleMesh heightfield_to_mesh(const HeightField& field);

struct HeightmapLoad {
  std::optional<HeightField> field;  // centred on the origin of W
  std::string error;                 // "<file>: <problem>"
};

HeightmapLoad load_heightmap(const HeightmapSpec& spec);

HeightField procedural_seabed(const ProceduralSeabedSpec& spec);

}  // namespace hadal::geometry
