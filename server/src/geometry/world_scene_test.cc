#include "hadal/geometry/world_scene.h"

#include "hadal/config/scenario_loader.h"
#include "hadal/geometry/ray_batch.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>

namespace hadal::geometry {
namespace {

RayHits cast_one(EmbreeScene& scene, const Eigen::Vector3f& p_WO, const Eigen::Vector3f& d_W,
                 const std::vector<Eigen::Isometry3d>& X_WB = {}) {
  if (!scene.built()) scene.build();
  if (scene.num_bodies() > 0) scene.set_body_poses(X_WB);
  RayBatch batch;
  batch.add_ray(p_WO, d_W);
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
  const Eigen::Vector3f p_WO = model.vehicles[0].X_WB_initial.translation().cast<float>();
  const RayHits hits = cast_one(scene, p_WO, Eigen::Vector3f(0, 0, -1));
  ASSERT_TRUE(hits.hit(0));
  // The AUV starts at (0, 0, -50) over the sediment plain, whose height at the origin is exactly the
  // datum -100 m (the regional slope term vanishes there): 50 m, to float rounding of a 100 m
  // coordinate (4 ulp of 100 m ~ 3e-5 m).
  EXPECT_NEAR(hits.distance[0], 50.0f, 4 * FLT_EPSILON * 100.0f);
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

}  // namespace
}  // namespace hadal::geometry
