#include "hadal/geometry/embree_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>
#include <optional>
#include <cstring>

namespace hadal::geometry {
namespace {

constexpr float kEps = std::numeric_limits<float>::epsilon();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Square [-h, h]^2 at height z, two triangles counter-clockwise seen from above (normal +z), split
// along the diagonal v0 (-h,-h) -> v2 (h,h): triangle 0 is below the diagonal (y < x), 1 above.
TriangleMesh flat_square(float h, float z) {
  TriangleMesh mesh;
  mesh.positions = {-h, -h, z, h, -h, z, h, h, z, -h, h, z};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

// Regular grid of n x n quads over [-h, h]^2 with heights z(x, y), counter-clockwise from above.
template <typename HeightFn>
TriangleMesh grid(int n, float h, HeightFn z) {
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float x = -h + 2.0f * h * static_cast<float>(i) / static_cast<float>(n);
      const float y = -h + 2.0f * h * static_cast<float>(j) / static_cast<float>(n);
      mesh.positions.insert(mesh.positions.end(), {x, y, z(x, y)});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const auto a = static_cast<std::uint32_t>(j * (n + 1) + i), b = a + 1;
      const auto c = a + static_cast<std::uint32_t>(n + 1), d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  }
  return mesh;
}

// Axis-aligned box with half extents (a, b, c) centred on the origin, outward winding.
TriangleMesh box(float a, float b, float c) {
  TriangleMesh mesh;
  for (int k = 0; k < 8; ++k) {
    mesh.positions.insert(mesh.positions.end(), {(k & 1) ? a : -a, (k & 2) ? b : -b, (k & 4) ? c : -c});
  }
  mesh.indices = {0, 2, 1, 1, 2, 3,  4, 5, 6, 5, 7, 6,  0, 1, 4, 1, 5, 4,
                  2, 6, 3, 3, 6, 7,  0, 4, 2, 2, 4, 6,  1, 3, 5, 3, 7, 5};
  return mesh;
}

RayBatch one_ray(const Eigen::Vector3f& p_WO, const Eigen::Vector3f& d_W, float t_near = 0.0f,
                 float t_far = kInf) {
  RayBatch batch;
  batch.add_ray(p_WO, d_W, t_near, t_far);
  return batch;
}

RayHits trace(const EmbreeScene& scene, const RayBatch& batch, QueryPath path = QueryPath::kAuto) {
  RayHits hits;
  hits.resize(batch.size());
  scene.intersect(batch, 0, batch.size(), path, hits);
  return hits;
}

Eigen::Vector3f normal(const RayHits& hits, std::size_t i) {
  return {hits.n_W_x[i], hits.n_W_y[i], hits.n_W_z[i]};
}

template <typename F>
std::string error_of(F f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(EmbreeScene, RayStraightDownOntoFlatTerrain) {
  EmbreeScene scene;
  const int id = scene.add_static_mesh(flat_square(500.0f, -100.0f), 7, "seabed");
  scene.build();
  const RayHits hits = trace(scene, one_ray({10.0f, -20.0f, 0.0f}, {0.0f, 0.0f, -1.0f}));
  ASSERT_TRUE(hits.hit(0));
  // Float intersection of exactly representable data: within a few ulp of 100 m.
  EXPECT_NEAR(hits.distance[0], 100.0f, 4 * kEps * 100.0f);
  // Axis-aligned edges give a normal with exact zeros; normalising by division keeps 1 exact.
  EXPECT_EQ(normal(hits, 0), Eigen::Vector3f(0.0f, 0.0f, 1.0f));
  EXPECT_EQ(hits.body[0], kStaticBody);
  EXPECT_EQ(hits.mesh[0], id);
  EXPECT_EQ(hits.material[0], 7u);
  EXPECT_EQ(hits.triangle[0], 0u);  // (10, -20) lies below the diagonal
  EXPECT_EQ(trace(scene, one_ray({-10.0f, 20.0f, 0.0f}, {0.0f, 0.0f, -1.0f})).triangle[0], 1u);
}

TEST(EmbreeScene, GridVerticesAndEdgesDoNotLetRaysThrough) {
  EmbreeScene scene;
  scene.add_static_mesh(grid(10, 50.0f, [](float, float) { return -100.0f; }));
  scene.build();
  RayBatch batch;
  for (int j = 1; j < 20; ++j) {
    for (int i = 1; i < 20; ++i) {  // every inner vertex and edge midpoint of the 10 m grid
      batch.add_ray({-50.0f + 5.0f * static_cast<float>(i), -50.0f + 5.0f * static_cast<float>(j), 0.0f},
                    {0.0f, 0.0f, -1.0f});
    }
  }
  for (QueryPath path : {QueryPath::kSingle, QueryPath::kPacket, QueryPath::kStream}) {
    const RayHits hits = trace(scene, batch, path);
    for (std::size_t i = 0; i < hits.size(); ++i) {
      ASSERT_TRUE(hits.hit(i)) << "ray " << i << " path " << to_string(path);
      EXPECT_NEAR(hits.distance[i], 100.0f, 4 * kEps * 100.0f);
    }
  }
}

TEST(EmbreeScene, TiltedPlaneNormalAndDistance) {
  // Plane through p0 = (0, 0, -100) with unit normal n = (1, 2, 5) / sqrt(30), as two triangles.
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, 2.0, 5.0).normalized();
  const Eigen::Vector3d u = n.cross(Eigen::Vector3d::UnitX()).normalized();
  const Eigen::Vector3d v = n.cross(u);  // (u, v, n) right-handed: counter-clockwise seen along -n
  const Eigen::Vector3d p0(0.0, 0.0, -100.0);
  TriangleMesh mesh;
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(-200, -200), Eigen::Vector2d(200, -200),
                                   Eigen::Vector2d(200, 200), Eigen::Vector2d(-200, 200)}) {
    const Eigen::Vector3d p = p0 + c.x() * u + c.y() * v;
    mesh.positions.insert(mesh.positions.end(),
                          {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
  }
  mesh.indices = {0, 1, 2, 0, 2, 3};
  EmbreeScene scene;
  scene.add_static_mesh(mesh);
  scene.build();
  const Eigen::Vector3f p_WO(3.0f, -4.0f, 0.0f);
  const RayHits hits = trace(scene, one_ray(p_WO, {0.0f, 0.0f, -1.0f}));
  ASSERT_TRUE(hits.hit(0));
  // The float vertices define the plane to ~1e-5 m and rotate it by ~1e-7 rad; the normal then
  // carries a few float ulp of error and the distance a few ulp of the 200 m coordinates.
  EXPECT_LT((normal(hits, 0).cast<double>() - n).norm(), 8 * kEps);
  const double expected = (p_WO.cast<double>() - p0).dot(n) / n.z();  // along -z to the plane
  EXPECT_NEAR(hits.distance[0], expected, 16 * kEps * 200.0);
}

TEST(EmbreeScene, MissGivesInfinity) {
  EmbreeScene scene;
  scene.add_static_mesh(flat_square(50.0f, -100.0f));
  scene.build();
  const RayHits hits = trace(scene, one_ray({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}));
  EXPECT_FALSE(hits.hit(0));
  EXPECT_EQ(hits.distance[0], kInf);
  EXPECT_EQ(normal(hits, 0), Eigen::Vector3f::Zero());
  EXPECT_EQ(hits.body[0], kNoHit);
  EXPECT_EQ(hits.mesh[0], kNoHit);
  EXPECT_EQ(hits.material[0], kInvalidIndex);
  EXPECT_EQ(hits.triangle[0], kInvalidIndex);
}

TEST(EmbreeScene, TFarAndTNearClip) {
  EmbreeScene scene;
  scene.add_static_mesh(flat_square(50.0f, -100.0f));
  scene.build();
  const Eigen::Vector3f p(0.0f, 1.0f, 0.0f), down(0.0f, 0.0f, -1.0f);
  EXPECT_FALSE(trace(scene, one_ray(p, down, 0.0f, 99.0f)).hit(0));
  EXPECT_TRUE(trace(scene, one_ray(p, down, 0.0f, 101.0f)).hit(0));
  EXPECT_FALSE(trace(scene, one_ray(p, down, 101.0f, kInf)).hit(0));
  EXPECT_TRUE(trace(scene, one_ray(p, down, 99.0f, 101.0f)).hit(0));
}

TEST(EmbreeScene, BackFaceNormalIsNotFlipped) {
  EmbreeScene scene;
  scene.add_static_mesh(flat_square(50.0f, -100.0f));
  scene.build();
  const RayHits hits = trace(scene, one_ray({1.0f, 2.0f, -150.0f}, {0.0f, 0.0f, 1.0f}));
  ASSERT_TRUE(hits.hit(0));
  EXPECT_NEAR(hits.distance[0], 50.0f, 4 * kEps * 150.0f);
  EXPECT_EQ(normal(hits, 0), Eigen::Vector3f(0.0f, 0.0f, 1.0f));  // dot(n, d) > 0: back face
}

TEST(EmbreeScene, PerTriangleMaterialsAddToTheMeshMaterialId) {
  TriangleMesh mesh = flat_square(50.0f, -100.0f);
  mesh.triangle_materials = {0, 1};
  mesh.materials.resize(2);
  EmbreeScene scene;
  scene.add_static_mesh(flat_square(10.0f, -120.0f), 3);  // below: must not shadow the square
  scene.add_static_mesh(mesh, 10);
  scene.build();
  EXPECT_EQ(trace(scene, one_ray({10.0f, -20.0f, 0.0f}, {0.0f, 0.0f, -1.0f})).material[0], 10u);
  EXPECT_EQ(trace(scene, one_ray({-10.0f, 20.0f, 0.0f}, {0.0f, 0.0f, -1.0f})).material[0], 11u);
}

// Texture coordinates of a hit interpolate the mesh's uvs over the hit triangle, the same on every
// query path (single rays, packets, streams) and on a posed body; NaN on a mesh without uvs and on a
// miss. The square's uvs are (x + h, y + h) / 2h, so a hit at (x, y) has tex (x / 2h + 1/2, y / 2h + 1/2)
// (float interpolation: within 1e-5).
TEST(EmbreeScene, HitsCarryTheMeshTextureCoordinates) {
  TriangleMesh textured = flat_square(10.0f, 0.0f);
  textured.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  EmbreeScene scene;
  scene.add_static_mesh(flat_square(100.0f, -100.0f), 1, "seabed");  // no uvs
  scene.add_body_mesh(0, textured, 2, "plate");
  scene.build();
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation() = Eigen::Vector3d(30.0, -20.0, -50.0);
  scene.set_body_poses({X_WB});
  RayBatch batch;
  batch.coherence = RayCoherence::kCoherent;
  std::vector<Eigen::Vector2f> expected;
  for (int k = 0; k < 37; ++k) {  // a row of points across the plate, both triangles
    const float x = -9.5f + 0.5f * static_cast<float>(k), y = 7.0f - 0.37f * static_cast<float>(k);
    batch.add_ray({30.0f + x, -20.0f + y, 0.0f}, {0.0f, 0.0f, -1.0f});
    expected.emplace_back(x / 20.0f + 0.5f, y / 20.0f + 0.5f);
  }
  batch.add_ray({60.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f});  // beside the plate: the seabed
  batch.add_ray({60.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f});   // up: nothing
  for (QueryPath path : {QueryPath::kSingle, QueryPath::kPacket, QueryPath::kStream}) {
    SCOPED_TRACE(to_string(path));
    RayHits hits;
    hits.resize(batch.size());
    scene.intersect(batch, 0, batch.size(), path, hits);
    for (std::size_t i = 0; i < expected.size(); ++i) {
      ASSERT_EQ(hits.body[i], 0);
      EXPECT_NEAR(hits.tex_u[i], expected[i].x(), 1e-5f) << i;
      EXPECT_NEAR(hits.tex_v[i], expected[i].y(), 1e-5f) << i;
    }
    const std::size_t seabed = expected.size(), miss = seabed + 1;
    ASSERT_EQ(hits.body[seabed], kStaticBody);
    EXPECT_TRUE(std::isnan(hits.tex_u[seabed]) && std::isnan(hits.tex_v[seabed]));
    ASSERT_FALSE(hits.hit(miss));
    EXPECT_TRUE(std::isnan(hits.tex_u[miss]) && std::isnan(hits.tex_v[miss]));
  }
  TriangleMesh bad = flat_square(1.0f, 0.0f);
  bad.uvs = {0, 0, 1, 0};
  EmbreeScene other;
  EXPECT_THROW(other.add_static_mesh(bad), std::invalid_argument);
}

// A static mesh declared a height field reports its steepest slope (a tilted plane z = 0.3 x + 0.1 y:
// sqrt(0.1) on every triangle); any other static mesh, declared or not, withdraws it; a declared mesh
// with a face turned down is an error. Body bounds are the posed box of the body's vertices, padded 1 cm.
TEST(EmbreeScene, HeightFieldSlopeAndBodyBounds) {
  const TriangleMesh tilted = grid(8, 10.0f, [](float x, float y) { return -100.0f + 0.3f * x + 0.1f * y; });
  {
    EmbreeScene scene;
    scene.add_static_mesh(tilted, 0, "seabed", StaticShape::kHeightField);
    scene.add_body_mesh(1, box(1.0f, 0.5f, 0.5f), 4, "hull");
    scene.build();
    ASSERT_TRUE(scene.static_height_field_max_slope().has_value());
    EXPECT_NEAR(*scene.static_height_field_max_slope(), std::sqrt(0.1), 1e-6);
    EXPECT_THROW(scene.body_bounds_W(), std::logic_error);  // no poses yet
    Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
    X_WB.translate(Eigen::Vector3d(10.0, 20.0, -50.0));
    X_WB.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
    scene.set_body_poses({Eigen::Isometry3d::Identity(), X_WB});
    const std::vector<BodyBounds> bounds = scene.body_bounds_W();
    ASSERT_EQ(bounds.size(), 1u);
    EXPECT_EQ(bounds[0].body, 1);
    EXPECT_TRUE(bounds[0].box_W.min().isApprox(Eigen::Vector3d(9.49, 18.99, -50.51), 1e-6)) << bounds[0].box_W.min().transpose();
    EXPECT_TRUE(bounds[0].box_W.max().isApprox(Eigen::Vector3d(10.51, 21.01, -49.49), 1e-6)) << bounds[0].box_W.max().transpose();
  }
  {
    EmbreeScene scene;
    scene.add_static_mesh(tilted, 0, "seabed", StaticShape::kHeightField);
    scene.add_static_mesh(flat_square(1.0f, -90.0f), 0, "rock");  // something above it: no longer a height field
    scene.build();
    EXPECT_FALSE(scene.static_height_field_max_slope().has_value());
  }
  {
    EmbreeScene scene;
    scene.add_static_mesh(tilted, 0, "seabed");
    scene.build();
    EXPECT_FALSE(scene.static_height_field_max_slope().has_value());
  }
  TriangleMesh down = flat_square(1.0f, 0.0f);
  down.indices = {0, 2, 1, 0, 3, 2};
  EmbreeScene scene;
  EXPECT_THROW(scene.add_static_mesh(down, 0, "upside down", StaticShape::kHeightField), std::invalid_argument);
}

TEST(EmbreeScene, BodyInstanceIsHitWhereItsPoseMovedIt) {
  EmbreeScene scene;
  scene.add_static_mesh(flat_square(500.0f, -100.0f), 1, "seabed");
  const int hull = scene.add_body_mesh(1, box(1.0f, 0.5f, 0.5f), 4, "hull");  // body 0 has no mesh
  scene.build();
  EXPECT_EQ(scene.num_bodies(), 2);
  EXPECT_THROW(trace(scene, one_ray({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f})), std::logic_error);

  // Body 1 at p_WB = (10, 20, -50), yawed +90 deg: B's x axis along W's y, B's y along W's -x.
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translate(Eigen::Vector3d(10.0, 20.0, -50.0));
  X_WB.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  scene.set_body_poses({Eigen::Isometry3d::Identity(), X_WB});

  RayBatch batch;
  batch.add_ray({10.0f, 20.8f, 0.0f}, {0.0f, 0.0f, -1.0f});   // onto the top face (B's x reaches y = 21)
  batch.add_ray({0.0f, 20.0f, -50.0f}, {1.0f, 0.0f, 0.0f});   // onto B's +y face, now facing W's -x
  batch.add_ray({10.0f, 21.2f, 0.0f}, {0.0f, 0.0f, -1.0f});   // beside the hull: the seabed
  const RayHits hits = trace(scene, batch);
  ASSERT_TRUE(hits.hit(0) && hits.hit(1) && hits.hit(2));
  EXPECT_NEAR(hits.distance[0], 49.5f, 4 * kEps * 50.0f);
  EXPECT_EQ(hits.body[0], 1);
  EXPECT_EQ(hits.mesh[0], hull);
  EXPECT_EQ(hits.material[0], 4u);
  EXPECT_LT((normal(hits, 0) - Eigen::Vector3f(0.0f, 0.0f, 1.0f)).norm(), 4 * kEps);
  // The half-width 0.5 of B's y now lies along W's x: the face is at x = 9.5.
  EXPECT_NEAR(hits.distance[1], 9.5f, 4 * kEps * 20.0f);
  EXPECT_EQ(hits.body[1], 1);
  // Embree reports the instanced normal in B; rotated into W it faces the ray (-x).
  EXPECT_LT((normal(hits, 1) - Eigen::Vector3f(-1.0f, 0.0f, 0.0f)).norm(), 4 * kEps);
  EXPECT_EQ(hits.body[2], kStaticBody);
  EXPECT_NEAR(hits.distance[2], 100.0f, 4 * kEps * 100.0f);

  // Moved back to the origin: the old place is empty, the new one is hit.
  X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation() = Eigen::Vector3d(0.0, 0.0, -50.0);
  scene.set_body_poses({Eigen::Isometry3d::Identity(), X_WB});
  EXPECT_EQ(trace(scene, batch).body[0], kStaticBody);
  const RayHits moved = trace(scene, one_ray({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}));
  EXPECT_EQ(moved.body[0], 1);
  EXPECT_NEAR(moved.distance[0], 49.5f, 4 * kEps * 50.0f);
}

// Views of one world share its geometry and pose their bodies independently: the hull at x = 0 in one
// view and at x = 30 in the other, the same ray sees each where its view put it; a view outlives the
// scene it was made from; a world without bodies is traced directly in every view.
TEST(EmbreeScene, ViewsShareTheWorldAndPoseTheirBodiesIndependently) {
  auto scene = std::make_unique<EmbreeScene>();
  scene->add_static_mesh(flat_square(500.0f, -100.0f), 1, "seabed");
  scene->add_body_mesh(0, box(1.0f, 0.5f, 0.5f), 4, "hull");
  EXPECT_THROW(scene->view(), std::logic_error);
  scene->build();
  EmbreeScene other = scene->view();
  EXPECT_EQ(other.num_bodies(), 1);
  EXPECT_EQ(other.num_meshes(), 2);
  EXPECT_EQ(other.num_static_triangles(), 2u);
  EXPECT_EQ(other.mesh_info(1).name, "hull");
  EXPECT_THROW(trace(other, one_ray({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f})), std::logic_error);  // not posed
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation() = Eigen::Vector3d(0.0, 0.0, -50.0);
  scene->set_body_poses({X_WB});
  X_WB.translation().x() = 30.0;
  other.set_body_poses({X_WB});
  const RayBatch down = one_ray({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f});
  EXPECT_EQ(trace(*scene, down).body[0], 0);
  EXPECT_NEAR(trace(*scene, down).distance[0], 49.5f, 4 * kEps * 50.0f);
  EXPECT_EQ(trace(other, down).body[0], kStaticBody);
  EXPECT_EQ(trace(other, one_ray({30.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f})).body[0], 0);
  scene.reset();  // the view keeps the world alive
  EXPECT_NEAR(trace(other, one_ray({30.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f})).distance[0], 49.5f, 4 * kEps * 50.0f);

  EmbreeScene still;
  still.add_static_mesh(flat_square(500.0f, -100.0f));
  still.build();
  const EmbreeScene still_view = still.view();
  EXPECT_NEAR(trace(still_view, down).distance[0], 100.0f, 4 * kEps * 100.0f);
}

TEST(EmbreeScene, BadMeshesAreClearErrors) {
  EmbreeScene scene;
  EXPECT_NE(error_of([&] { scene.add_static_mesh(TriangleMesh{}, 0, "seabed"); }).find("'seabed': empty mesh"),
            std::string::npos);
  TriangleMesh bad_index = flat_square(1.0f, 0.0f);
  bad_index.indices[4] = 9;
  EXPECT_NE(error_of([&] { scene.add_static_mesh(bad_index, 0, "rock"); })
                .find("'rock': triangle 1 has vertex index 9, out of range (the mesh has 4 vertices)"),
            std::string::npos);
  TriangleMesh nan_vertex = flat_square(1.0f, 0.0f);
  nan_vertex.positions[7] = std::nanf("");
  EXPECT_NE(error_of([&] { scene.add_static_mesh(nan_vertex); }).find("vertex 2 is not finite"), std::string::npos);
  TriangleMesh odd = flat_square(1.0f, 0.0f);
  odd.indices.pop_back();
  EXPECT_NE(error_of([&] { scene.add_static_mesh(odd); }).find("not a multiple of 3"), std::string::npos);
  TriangleMesh materials = flat_square(1.0f, 0.0f);
  materials.triangle_materials = {0};
  EXPECT_NE(error_of([&] { scene.add_static_mesh(materials); }).find("triangle_materials has 1 entries for 2"),
            std::string::npos);
  materials.triangle_materials = {0, 2};
  materials.materials.resize(2);
  EXPECT_NE(error_of([&] { scene.add_static_mesh(materials); }).find("triangle 1 has material 2, out of range"),
            std::string::npos);
  EXPECT_THROW(scene.add_body_mesh(-1, box(1, 1, 1)), std::invalid_argument);
  EXPECT_THROW(scene.build(), std::logic_error);  // nothing valid was added
  EXPECT_THROW(scene.mesh_info(0), std::out_of_range);

  scene.add_static_mesh(flat_square(1.0f, 0.0f));
  scene.build();
  EXPECT_THROW(scene.add_static_mesh(flat_square(1.0f, 0.0f)), std::logic_error);
  EXPECT_THROW(scene.build(), std::logic_error);
}

TEST(EmbreeScene, BadPosesAreClearErrors) {
  EmbreeScene scene;
  scene.add_body_mesh(2, box(1, 1, 1));
  scene.build();
  EXPECT_NE(error_of([&] { scene.set_body_poses({}); }).find("0 body poses for 3 bodies"), std::string::npos);
  std::vector<Eigen::Isometry3d> poses(3, Eigen::Isometry3d::Identity());
  poses[2].linear() *= 2.0;
  EXPECT_NE(error_of([&] { scene.set_body_poses(poses); }).find("X_WB of body 2 is not a rigid transform"),
            std::string::npos);
  poses[2] = Eigen::Isometry3d::Identity();
  poses[2].translation().x() = std::nan("");
  EXPECT_NE(error_of([&] { scene.set_body_poses(poses); }).find("X_WB of body 2 is not finite"), std::string::npos);
  poses[0].translation().x() = std::nan("");  // body 0 has no mesh: its pose is not used
  poses[2] = Eigen::Isometry3d::Identity();
  EXPECT_NO_THROW(scene.set_body_poses(poses));
}

TEST(EmbreeScene, BadRaysAreClearErrors) {
  EmbreeScene scene;
  scene.add_static_mesh(flat_square(50.0f, -100.0f));
  scene.build();
  RayBatch batch;
  for (int i = 0; i < 10; ++i) batch.add_ray({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f});
  auto error_for = [&](RayBatch b) {
    try {
      trace(scene, b);
    } catch (const InvalidRayError& e) {
      return std::to_string(e.ray_index()) + " " + e.what();
    }
    return std::string("(no exception)");
  };
  RayBatch b = batch;
  b.d_W_z[6] = -2.0f;
  EXPECT_NE(error_for(b).find("6 ray 6: direction (0, 0, -2) is not unit length (|d| = 2"), std::string::npos);
  b = batch;
  b.p_WO_y[3] = kInf;
  EXPECT_NE(error_for(b).find("3 ray 3: origin (0, inf, 0) is not finite"), std::string::npos);
  b = batch;
  b.t_near[4] = -1.0f;
  EXPECT_NE(error_for(b).find("4 ray 4: t_near = -1"), std::string::npos);
  b = batch;
  b.t_near[5] = 2.0f;
  b.t_far[5] = 1.0f;
  EXPECT_NE(error_for(b).find("5 ray 5: t_far = 1.000000 must be >= t_near = 2.000000"), std::string::npos);
  b = batch;
  b.t_far.pop_back();
  EXPECT_THROW(trace(scene, b), std::invalid_argument);
  RayHits short_hits;
  short_hits.resize(3);
  EXPECT_THROW(scene.intersect(batch, 0, 10, QueryPath::kAuto, short_hits), std::out_of_range);
}

// True when triangles a and b of `mesh` share a vertex: a ray through their common edge or vertex
// meets both at the same distance, and which one a query path reports is a tie.
bool share_vertex(const TriangleMesh& mesh, std::uint32_t a, std::uint32_t b) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (mesh.indices[3 * a + i] == mesh.indices[3 * b + j]) return true;
    }
  }
  return false;
}

