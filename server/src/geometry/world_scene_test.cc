#include "hadal/geometry/world_scene.h"

#include "hadal/config/scenario_loader.h"
#include "hadal/geometry/ray_batch.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <limits>

namespace hadal::geometry {
namespace {

RayHits cast_one(EmbreeScene& scene, const Eigen::Vector3f& p_WO, const Eigen::Vector3f& d_W,
                 const std::vector<Eigen::Isometry3d>& X_WB = {}, std::int32_t ignore_body = kNoHit) {
  if (!scene.built()) scene.build();
  if (scene.num_bodies() > 0) scene.set_body_poses(X_WB);
  RayBatch batch;
  batch.add_ray(p_WO, d_W, 0.0f, std::numeric_limits<float>::infinity(), ignore_body);
  RayHits hits;
  hits.resize(1);
  scene.intersect(batch, 0, 1, QueryPath::kSingle, hits);
  return hits;
}

TEST(WorldSceneTest, RayStraightDownFromTheDefaultAuvMeetsTheGeneratedSeabed) {
  const config::LoadResult loaded =
      config::load_scenario_file(std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/default.yaml");
  ASSERT_TRUE(loaded.ok());
  const Model& model = *loaded.model;
  EmbreeScene scene = build_world_scene(model);
  const std::vector<Eigen::Isometry3d> X_WB = {model.vehicles[0].X_WB_initial, model.vehicles[1].X_WB_initial};
  const Eigen::Vector3f p_WO = model.vehicles[0].X_WB_initial.translation().cast<float>();
  // From the AUV's centre the ray first leaves its own hull (a back face 0.0775 m down: the capsule's
  // radius, less the inscribed polygon's deficit); ignoring its own body it meets the seabed.
  const RayHits own = cast_one(scene, p_WO, Eigen::Vector3f(0, 0, -1), X_WB);
  ASSERT_EQ(scene.num_bodies(), 2);  // the AUV's capsule and fins, the lander's frame (collision primitives)
  ASSERT_TRUE(own.hit(0));
  EXPECT_EQ(own.body[0], 0);
  EXPECT_NEAR(own.distance[0], 0.0775f, 0.0775f * 0.01f);  // 32 segments: deficit < 0.5 %
  EXPECT_LT(own.n_W_z[0], -0.9f);  // outward (down): a back face seen from inside
  const RayHits hits = cast_one(scene, p_WO, Eigen::Vector3f(0, 0, -1), X_WB, 0);
  ASSERT_TRUE(hits.hit(0));
  // The AUV starts at (0, 0, -96) over the sediment plain, whose height at the origin is exactly the
  // datum -100 m (the regional slope term vanishes there): 4 m, to float rounding of a 100 m
  // coordinate (4 ulp of 100 m ~ 3e-5 m).
  EXPECT_NEAR(hits.distance[0], 4.0f, 4 * FLT_EPSILON * 100.0f);
  EXPECT_EQ(hits.body[0], kStaticBody);
  EXPECT_EQ(hits.material[0], kSeabedMaterial);
  // The plain is tilted by the 1 deg regional slope: the normal is 1 deg off vertical.
  EXPECT_NEAR(hits.n_W_z[0], std::cos(M_PI / 180.0), 1e-5);
}

TEST(WorldSceneTest, PlaneSeabedAndLinkMeshesMoveWithTheirVehicle) {
  Model model;
  model.world.seabed.z = -30.0;
  VehicleSpec vehicle;
  vehicle.name = "rov";
  LinkSpec link;
  link.name = "frame";
  link.X_BL.translation() = Eigen::Vector3d(0.0, 0.0, 1.0);  // the mesh sits 1 m above B
  LinkMesh link_mesh;
  auto square = std::make_shared<TriangleMesh>();
  square->positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  square->indices = {0, 1, 2, 0, 2, 3};
  link_mesh.mesh = square;
  link.mesh = link_mesh;
  vehicle.links.push_back(link);
  model.vehicles.push_back(vehicle);

  EmbreeScene scene = build_world_scene(model);
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation() = Eigen::Vector3d(100.0, 0.0, -20.0);
  // From 10 m below the vehicle, straight up: the square is at z = -20 + 1.
  RayHits up = cast_one(scene, Eigen::Vector3f(100.0f, 0.0f, -29.0f), Eigen::Vector3f(0, 0, 1), {X_WB});
  ASSERT_TRUE(up.hit(0));
  EXPECT_NEAR(up.distance[0], 10.0f, 4 * FLT_EPSILON * 30.0f);
  EXPECT_EQ(up.body[0], 0);
  EXPECT_EQ(up.material[0], kVehicleMaterial);
  // Straight down next to it: the plane seabed at -30.
  RayHits down = cast_one(scene, Eigen::Vector3f(0.0f, 0.0f, 0.0f), Eigen::Vector3f(0, 0, -1), {X_WB});
  ASSERT_TRUE(down.hit(0));
  EXPECT_NEAR(down.distance[0], 30.0f, 4 * FLT_EPSILON * 30.0f);
  EXPECT_EQ(down.n_W_z[0], 1.0f);
}

TEST(WorldSceneTest, RaysPassThroughTheBodyTheyIgnoreOnly) {
  // Two 1 m boxes on a line above a plane seabed at z = -30: a ray from inside the first, straight
  // down through both, ignoring the first, meets the second; ignoring the second (or nothing) it
  // meets the first; a body hit more than kMaxIgnoredHits times is never reported.
  Model model;
  model.world.seabed.z = -30.0;
  for (const char* name : {"a", "b"}) {
    VehicleSpec vehicle;
    vehicle.name = name;
    LinkSpec link;
    link.name = "hull";
    CollisionShape box;
    box.box_size = Eigen::Vector3d(1.0, 1.0, 1.0);
    link.collisions.push_back(box);
    vehicle.links.push_back(link);
    model.vehicles.push_back(vehicle);
  }
  EmbreeScene scene = build_world_scene(model);
  std::vector<Eigen::Isometry3d> X_WB(2, Eigen::Isometry3d::Identity());
  X_WB[1].translation() = Eigen::Vector3d(0.0, 0.0, -10.0);  // box b spans z in [-10.5, -9.5]
  const Eigen::Vector3f p(0.1f, 0.2f, 0.0f), down(0.0f, 0.0f, -1.0f);
  const RayHits none = cast_one(scene, p, down, X_WB);
  EXPECT_EQ(none.body[0], 0);
  EXPECT_NEAR(none.distance[0], 0.5f, 1e-6f);  // the bottom face of a, from inside
  EXPECT_LT(none.n_W_z[0], -0.99f);             // outward (down), not flipped: a back face
  const RayHits skip_a = cast_one(scene, p, down, X_WB, 0);
  EXPECT_EQ(skip_a.body[0], 1);
  EXPECT_NEAR(skip_a.distance[0], 9.5f, 4 * FLT_EPSILON * 10.0f);
  const RayHits skip_b = cast_one(scene, p, down, X_WB, 1);
  EXPECT_EQ(skip_b.body[0], 0);
  // From above both, ignoring b: a's top and bottom are hit (a is not ignored: top at 19.5 m), and
  // from below a, ignoring b, the seabed.
  const RayHits from_top = cast_one(scene, Eigen::Vector3f(0.1f, 0.2f, 20.0f), down, X_WB, 1);
  EXPECT_EQ(from_top.body[0], 0);
  EXPECT_NEAR(from_top.distance[0], 19.5f, 4 * FLT_EPSILON * 20.0f);
  const RayHits below_a = cast_one(scene, Eigen::Vector3f(0.1f, 0.2f, -5.0f), down, X_WB, 1);
  EXPECT_EQ(below_a.body[0], kStaticBody);
  EXPECT_NEAR(below_a.distance[0], 25.0f, 4 * FLT_EPSILON * 30.0f);
}

}  // namespace
}  // namespace hadal::geometry
