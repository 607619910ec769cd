#include "hadal/geometry/seabed_height.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hadal/geometry/terrain.h"

namespace hadal::geometry {
namespace {

// A tilted plane h = z0 + a x + b y as a 21 x 11 height field of 0.5 m cells: its triangles reproduce
// the plane exactly, so samples match it to the float precision of the vertices: 1e-5 m at |h| ~ 100 m,
// and the normal to that over the 0.5 m cells, 5e-5.
HeightField tilted(double a, double b, double z0) {
  HeightField field;
  field.nx = 21;
  field.ny = 11;
  field.dx = field.dy = 0.5;
  field.x0 = -5.0;
  field.y0 = -2.5;
  for (int j = 0; j < field.ny; ++j) {
    for (int i = 0; i < field.nx; ++i) {
      field.heights.push_back(static_cast<float>(z0 + a * (field.x0 + i * field.dx) + b * (field.y0 + j * field.dy)));
    }
  }
  return field;
}

TEST(SeabedHeight, PlaneIsEverywhere) {
  const SeabedHeight plane = SeabedHeight::plane(-42.0);
  SeabedHeight::Sample s;
  ASSERT_TRUE(plane.sample(1e6, -3e5, &s));
  EXPECT_EQ(s.height, -42.0);
  EXPECT_EQ(s.normal_W, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(plane.max_height_in(Eigen::AlignedBox2d(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1))), -42.0);
}

TEST(SeabedHeight, HeightFieldSamplesAreItsTrianglesPlane) {
  const double a = 0.2, b = -0.1, z0 = -100.0;
  const SeabedHeight seabed(heightfield_to_mesh(tilted(a, b, z0)));
  const Eigen::Vector3d normal = Eigen::Vector3d(-a, -b, 1.0).normalized();
  SeabedHeight::Sample s;
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0.13, 0.71), Eigen::Vector2d(-4.99, 2.49), Eigen::Vector2d(4.0, -1.0),
                                  Eigen::Vector2d(5.0, 2.5), Eigen::Vector2d(-5.0, -2.5)}) {
    ASSERT_TRUE(seabed.sample(p.x(), p.y(), &s)) << p.transpose();
    EXPECT_NEAR(s.height, z0 + a * p.x() + b * p.y(), 1e-5) << p.transpose();
    EXPECT_NEAR((s.normal_W - normal).norm(), 0.0, 5e-5);
  }
  EXPECT_FALSE(seabed.sample(5.01, 0.0, &s));
  EXPECT_FALSE(seabed.sample(0.0, -2.6, &s));
  // The bound over a region holds every height in it; far away there is no seabed.
  const Eigen::AlignedBox2d region(Eigen::Vector2d(1.0, -1.0), Eigen::Vector2d(2.0, 0.0));
  EXPECT_GE(seabed.max_height_in(region), z0 + a * 2.0 + b * -1.0 - 1e-5);
  EXPECT_LE(seabed.max_height_in(region), z0 + a * 3.0 + b * -1.5 + 1e-5);  // at most a cell beyond
  EXPECT_EQ(seabed.max_height_in(Eigen::AlignedBox2d(Eigen::Vector2d(50, 50), Eigen::Vector2d(60, 60))), -INFINITY);
}

// Where a mesh has two layers over a point (an overhang), the top one is the seabed.
TEST(SeabedHeight, TheTopLayerOfAnOverhangCounts) {
  TriangleMesh mesh;
  mesh.positions = {0, 0, -10, 4, 0, -10, 0, 4, -10,   // lower, facing up
                    0, 0, -8, 0, 4, -7, 4, 0, -9};     // upper, facing down (orientation does not matter)
  mesh.indices = {0, 1, 2, 3, 4, 5};
  const SeabedHeight seabed(mesh);
  SeabedHeight::Sample s;
  ASSERT_TRUE(seabed.sample(1.0, 1.0, &s));
  EXPECT_NEAR(s.height, -8.0 - 0.25 * 1.0 + 0.25 * 1.0, 1e-12);  // h = -8 - x/4 + y/4 on the upper one
  EXPECT_GT(s.normal_W.z(), 0.0);
}

}  // namespace
}  // namespace hadal::geometry