// A bumpy grid, two bodies (one of them rotated), camera-like and scattered rays: every path gives
// bit-identical distances, bodies and meshes, also for ranges that start off the 16-byte alignment
// streams need. Triangle and normal are identical too except for ties: a ray through an edge or vertex
// shared by two triangles (the camera's middle column runs along the grid line y = 0).
TEST(EmbreeScene, AllQueryPathsGiveIdenticalHits) {
  std::vector<TriangleMesh> meshes = {
      grid(64, 100.0f, [](float x, float y) { return -100.0f + 3.0f * std::sin(0.1f * x) * std::cos(0.07f * y); }),
      box(2.0f, 1.0f, 1.0f), box(1.0f, 1.0f, 3.0f)};
  EmbreeScene scene;
  scene.add_static_mesh(meshes[0]);
  scene.add_body_mesh(0, meshes[1]);
  scene.add_body_mesh(1, meshes[2]);
  scene.build();
  std::vector<Eigen::Isometry3d> poses(2, Eigen::Isometry3d::Identity());
  poses[0].translation() = Eigen::Vector3d(5.0, 0.0, -90.0);
  poses[1].translate(Eigen::Vector3d(-3.0, 4.0, -92.0));
  poses[1].rotate(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()));
  scene.set_body_poses(poses);

  std::mt19937 rng(42);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  for (RayCoherence coherence : {RayCoherence::kCoherent, RayCoherence::kIncoherent}) {
    RayBatch batch;
    batch.coherence = coherence;
    for (int k = 0; k < 1000; ++k) {
      Eigen::Vector3f p, d;
      if (coherence == RayCoherence::kCoherent) {  // a 40 x 25 pinhole looking forward and down
        p = Eigen::Vector3f(-10.0f, 0.0f, -80.0f);
        d = Eigen::Vector3f(1.0f, 0.02f * static_cast<float>(k % 40 - 20), -0.5f - 0.02f * static_cast<float>(k / 40));
      } else {
        p = Eigen::Vector3f(80.0f * uniform(rng), 80.0f * uniform(rng), -85.0f + 10.0f * uniform(rng));
        d = Eigen::Vector3f(uniform(rng), uniform(rng), uniform(rng));
      }
      batch.add_ray(p, d.normalized());
    }
    const RayHits single = trace(scene, batch, QueryPath::kSingle);
    std::size_t hits = 0, body_hits = 0;
    for (std::size_t i = 0; i < single.size(); ++i) {
      hits += single.hit(i);
      body_hits += single.body[i] >= 0;
    }
    EXPECT_GT(hits, 300u);
    if (coherence == RayCoherence::kCoherent) {
      EXPECT_GT(body_hits, 20u);
    }
    for (QueryPath path : {QueryPath::kPacket, QueryPath::kStream}) {
      RayHits other;
      other.resize(batch.size());
      scene.intersect(batch, 0, 3, path, other);  // off-alignment head, then the rest
      scene.intersect(batch, 3, 517, path, other);
      scene.intersect(batch, 517, batch.size(), path, other);
      for (std::size_t i = 0; i < batch.size(); ++i) {
        SCOPED_TRACE("ray " + std::to_string(i) + " path " + to_string(path));
        ASSERT_EQ(single.distance[i], other.distance[i]);
        ASSERT_EQ(single.body[i], other.body[i]);
        ASSERT_EQ(single.mesh[i], other.mesh[i]);
        ASSERT_EQ(single.material[i], other.material[i]);
        if (single.triangle[i] != other.triangle[i]) {
          ASSERT_TRUE(share_vertex(meshes[static_cast<std::size_t>(single.mesh[i])], single.triangle[i],
                                   other.triangle[i]));
          continue;
        }
        ASSERT_EQ(single.n_W_x[i], other.n_W_x[i]);
        ASSERT_EQ(single.n_W_y[i], other.n_W_y[i]);
        ASSERT_EQ(single.n_W_z[i], other.n_W_z[i]);
      }
    }
  }
}

