#include "hadal/geometry/primitive_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "hadal/geometry/mesh_properties.h"
#include "hadal/core/units.h"

namespace hadal::geometry {
namespace {

// Vertices are float: relative volume error a few float epsilons (1.2e-7) per term.
constexpr double kFloatRel = 1e-5;

CollisionShape shape(CollisionShapeType type, double radius, double length) {
  CollisionShape s;
  s.type = type;
  s.radius = radius;
  s.length = length;
  return s;
}

// Sphere or capsule: closed, outward (positive volume), and its volume: exactly the revolved
// polyhedron's (float rounding), and between volume_of(h_min) and volume_of(radius). The mesh is
// convex with its vertices on the smooth surface (so inside the smooth solid), and it contains the
// solid of radius h_min about the same axis segment (|z| <= length / 2), h_min being the smallest
// distance of a face plane from that segment (n . c minus n . the segment point nearest the face).
template <typename VolumeOf>
void expect_solid(const CollisionShape& s, VolumeOf volume_of) {
  const TriangleMesh mesh = tessellate(s);
  const MeshProperties properties = compute_mesh_properties(mesh);
  EXPECT_TRUE(properties.closed);
  EXPECT_EQ(properties.boundary_edges, 0u);
  EXPECT_EQ(properties.non_manifold_edges, 0u);
  const double polyhedron = revolved_polyhedron_volume(revolution_profile(s, kPrimitiveSegments),
                                                       kPrimitiveSegments);
  EXPECT_NEAR(properties.volume, polyhedron, kFloatRel * polyhedron);
  // Distance of each face plane from the centre of the round part it belongs to (capsule caps are
  // centred at z = +-length / 2, the cylindrical band at the axis).
  double h_min = s.radius;
  for (std::size_t f = 0; f < properties.face_area.size(); ++f) {
    const Eigen::Vector3d n(properties.normal_x[f], properties.normal_y[f], properties.normal_z[f]);
    Eigen::Vector3d c(properties.centroid_x[f], properties.centroid_y[f], properties.centroid_z[f]);
    c.z() -= std::clamp(c.z(), -0.5 * s.length, 0.5 * s.length);
    h_min = std::min(h_min, n.dot(c));
  }
  EXPECT_GT(h_min, 0.98 * s.radius);
  EXPECT_LT(properties.volume, volume_of(s.radius) * (1 + kFloatRel));
  EXPECT_GT(properties.volume, volume_of(h_min) * (1 - kFloatRel));
  EXPECT_NEAR(properties.centroid.norm(), 0.0, 1e-6);
}

TEST(PrimitiveMeshTest, BoxIsClosedOutwardAndExact) {
  CollisionShape box;
  box.box_size = Eigen::Vector3d(1.0, 0.4, 0.3);
  const MeshProperties properties = compute_mesh_properties(tessellate(box));
  EXPECT_TRUE(properties.closed);
  EXPECT_EQ(properties.face_area.size(), 12u);
  EXPECT_NEAR(properties.volume, 0.12, kFloatRel * 0.12);
  EXPECT_NEAR(properties.surface_area, 2 * (0.4 + 0.3 + 0.12), 1e-6);
}

// Cylinder: the N-gon prism, volume exactly (1 - e) pi r^2 l with e = 1 - sin(2 pi/N) / (2 pi/N)
// (0.64 % at N = 32).
TEST(PrimitiveMeshTest, CylinderVolumeWithinThePolygonBound) {
  const double r = 0.3, l = 1.2, x = 2 * kPi / kPrimitiveSegments;
  const CollisionShape cylinder = shape(CollisionShapeType::kCylinder, r, l);
  const MeshProperties properties = compute_mesh_properties(tessellate(cylinder));
  EXPECT_TRUE(properties.closed);
  EXPECT_EQ(properties.non_manifold_edges, 0u);
  EXPECT_NEAR(properties.volume,
              revolved_polyhedron_volume(revolution_profile(cylinder, kPrimitiveSegments), kPrimitiveSegments),
              kFloatRel * properties.volume);
  EXPECT_NEAR(properties.centroid.norm(), 0.0, 1e-6);
  EXPECT_NEAR(properties.volume, std::sin(x) / x * kPi * r * r * l, kFloatRel * properties.volume);
}

TEST(PrimitiveMeshTest, SphereAndCapsuleVolumesWithinThePolygonBound) {
  const double r = 0.5, l = 0.8;
  const auto ball = [](double h) { return 4.0 / 3.0 * kPi * h * h * h; };
  expect_solid(shape(CollisionShapeType::kSphere, r, 0.0), ball);
  expect_solid(shape(CollisionShapeType::kCapsule, r, l), [&](double h) { return ball(h) + kPi * h * h * l; });
  expect_solid(shape(CollisionShapeType::kCapsule, r, 0.0), ball);
}

TEST(PrimitiveMeshTest, AppendTransformedMovesVerticesAndOffsetsIndices) {
  CollisionShape box;
  box.box_size = Eigen::Vector3d(1.0, 1.0, 1.0);
  const TriangleMesh cube = tessellate(box);
  TriangleMesh both;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(5.0, 0.0, 0.0);
  append_transformed(cube, Eigen::Isometry3d::Identity(), &both);
  append_transformed(cube, X, &both);
  const MeshProperties properties = compute_mesh_properties(both);
  EXPECT_TRUE(properties.closed);
  EXPECT_NEAR(properties.volume, 2.0, 1e-5);
  EXPECT_NEAR(properties.centroid.x(), 2.5, 1e-5);
}

// A vehicle's surface: a link mesh is used as it is (moved by X_BL), a link without one contributes
// its collision primitives; the union of closed parts has the parts' summed volume.
TEST(PrimitiveMeshTest, VehicleSurfaceTakesLinkMeshesOrPrimitives) {
  CollisionShape box;
  box.type = CollisionShapeType::kBox;
  box.box_size = Eigen::Vector3d(1.0, 0.5, 0.25);
  VehicleSpec vehicle;
  LinkSpec hull;
  hull.collisions = {box, shape(CollisionShapeType::kSphere, 0.1, 0.0)};
  hull.collisions[1].X_LG.translation() = Eigen::Vector3d(2.0, 0.0, 0.0);
  LinkSpec meshed;
  meshed.X_BL.translation() = Eigen::Vector3d(0.0, 0.0, -3.0);
  meshed.collisions = {box};  // ignored: the link has a mesh
  LinkMesh mesh;
  mesh.mesh = std::make_shared<TriangleMesh>(tessellate(shape(CollisionShapeType::kCylinder, 0.2, 1.0)));
  meshed.mesh = mesh;
  vehicle.links = {hull, meshed};
  const TriangleMesh surface = vehicle_surface_B(vehicle);
  const std::size_t expected = tessellate(box).num_triangles() +
                               tessellate(hull.collisions[1]).num_triangles() + mesh.mesh->num_triangles();
  EXPECT_EQ(surface.num_triangles(), expected);
  const MeshProperties props = compute_mesh_properties(surface);
  const double volume = box.box_size.prod() +
                        compute_mesh_properties(tessellate(hull.collisions[1])).volume +
                        compute_mesh_properties(*mesh.mesh).volume;
  EXPECT_NEAR(props.volume, volume, kFloatRel * volume);
  EXPECT_NEAR(props.bounds_min.z(), -3.5, 1e-6);  // the cylinder (along z, 1 m) moved 3 m down
  EXPECT_EQ(vehicle_surface_B(VehicleSpec{}).num_triangles(), 0u);
}

}  // namespace
}  // namespace hadal::geometry
