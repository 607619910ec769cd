// A ray's hit on a triangle mesh recomputed in Hadal's own code from the triangle Embree found, so that
// the answer does not depend on which of Embree's kernels traced it (docs/ARCHITECTURE.md, "One ray-cast world";
// tests/regression/README.md, "Machines").
//
// Embree computes a hit's distance, normal and barycentrics with approximate reciprocals and fused
// multiply-adds that differ between its kernels (SSE4.2, AVX, AVX2, AVX-512) and between CPU vendors, and
// where a ray meets an edge or a vertex shared by several triangles, which of them it reports depends on
// that arithmetic too. refine_hit() recomputes the hit in double precision (Moeller-Trumbore) and, for a
// hit within a few rounding units of an edge or a vertex, or a grazing one, chooses among the triangles
// around it by a rule of its own: the nearest the ray meets. The result depends only on the mesh and the ray.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hadal::geometry {

// The triangles around each vertex position. Vertices at the same position (exactly) are one: meshes
// repeat a vertex where its normal or texture coordinates change (a cylinder's rim, a box's edges).
// position[v] is vertex v's position id (the lowest index at that position); the triangles using any
// vertex at position v are triangles[offsets[v] .. offsets[v + 1]).
struct VertexTriangles {
  std::vector<std::uint32_t> position;
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> triangles;
};
VertexTriangles vertex_triangles(const float* vertices, std::size_t num_vertices, const std::uint32_t* indices,
                                 std::size_t num_triangles);

// A mesh as the refinement reads it: x, y, z floats per vertex, three vertex indices per triangle, and
// the vertices' triangles.
struct RefinementMesh {
  const float* vertices = nullptr;
  const std::uint32_t* triangles = nullptr;
  const VertexTriangles* adjacency = nullptr;
};

struct RefinedHit {
  bool ok = false;         // false: the triangle is degenerate or the ray lies in its plane; keep Embree's
  std::uint32_t triangle = 0;  // the triangle chosen (Embree's, or a neighbour at an edge or vertex)
  double t = 0.0;          // ray parameter [m] (unit direction)
  double u = 0.0, v = 0.0; // barycentric coordinates of the hit on vertices 1 and 2 of `triangle`
  double n[3] = {0.0, 0.0, 0.0};  // unit normal (v1 - v0) x (v2 - v0), in the mesh's frame
};

// The hit of the ray o + t d (mesh frame, |d| = 1) given that Embree reported `triangle`. When the hit is
// certain -- farther than the zone (32 single-precision rounding units of the largest coordinate involved)
// from every edge of the triangle, and not grazing (cosine to its normal >= 0.05) -- it is that triangle's.
// Otherwise the candidates are the triangles around its three vertices (its 1-ring; vertices at one
// position are one) that the ray meets inside them within the zone, near Embree's distance (within 4
// zones / cosine); the chosen one is the nearest, ties by the deeper inside (the larger of the smallest
// distances to a triangle's edges), then by the lower index.
RefinedHit refine_hit(const RefinementMesh& mesh, std::uint32_t triangle, const double o[3], const double d[3]);

}  // namespace hadal::geometry
