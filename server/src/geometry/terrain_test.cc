#include "hadal/geometry/terrain.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace hadal::geometry {
namespace {

Eigen::Vector3d vertex(const TriangleMesh& mesh, std::uint32_t index) {
  return Eigen::Vector3d(mesh.positions[3 * index], mesh.positions[3 * index + 1], mesh.positions[3 * index + 2]);
}

TEST(TerrainTest, HeightFieldBecomesTwoUpwardTrianglesPerCell) {
  HeightField field;
  field.nx = 3;
  field.ny = 2;
  field.dx = 2.0;
  field.dy = 5.0;
  field.x0 = -2.0;
  field.y0 = 10.0;
  field.heights = {-100.0f, -99.0f, -98.0f,   // j = 0
                   -101.0f, -100.5f, -97.0f};  // j = 1
  const TriangleMesh mesh = heightfield_to_mesh(field);
  ASSERT_EQ(mesh.num_vertices(), 6u);
  ASSERT_EQ(mesh.num_triangles(), 4u);  // (nx-1)(ny-1) cells x 2
  EXPECT_EQ(vertex(mesh, 0), Eigen::Vector3d(-2.0, 10.0, -100.0));
  EXPECT_EQ(vertex(mesh, 5), Eigen::Vector3d(2.0, 15.0, -97.0));
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d a = vertex(mesh, mesh.indices[3 * t]);
    const Eigen::Vector3d b = vertex(mesh, mesh.indices[3 * t + 1]);
    const Eigen::Vector3d c = vertex(mesh, mesh.indices[3 * t + 2]);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    EXPECT_GT(n.z(), 0.0) << "triangle " << t << " faces down";
    // Each cell is 2 m x 5 m: the two triangles' horizontal projections cover half of it each.
    EXPECT_DOUBLE_EQ(0.5 * std::abs(n.z()), 5.0);
  }
  ASSERT_EQ(mesh.materials.size(), 1u);
  EXPECT_EQ(mesh.materials[0].name, "seabed");
}

}  // namespace
}  // namespace hadal::geometry