// The portable tests' world: a bumpy 80 m grid as the seabed and a smaller bumpy sheet as a body (its
// triangles at angles in B, unlike a box's faces), rotated off every axis and moved.
struct BumpyWorld {
  TriangleMesh seabed =
      grid(16, 40.0f, [](float x, float y) { return -100.0f + 2.0f * std::sin(0.3f * x) * std::cos(0.2f * y + 0.4f); });
  TriangleMesh hull = grid(6, 1.5f, [](float x, float y) { return 0.3f * std::cos(1.1f * x - 0.4f * y); });
  Eigen::Isometry3d X_WB = pose();

  static Eigen::Isometry3d pose() {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translate(Eigen::Vector3d(3.0, -4.0, -96.0));
    X.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d(1.0, -2.0, 3.0).normalized()));
    return X;
  }
  // The world built and posed in a scene of the given kernels.
  EmbreeScene scene(const std::string& device_config, RayKernels kernels) const {
    EmbreeScene s(device_config, kernels);
    s.add_static_mesh(seabed);
    s.add_body_mesh(0, hull);
    s.build();
    s.set_body_poses({X_WB});
    return s;
  }
};

// RayKernels::kPortable recomputes each hit from the triangle found and decides edges and vertices by
// its own rule, so the hits do not depend on how Embree's kernel computed them: Embree's SSE4.2 kernels
// (4-wide BVH, what kPortable uses) and its AVX kernels (8-wide BVH, another traversal order) give the
// same bits on every query path. The rays aim at what makes kernels disagree: every vertex and edge
// midpoint of a bumpy grid (where two to six triangles meet, at angles), and of a smaller one as a
// rotated body, from a viewpoint off every axis. (Embree 3.13.5's AVX2 kernels are not comparable: with
// a box as the body they missed 28 more of these rays, at the grid's vertices and the box's silhouette;
// kPortable never uses them.)
TEST(EmbreeScene, PortableHitsAreTheSameWhicheverKernelTraces) {
  const BumpyWorld world;
  const TriangleMesh &seabed = world.seabed, &hull = world.hull;
  const Eigen::Isometry3d& X_WB = world.X_WB;
  const Eigen::Vector3f origin(-7.3f, 5.9f, -60.0f);
  RayBatch batch;
  const auto aim = [&](const Eigen::Vector3f& target) { batch.add_ray(origin, (target - origin).normalized()); };
  const auto vertex = [](const TriangleMesh& m, std::uint32_t v) {
    return Eigen::Vector3f(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
  };
  for (const TriangleMesh* mesh : {&seabed, &hull}) {
    const Eigen::Isometry3f X = mesh == &hull ? X_WB.cast<float>() : Eigen::Isometry3f::Identity();
    for (std::size_t t = 0; t < mesh->num_triangles(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3f a = X * vertex(*mesh, mesh->indices[3 * t + k]);
        const Eigen::Vector3f b = X * vertex(*mesh, mesh->indices[3 * t + (k + 1) % 3]);
        aim(a);
        aim(0.5f * (a + b));
      }
    }
  }
  if (!__builtin_cpu_supports("avx")) GTEST_SKIP() << "this CPU has no AVX: no second kernel to compare SSE4.2 with";
  const std::vector<std::string> isas = {"sse4.2", "avx"};
  std::optional<RayHits> reference;
  for (const std::string& isa : isas) {
    const EmbreeScene scene = world.scene("isa=" + isa, RayKernels::kPortable);
    for (QueryPath path : {QueryPath::kSingle, QueryPath::kPacket, QueryPath::kStream}) {
      const RayHits hits = trace(scene, batch, path);
      if (!reference) {
        reference = hits;
        std::size_t on_body = 0, on_seabed = 0;
        for (std::size_t i = 0; i < hits.size(); ++i) {
          on_body += hits.body[i] == 0;
          on_seabed += hits.body[i] == kStaticBody;
        }
        EXPECT_GT(on_body, 20u);
        EXPECT_GT(on_seabed, 1000u);
        continue;
      }
      for (std::size_t i = 0; i < hits.size(); ++i) {
        SCOPED_TRACE("ray " + std::to_string(i) + ", isa " + isa + ", path " + to_string(path));
        ASSERT_EQ(std::memcmp(&hits.distance[i], &reference->distance[i], sizeof(float)), 0);
        ASSERT_EQ(hits.triangle[i], reference->triangle[i]);
        ASSERT_EQ(hits.body[i], reference->body[i]);
        ASSERT_EQ(std::memcmp(&hits.n_W_x[i], &reference->n_W_x[i], sizeof(float)), 0);
        ASSERT_EQ(std::memcmp(&hits.n_W_y[i], &reference->n_W_y[i], sizeof(float)), 0);
        ASSERT_EQ(std::memcmp(&hits.n_W_z[i], &reference->n_W_z[i], sizeof(float)), 0);
      }
    }
  }
}

// RayKernels::kPortable: a hit's distance is the exact distance to the geometry Embree traced (float
// vertices, a body moved by the single-precision transform Embree holds), rounded once to float: within
// half a unit in the last place. Rays at random inner points of random triangles of a bumpy static
// grid and of a rotated, translated body; Embree's own distances (RayKernels::kNative) are off by more
// for some of them.
TEST(EmbreeScene, PortableDistancesAreTheExactHitRoundedOnce) {
  const BumpyWorld world;
  const TriangleMesh &seabed = world.seabed, &hull = world.hull;
  const Eigen::Isometry3d& X_WB = world.X_WB;
  // The transform as Embree holds it (each element rounded to float), and its exact inverse. Rounded
  // through a volatile float: GCC 12 -O3 left one element of this loop unrounded otherwise (seen: A(2, 2)
  // kept its double value, with a plain static_cast and with Eigen's cast<float>()).
  Eigen::Matrix3d A;
  Eigen::Vector3d p;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const volatile float element = static_cast<float>(X_WB.linear()(r, c));
      A(r, c) = element;
    }
    const volatile float element = static_cast<float>(X_WB.translation()[r]);
    p[r] = element;
  }
  const Eigen::Matrix3d A_inverse = A.inverse();
  const auto vertex = [](const TriangleMesh& m, std::uint32_t v) {
    return Eigen::Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
  };
  // The exact parameter at which ray i meets the plane of triangle t of its mesh (the ray as given: float
  // origin and direction; for the body, taken into B by the exact inverse).
  const Eigen::Vector3f origin(-7.3f, 5.9f, -60.0f);
  RayBatch batch;
  const auto exact = [&](std::size_t i, const TriangleMesh& mesh, std::size_t t) {
    Eigen::Vector3d o = origin.cast<double>();
    Eigen::Vector3d d(batch.d_W_x[i], batch.d_W_y[i], batch.d_W_z[i]);
    if (&mesh == &hull) {
      o = A_inverse * (o - p);
      d = A_inverse * d;
    }
    const Eigen::Vector3d v0 = vertex(mesh, mesh.indices[3 * t]);
    const Eigen::Vector3d n =
        (vertex(mesh, mesh.indices[3 * t + 1]) - v0).cross(vertex(mesh, mesh.indices[3 * t + 2]) - v0);
    return std::make_pair(n.dot(v0 - o) / n.dot(d), std::abs(n.normalized().dot(d.normalized())));
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(0.1, 0.45);
  std::vector<std::size_t> aimed;
  for (const TriangleMesh* mesh : {&seabed, &hull}) {
    std::uniform_int_distribution<std::size_t> pick(0, mesh->num_triangles() - 1);
    for (int k = 0; k < 500; ++k) {
      const std::size_t t = pick(rng);
      const Eigen::Vector3d v0 = vertex(*mesh, mesh->indices[3 * t]), v1 = vertex(*mesh, mesh->indices[3 * t + 1]),
                            v2 = vertex(*mesh, mesh->indices[3 * t + 2]);
      const Eigen::Vector3d target_B = v0 + uniform(rng) * (v1 - v0) + uniform(rng) * (v2 - v0);
      const Eigen::Vector3d target_W = mesh == &hull ? Eigen::Vector3d(A * target_B + p) : target_B;
      batch.add_ray(origin, (target_W.cast<float>() - origin).normalized());
      aimed.push_back(t);
    }
  }
  std::size_t native_off = 0;
  for (RayKernels kernels : {RayKernels::kPortable, RayKernels::kNative}) {
    const EmbreeScene scene = world.scene("", kernels);
    const RayHits hits = trace(scene, batch);
    std::size_t aimed_hits = 0;
    for (std::size_t i = 0; i < hits.size(); ++i) {
      // A seabed target may lie behind the body or the reverse, a bump in front of a target: the hit's
      // own triangle counts, and it is the aimed one or a nearer one.
      const TriangleMesh& mesh = hits.body[i] == 0 ? hull : seabed;
      ASSERT_TRUE(hits.hit(i)) << "ray " << i;
      const auto [t, cosine] = exact(i, mesh, hits.triangle[i]);
      // Within 1e-3 of edge-on, double precision itself places the hit no better than ~1e-13 / cosine
      // relative: not within half a float ulp.
      if (cosine < 1e-3) continue;
      const double error = std::abs(static_cast<double>(hits.distance[i]) - t);
      const double half_ulp = 0.5 * (std::nextafter(static_cast<float>(t), kInf) - static_cast<float>(t));
      if (kernels == RayKernels::kPortable) {
        ASSERT_LE(error, half_ulp * (1.0 + 1e-6)) << "ray " << i;
        const TriangleMesh& aimed_mesh = i >= 500 ? hull : seabed;
        if (&mesh == &aimed_mesh && hits.triangle[i] == aimed[i]) {
          ++aimed_hits;
        } else {
          ASSERT_LT(t, exact(i, aimed_mesh, aimed[i]).first) << "ray " << i;
        }
      } else {
        native_off += error > half_ulp * (1.0 + 1e-6);
      }
    }
    if (kernels == RayKernels::kPortable) {
      EXPECT_GT(aimed_hits, 800u);
    }
  }
  EXPECT_GT(native_off, 0u);  // else the check above could not tell a refined distance from Embree's
}

