#include "hadal/geometry/hit_refinement.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstring>
#include <vector>

namespace hadal::geometry {
namespace {

// A mesh for refine_hit: vertices, triangles and their adjacency, kept together.
struct Mesh {
  std::vector<float> vertices;
  std::vector<std::uint32_t> triangles;
  VertexTriangles adjacency;
  RefinementMesh view() const { return RefinementMesh{vertices.data(), triangles.data(), &adjacency}; }
};

Mesh make_mesh(std::vector<float> vertices, std::vector<std::uint32_t> triangles) {
  Mesh mesh{std::move(vertices), std::move(triangles), {}};
  mesh.adjacency = vertex_triangles(mesh.vertices.data(), mesh.vertices.size() / 3, mesh.triangles.data(),
                                    mesh.triangles.size() / 3);
  return mesh;
}

Eigen::Vector3d at(const Mesh& mesh, std::uint32_t v) {
  return Eigen::Vector3d(mesh.vertices[3 * v], mesh.vertices[3 * v + 1], mesh.vertices[3 * v + 2]);
}

RefinedHit refine(const Mesh& mesh, std::uint32_t triangle, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  return refine_hit(mesh.view(), triangle, o.data(), d.data());
}

// The hit point from the barycentrics on the chosen triangle is the point along the ray: within 1e-9 m
// (double rounding of coordinates ~ 10 m, with margin), so u and v belong to vertices 1 and 2.
void expect_consistent(const Mesh& mesh, const RefinedHit& hit, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  const std::uint32_t* tri = &mesh.triangles[3 * hit.triangle];
  const Eigen::Vector3d v0 = at(mesh, tri[0]);
  const Eigen::Vector3d p = v0 + hit.u * (at(mesh, tri[1]) - v0) + hit.v * (at(mesh, tri[2]) - v0);
  EXPECT_LT((p - (o + hit.t * d)).norm(), 1e-9);
}

// Bit for bit: the same triangle, distance, barycentrics and normal.
void expect_identical(const RefinedHit& a, const RefinedHit& b) {
  EXPECT_TRUE(a.ok && b.ok);
  EXPECT_EQ(a.triangle, b.triangle);
  EXPECT_EQ(std::memcmp(&a.t, &b.t, sizeof a.t), 0) << a.t << " vs " << b.t;
  EXPECT_EQ(std::memcmp(&a.u, &b.u, sizeof a.u), 0);
  EXPECT_EQ(std::memcmp(&a.v, &b.v, sizeof a.v), 0);
  EXPECT_EQ(std::memcmp(a.n, b.n, sizeof a.n), 0);
}

// A scalene triangle tilted out of every axis plane, hit inside at barycentrics (u, v) = (0.2, 0.3) from
// a point off its normal: the distance, both barycentrics (not swapped) and the normal's sign and
// direction, against the closed form. Tolerance 1e-12: double rounding of a well-conditioned system
// (det ~ 4) with coordinates ~ 10, about 1e-14, with margin.
TEST(HitRefinementTest, RecomputesDistanceBarycentricsAndNormalOfAScaleneTriangle) {
  const Mesh mesh = make_mesh({1.0f, 2.0f, -3.0f, 4.0f, 2.5f, -3.25f, 1.5f, 6.0f, -2.0f}, {0, 1, 2});
  const Eigen::Vector3d v0 = at(mesh, 0), v1 = at(mesh, 1), v2 = at(mesh, 2);
  const Eigen::Vector3d p = v0 + 0.2 * (v1 - v0) + 0.3 * (v2 - v0);
  const Eigen::Vector3d o(2.0, 3.0, 5.0);
  const Eigen::Vector3d d = (p - o).normalized();
  const RefinedHit hit = refine(mesh, 0, o, d);
  ASSERT_TRUE(hit.ok);
  EXPECT_EQ(hit.triangle, 0u);
  EXPECT_NEAR(hit.t, (p - o).norm(), 1e-12);
  EXPECT_NEAR(hit.u, 0.2, 1e-12);
  EXPECT_NEAR(hit.v, 0.3, 1e-12);
  const Eigen::Vector3d n = (v1 - v0).cross(v2 - v0).normalized();
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(hit.n[a], n[a], 1e-12) << "axis " << a;
  EXPECT_GT(hit.n[2], 0.5);  // counter-clockwise seen from above: the normal points up
}

// A ray in the triangle's plane has no hit to recompute: Embree's stands.
TEST(HitRefinementTest, ARayInTheTrianglesPlaneKeepsEmbreesHit) {
  const Mesh mesh = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
  EXPECT_FALSE(refine(mesh, 0, Eigen::Vector3d(-1, 0.2, 0), Eigen::Vector3d(1, 0, 0)).ok);
}

// A ridge: two triangles meeting at an angle along the edge A-B. A ray onto the edge, or within a few
// rounding units of it, gets the same answer whichever of the two Embree reported; a ray well inside one
// keeps it.
TEST(HitRefinementTest, AHitOnASharedEdgeIsTheSameWhicheverTriangleWasReported) {
  // A (0, -1, 1), B (0, 1, 1) on the ridge; C (-2, 0.2, 0) on the left, D (2.5, -0.3, -0.4) on the right.
  const Mesh mesh = make_mesh({0, -1, 1, 0, 1, 1, -2, 0.2f, 0, 2.5f, -0.3f, -0.4f}, {2, 0, 1, 0, 3, 1});
  const Eigen::Vector3d A = at(mesh, 0), B = at(mesh, 1);
  const Eigen::Vector3d o(0.7, -0.4, 6.0);
  for (const double offset : {0.0, 3e-8, -3e-8, 2e-7, -2e-7}) {
    const Eigen::Vector3d p = A + 0.37 * (B - A) + Eigen::Vector3d(offset, 0, 0);
    const Eigen::Vector3d d = (p - o).normalized();
    const RefinedHit from_left = refine(mesh, 0, o, d), from_right = refine(mesh, 1, o, d);
    SCOPED_TRACE(offset);
    expect_identical(from_left, from_right);
    expect_consistent(mesh, from_left, o, d);
    EXPECT_NEAR(from_left.t, (p - o).norm(), 1e-6);
  }
  // 1 mm into the right triangle: far outside the zone (32 float rounding units of 6 m, 2.3e-5 m).
  const Eigen::Vector3d p = A + 0.37 * (B - A) + Eigen::Vector3d(1e-3, 0, 0);
  const Eigen::Vector3d d = (p - o).normalized();
  EXPECT_EQ(refine(mesh, 1, o, d).triangle, 1u);
}

// Six triangles of different slopes around one vertex: a ray onto the vertex gets the same answer from
// each of them.
TEST(HitRefinementTest, AHitOnAVertexIsTheSameFromEveryTriangleAroundIt) {
  std::vector<float> vertices = {0.1f, -0.2f, 0.5f};  // the centre, vertex 0
  std::vector<std::uint32_t> triangles;
  for (int k = 0; k < 6; ++k) {
    const double angle = 2.0 * M_PI * k / 6.0 + 0.1 * k * k;
    const double radius = 1.0 + 0.15 * k;
    vertices.insert(vertices.end(), {static_cast<float>(radius * std::cos(angle)),
                                     static_cast<float>(radius * std::sin(angle)), static_cast<float>(0.1 * (k % 3))});
  }
  for (std::uint32_t k = 0; k < 6; ++k) triangles.insert(triangles.end(), {0, 1 + k, 1 + (k + 1) % 6});
  const Mesh mesh = make_mesh(vertices, triangles);
  const Eigen::Vector3d o(-0.8, 0.9, 4.0);
  const Eigen::Vector3d d = (at(mesh, 0) - o).normalized();
  const RefinedHit first = refine(mesh, 0, o, d);
  for (std::uint32_t k = 1; k < 6; ++k) {
    SCOPED_TRACE(k);
    expect_identical(refine(mesh, k, o, d), first);
  }
  expect_consistent(mesh, first, o, d);
  EXPECT_NEAR(first.t, (at(mesh, 0) - o).norm(), 1e-6);
}

// Meshes repeat a vertex where its normal changes (a box's edges): vertices at the same position are one
// for the adjacency, so such an edge is handled like a shared one.
TEST(HitRefinementTest, VerticesAtTheSamePositionAreJoined) {
  // The ridge of the edge test with the edge's vertices repeated for the right triangle (4, 5).
  const Mesh mesh = make_mesh({0, -1, 1, 0, 1, 1, -2, 0.2f, 0, 2.5f, -0.3f, -0.4f, 0, -1, 1, 0, 1, 1},
                              {2, 0, 1, 4, 3, 5});
  EXPECT_EQ(mesh.adjacency.position[4], 0u);
  EXPECT_EQ(mesh.adjacency.position[5], 1u);
  EXPECT_EQ(mesh.adjacency.position[3], 3u);
  const Eigen::Vector3d o(0.7, -0.4, 6.0);
  const Eigen::Vector3d d = (Eigen::Vector3d(0, -0.26, 1) - o).normalized();
  expect_identical(refine(mesh, 0, o, d), refine(mesh, 1, o, d));
}

// A ray that grazes a ridge (cosine 0.001 to both faces) enters it through the left face and leaves
// through the right one 0.2 mm further on, both crossings 0.1 mm from the crest: farther from the edge
// than the zone, but nearer each other than single precision resolves along so grazing a ray (~1 mm at
// 2 m). Reported the exit, the refinement finds the entry, the nearer hit.
TEST(HitRefinementTest, AGrazingRayGetsItsNearestCrossingWhicheverWasReported) {
  // Crest A (0, -1, 0) - B (0, 1, 0); left face down to C (-3, 0, -0.003), right face to D (3, 0.1, -0.003).
  const Mesh mesh = make_mesh({0, -1, 0, 0, 1, 0, -3, 0, -0.003f, 3, 0.1f, -0.003f}, {2, 0, 1, 0, 3, 1});
  const Eigen::Vector3d o(-2.0, 0.05, -1e-7);
  const Eigen::Vector3d d(1.0, 0.0, 0.0);
  const RefinedHit from_exit = refine(mesh, 1, o, d), from_entry = refine(mesh, 0, o, d);
  EXPECT_EQ(from_exit.triangle, 0u);
  expect_identical(from_exit, from_entry);
  expect_consistent(mesh, from_exit, o, d);
  // The left face is z = 0.001 x (its float vertices: within 1e-9 m): entered at x = -1e-4.
  EXPECT_NEAR(from_entry.t, 2.0 - 1e-4, 1e-6);
}

}  // namespace
}  // namespace hadal::geometry