// A camera's frame as the renderer traces it: every ray ignores the camera's own hull (a body around
// the rays' origin), and a small body sits on the seabed in one corner of the view. The stream path
// skips the bodies' pass for the blocks whose rays cannot reach a body (most of them here); its hits,
// and occluded()'s answers, stay those of single rays, which always trace both passes.
TEST(EmbreeScene, BlocksOutOfTheBodiesReachGiveTheSameHits) {
  EmbreeScene scene;
  scene.add_static_mesh(grid(64, 100.0f, [](float x, float y) { return -100.0f + 0.5f * std::sin(0.3f * x) * std::cos(0.2f * y); }));
  scene.add_body_mesh(0, box(1.0f, 0.3f, 0.3f));  // the camera's hull
  scene.add_body_mesh(1, box(0.6f, 0.6f, 0.6f));  // a small object on the seabed
  scene.build();
  std::vector<Eigen::Isometry3d> poses(2, Eigen::Isometry3d::Identity());
  poses[0].translation() = Eigen::Vector3d(0.0, 0.0, -95.0);
  poses[1].translate(Eigen::Vector3d(9.13, 1.27, -99.41));
  poses[1].rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 0.1, 1.0).normalized()));
  scene.set_body_poses(poses);

  const int width = 160, height = 120;
  const Eigen::Vector3f p_WC(0.5f, 0.0f, -95.0f);  // inside the hull
  RayBatch batch;
  batch.coherence = RayCoherence::kCoherent;
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {  // forward (x), 30 deg down, 60 deg across
      const float across = 0.6f * (static_cast<float>(u) / width - 0.5f);
      const float down = -0.55f - 0.45f * (static_cast<float>(v) / height - 0.5f);
      batch.add_ray(p_WC, Eigen::Vector3f(1.0f, -across, down).normalized(), 0.0f, 30.0f, 0);
    }
  }
  const RayHits single = trace(scene, batch, QueryPath::kSingle);
  const RayHits stream = trace(scene, batch, QueryPath::kStream);
  std::size_t object_hits = 0;
  std::vector<bool> block_sees_object((batch.size() + 255) / 256, false);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    SCOPED_TRACE("ray " + std::to_string(i) + " bodies " + std::to_string(single.body[i]) + " " + std::to_string(stream.body[i]));
    ASSERT_EQ(single.distance[i], stream.distance[i]);
    ASSERT_EQ(single.body[i], stream.body[i]);
    ASSERT_EQ(single.mesh[i], stream.mesh[i]);
    ASSERT_NE(stream.body[i], 0);  // the hull is passed
    if (stream.body[i] == 1) {
      ++object_hits;
      block_sees_object[i / 256] = true;
    }
  }
  EXPECT_GT(object_hits, 50u);
  const auto blocks_with_object = static_cast<std::size_t>(std::count(block_sees_object.begin(), block_sees_object.end(), true));
  EXPECT_GT(blocks_with_object, 0u);
  EXPECT_LT(blocks_with_object, block_sees_object.size() / 2);  // most blocks never see the object

  // Rays from the seabed's hit points towards a light above the object: the object shadows some.
  RayBatch shadows;
  shadows.coherence = RayCoherence::kCoherent;
  const Eigen::Vector3f light(9.1f, 1.3f, -96.0f);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    if (stream.body[i] != kStaticBody) continue;
    const Eigen::Vector3f p = p_WC + stream.distance[i] * Eigen::Vector3f(batch.d_W_x[i], batch.d_W_y[i], batch.d_W_z[i]) +
                              Eigen::Vector3f(0.0f, 0.0f, 1e-3f);
    shadows.add_ray(p, (light - p).normalized(), 0.0f, (light - p).norm(), 0);
  }
  const RayHits shadow_hits = trace(scene, shadows, QueryPath::kSingle);
  std::vector<std::uint8_t> blocked(shadows.size(), 7);
  scene.occluded(shadows, 0, shadows.size(), blocked);
  std::size_t shadowed = 0;
  for (std::size_t i = 0; i < shadows.size(); ++i) {
    ASSERT_EQ(blocked[i], shadow_hits.hit(i) ? 1 : 0) << "shadow ray " << i;
    shadowed += blocked[i];
  }
  EXPECT_GT(shadowed, 20u);
}

// occluded() answers intersect()'s "hit or not" for every ray: random rays with random far clips, a
// third ignoring body 0, a third body 1 (some starting inside a body, so its surfaces must be passed),
// over a seabed and two posed bodies, through the stream path (aligned blocks) and packets (the
// misaligned head).
TEST(EmbreeScene, OccludedAgreesWithIntersect) {
  EmbreeScene scene;
  scene.add_static_mesh(grid(64, 100.0f, [](float x, float y) { return -100.0f + 3.0f * std::sin(0.1f * x) * std::cos(0.07f * y); }));
  scene.add_body_mesh(0, box(2.0f, 1.0f, 1.0f));
  scene.add_body_mesh(1, box(1.0f, 1.0f, 3.0f));
  scene.build();
  std::vector<Eigen::Isometry3d> poses(2, Eigen::Isometry3d::Identity());
  poses[0].translation() = Eigen::Vector3d(5.0, 0.0, -90.0);
  poses[1].translation() = Eigen::Vector3d(-3.0, 4.0, -92.0);
  scene.set_body_poses(poses);

  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  RayBatch batch;
  for (int k = 0; k < 3000; ++k) {
    const int kind = k % 3;  // 0: no ignored body (every 7th: ignores the static world), 1: body 0, 2: body 1
    Eigen::Vector3f p(8.0f * uniform(rng), 6.0f * uniform(rng), -91.0f + 3.0f * uniform(rng));
    if (k % 5 == 0) p = (kind == 2 ? poses[1] : poses[0]).translation().cast<float>();  // inside a body
    const Eigen::Vector3f d = Eigen::Vector3f(uniform(rng), uniform(rng), uniform(rng)).normalized();
    const float t_far = k % 4 == 0 ? kInf : 12.0f * (1.0f + uniform(rng));
    batch.add_ray(p, d, 0.0f, t_far, kind == 0 ? (k % 7 == 0 ? kStaticBody : kNoHit) : kind - 1);
  }
  const RayHits hits = trace(scene, batch);
  std::vector<std::uint8_t> blocked(batch.size(), 7);
  scene.occluded(batch, 0, 3, blocked);
  scene.occluded(batch, 3, batch.size(), blocked);
  std::size_t hit_count = 0, passed_ignored = 0;
  for (std::size_t i = 0; i < batch.size(); ++i) {
    ASSERT_EQ(blocked[i], hits.hit(i) ? 1 : 0) << "ray " << i;
    hit_count += hits.hit(i);
  }
  // Rays starting inside the body they ignore: Embree's occlusion finds that body's surface first, so
  // these exercise the re-trace past it.
  for (std::size_t i = 0; i < batch.size(); i += 5) passed_ignored += batch.ignore_body[i] != kNoHit;
  EXPECT_GT(hit_count, 500u);
  EXPECT_LT(hit_count, 2800u);
  EXPECT_GT(passed_ignored, 300u);
  std::vector<std::uint8_t> short_output(10);
  EXPECT_THROW(scene.occluded(batch, 0, 20, short_output), std::out_of_range);
}

// A ray that ignores its own body passes through it and stops at the next one, whatever the body
// indices: with bodies 0..30 each instance has a ray-mask bit of its own (the ignored body left out by
// mask); body 32 shares body 1's bit, so there the re-trace past ignored hits (intersect) and the
// filter (occluded) do it. Boxes on a line over the seabed, rays from inside one box along the line,
// on every query path.
TEST(EmbreeScene, IgnoredBodyIsPassedWhateverItsIndex) {
  for (const std::int32_t far_body : {2, 32}) {
    SCOPED_TRACE(far_body);
    EmbreeScene scene;
    scene.add_static_mesh(grid(16, 50.0f, [](float, float) { return -100.0f; }));
    scene.add_body_mesh(1, box(0.5f, 0.5f, 0.5f));
    scene.add_body_mesh(far_body, box(0.5f, 0.5f, 0.5f));
    scene.build();
    std::vector<Eigen::Isometry3d> poses(static_cast<std::size_t>(far_body) + 1, Eigen::Isometry3d::Identity());
    poses[1].translation() = Eigen::Vector3d(0.0, 0.0, -90.0);
    poses[static_cast<std::size_t>(far_body)].translation() = Eigen::Vector3d(5.0, 0.0, -90.0);
    scene.set_body_poses(poses);
    RayBatch batch;
    batch.coherence = RayCoherence::kCoherent;
    for (int k = 0; k < 64; ++k) {
      const float dy = 0.004f * static_cast<float>(k % 8 - 4), dz = 0.004f * static_cast<float>(k / 8 - 4);
      // From inside body 1 towards the far body, ignoring body 1; and back, ignoring the far body.
      batch.add_ray(Eigen::Vector3f(0.0f, 0.0f, -90.0f), Eigen::Vector3f(1.0f, dy, dz).normalized(), 0.0f, kInf, 1);
      batch.add_ray(Eigen::Vector3f(5.0f, 0.0f, -90.0f), Eigen::Vector3f(-1.0f, dy, dz).normalized(), 0.0f, kInf, far_body);
      // Straight down from below body 1, ignoring the static world: nothing below but the seabed.
      batch.add_ray(Eigen::Vector3f(0.0f, 0.0f, -95.0f), Eigen::Vector3f(dy, dz, -1.0f).normalized(), 0.0f, kInf,
                    kStaticBody);
    }
    for (QueryPath path : {QueryPath::kSingle, QueryPath::kPacket, QueryPath::kStream}) {
      SCOPED_TRACE(to_string(path));
      const RayHits hits = trace(scene, batch, path);
      for (std::size_t i = 0; i < batch.size(); i += 3) {
        ASSERT_EQ(hits.body[i], far_body) << i;
        ASSERT_NEAR(hits.distance[i], 4.5f, 0.01f) << i;  // the far box's near face
        ASSERT_EQ(hits.body[i + 1], 1) << i;
        ASSERT_NEAR(hits.distance[i + 1], 4.5f, 0.01f) << i;
        ASSERT_FALSE(hits.hit(i + 2)) << i;
      }
    }
    std::vector<std::uint8_t> blocked(batch.size(), 7);
    scene.occluded(batch, 0, batch.size(), blocked);
    for (std::size_t i = 0; i < batch.size(); ++i) ASSERT_EQ(blocked[i], i % 3 == 2 ? 0 : 1) << i;
  }
}

}  // namespace
}  // namespace hadal::geometry
