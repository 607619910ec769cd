// Loading a link's keys (links[], geometry/link_spec.cc) through the scenario loader: values, defaults,
// conversions and the errors at file:line:col (config/scenario_test_support.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/assets/mesh_generators.h"
#include "hadal/assets/scene_writer.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/geometry/primitive_mesh.h"

namespace hadal::config {
namespace {

TEST_F(ScenarioLoaderTest, ShapeSpecificKeys) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - name: hull
        mass: 1
        inertia: {ixx: 1, iyy: 1, izz: 1}
        collisions:
          - shape: sphere
            radius: 0.1
            size: [1, 1, 1]
          - {shape: cylinder, radius: 0.1}
          - {shape: cone, radius: 0.1}
)");
  EXPECT_EQ(
      errors_of(path),
      (Lines{
          path + ":12:13: error: vehicles[0].links[0].collisions[0].size: key 'size' is not used by shape "
                 "'sphere'",
          path + ":13:13: error: vehicles[0].links[0].collisions[1]: missing required key 'length' (needed "
                 "by shape 'cylinder')",
          path + ":14:21: error: vehicles[0].links[0].collisions[2].shape: must be one of 'box', 'sphere', "
                 "'cylinder', 'capsule' (got 'cone')"}));
}

TEST_F(ScenarioLoaderTest, InertiaMustBePhysical) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: a, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1, ixy: 2}}
      - {name: b, mass: 1, inertia: {ixx: 0.1, iyy: 0.1, izz: 6.4}}
      - {name: c, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 2}}
      - {name: d, mass: 1, inertia: {ixx: 0.0833, iyy: 0.0833, izz: 0.1667}}
      - {name: e, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1, ixy: 0.9}}
)");
  // c and d are the limiting cases (flat plate), d rounded by hand: accepted. e passes the diagonal test
  // but its principal moments 0.1, 1, 1.9 do not.
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":6:37: error: vehicles[0].links[0].inertia: must be positive definite "
                          "(principal moments -1, 1, 3)",
                   path + ":7:37: error: vehicles[0].links[1].inertia: violates the triangle "
                          "inequality ixx + iyy >= izz (0.1 + 0.1 < 6.4)",
                   path + ":10:37: error: vehicles[0].links[4].inertia: violates the triangle "
                          "inequality for principal moments (0.1 + 1 < 1.9)"}));
}

// link.visual: what ray casts see (geometry::vehicle_visual_B); the physics keeps the collision shapes
// (geometry::vehicle_surface_B), and mass and buoyancy ignore the visual mesh.
TEST_F(ScenarioLoaderTest, LinkVisualIsSeenNotSimulated) {
  ASSERT_EQ(assets::write_scene(assets::single_mesh_scene(assets::make_uv_sphere(0.5, 16, 8)),
                                (dir_ / "looks.glb").string()),
            "");
  const std::string rov_yaml = R"(world: {}
vehicles:
  - name: rov
    type: rov
    links:
      - name: frame
        visual: {file: looks.glb, pose: {position: [0, 0, 0.1]}}
        mass: 10.0
        inertia: {ixx: 1, iyy: 1, izz: 1}
        collisions: [{shape: box, size: [1.0, 0.8, 0.5]}]
)";
  const std::string path = write("s.yaml", rov_yaml + R"(  - name: ghost
    type: rov
    links:
      - name: frame
        visual: {file: missing.glb}
        mass: 10.0
        inertia: {ixx: 1, iyy: 1, izz: 1}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_NE(result.errors[0].format().find(path + ":15:24: error: vehicles[1].links[0].visual.file: "),
            std::string::npos)
      << result.errors[0].format();
  const std::string good = write("g.yaml", rov_yaml);
  const LoadResult loaded = load_scenario_file(good);
  for (const Diagnostic& d : loaded.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(loaded.ok());
  const VehicleSpec& rov = loaded.model->vehicles[0];
  const LinkSpec& link = rov.links[0];
  ASSERT_TRUE(link.visual.has_value());
  EXPECT_EQ(link.seen_mesh(), &*link.visual);
  EXPECT_FALSE(link.mesh.has_value());
  EXPECT_EQ(link.buoyancy.volume, 0.0);
  EXPECT_EQ(geometry::vehicle_surface_B(rov).num_triangles(), 12u);  // the box
  const geometry::TriangleMesh seen = geometry::vehicle_visual_B(rov);
  EXPECT_EQ(seen.num_triangles(), link.visual->mesh->num_triangles());  // the sphere
  float top = -1.0f;
  for (std::size_t v = 0; v < seen.num_vertices(); ++v) top = std::max(top, seen.positions[3 * v + 2]);
  EXPECT_NEAR(top, 0.6f, 1e-6f);  // 0.5 m radius, raised 0.1 m by its pose
}

TEST_F(ScenarioLoaderTest, LinkMassPropertiesAndBuoyancyFromAClosedMesh) {
  // A 2 m x 1 m x 0.5 m box hull (generated, exported as GLB) placed 1 m forward in L, density 1000.
  ASSERT_EQ(assets::write_scene(assets::single_mesh_scene(assets::make_box(2.0, 1.0, 0.5)),
                                (dir_ / "hull.glb").string()),
            "");
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: box
    type: rov
    links:
      - name: hull
        mesh: {file: hull.glb, pose: {position: [1, 0, 0]}}
        density: 1000
)");
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result.warnings.empty());
  const LinkSpec& link = result.model->vehicles[0].links[0];
  ASSERT_TRUE(link.mesh.has_value());
  EXPECT_TRUE(link.mesh->closed);
  // Closed forms of a homogeneous box, V = a b c = 1 m^3, I = m/12 diag(b^2+c^2, a^2+c^2, a^2+b^2).
  // The vertices are floats (2, 1, 0.5, 1 are exact in float), so 1e-9 relative covers the algebra.
  EXPECT_NEAR(link.mass, 1000.0, 1e-6);
  EXPECT_NEAR((link.p_LLcm - Eigen::Vector3d(1.0, 0.0, 0.0)).norm(), 0.0, 1e-9);
  const Eigen::Matrix3d I_expected = Eigen::Vector3d(1.25, 4.25, 5.0).asDiagonal() * (1000.0 / 12.0);
  EXPECT_LT((link.I_LLcm_L - I_expected).norm(), 1e-9 * I_expected.norm());
  // No buoyancy key: the closed hull displaces its own volume at its centroid.
  EXPECT_NEAR(link.buoyancy.volume, 1.0, 1e-9);
  EXPECT_NEAR((link.buoyancy.p_LCb - Eigen::Vector3d(1.0, 0.0, 0.0)).norm(), 0.0, 1e-9);
}

TEST_F(ScenarioLoaderTest, OpenMeshesWarnForBuoyancyAndCannotGiveMass) {
  ASSERT_EQ(assets::write_scene(assets::textured_quad_scene(4, 4), (dir_ / "quad.glb").string()), "");
  const std::string warn = write("w.yaml", R"(world: {}
vehicles:
  - name: plate
    type: lander
    links:
      - name: hull
        mesh: {file: quad.glb}
        mass: 5
        inertia: {ixx: 1, iyy: 1, izz: 1}
)");
  const LoadResult w = load_scenario_file(warn);
  ASSERT_TRUE(w.ok());
  ASSERT_EQ(w.warnings.size(), 1u);
  EXPECT_EQ(w.warnings[0].format(),
            warn + ":7:15: warning: vehicles[0].links[0].mesh: mesh is open (4 boundary edges): its volume is "
                   "undefined, so the link gets no buoyancy; give buoyancy: {volume, center} or close the mesh");
  EXPECT_EQ(w.model->vehicles[0].links[0].buoyancy.volume, 0.0);

  const std::string error = write("e.yaml", R"(world: {}
vehicles:
  - name: plate
    type: lander
    links:
      - name: hull
        mesh: {file: quad.glb}
        density: 1000
        mass: 5
  - name: other
    type: lander
    links:
      - name: hull
        density: 1000
)");
  EXPECT_EQ(errors_of(error),
            (Lines{error + ":7:15: error: vehicles[0].links[0].mesh: mesh is open (4 boundary edges): mass from "
                           "'density' needs a closed mesh",
                   error + ":9:9: error: vehicles[0].links[0].mass: key 'mass' cannot be combined with 'density' "
                           "(the mesh and density give it)",
                   error + ":14:9: error: vehicles[1].links[0].density: key 'density' needs 'mesh' (mass "
                           "properties from the mesh's volume)"}));
}

// A link's appearance (albedo, checkerboard) and a vehicle's initial angular velocity; then their errors.
TEST_F(ScenarioLoaderTest, AppearanceAndInitialAngularVelocity) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: target
    type: lander
    initial_angular_velocity: [0.1, -0.2, 0.3]
    links:
      - name: board
        mass: 1.0
        inertia: {ixx: 1, iyy: 1, izz: 1}
        appearance:
          albedo: [0.9, 0.8, 0.7]
          checkerboard: {squares: [8, 6], square_size: 0.05, pose: {position: [-0.2, -0.15, 0.0]}}
      - {name: plain, mass: 1.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const VehicleSpec& target = result.model->vehicles[0];
  EXPECT_EQ(target.w_WB_initial, Eigen::Vector3d(0.1, -0.2, 0.3));
  const AppearanceSpec& board = target.links[0].appearance;
  ASSERT_TRUE(board.albedo && board.checkerboard);
  EXPECT_EQ((*board.albedo)[2], 0.7);
  EXPECT_EQ(board.checkerboard->columns, 8);
  EXPECT_EQ(board.checkerboard->rows, 6);
  EXPECT_EQ(board.checkerboard->square_size, 0.05);
  EXPECT_EQ(board.checkerboard->X_LP.translation(), Eigen::Vector3d(-0.2, -0.15, 0.0));
  EXPECT_EQ(board.checkerboard->dark_albedo[0], 0.03);
  EXPECT_FALSE(target.links[1].appearance.albedo || target.links[1].appearance.checkerboard);

  const std::string bad = write("bad.yaml", R"(world: {}
vehicles:
  - name: target
    type: lander
    initial_angular_velocity: [0, 0, 500]
    links:
      - name: board
        mass: 1.0
        inertia: {ixx: 1, iyy: 1, izz: 1}
        appearance:
          albedo: [1.5, 0, 0]
          checkerboard: {squares: [8.5, 6], dark_albedo: [0, 0, 0]}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":5:38: error: vehicles[0].initial_angular_velocity[2]: must be in [-100, 100] (got 500)",
                   bad + ":11:20: error: vehicles[0].links[0].appearance.albedo[0]: must be in [0, 1] (got 1.5)",
                   bad + ":12:25: error: vehicles[0].links[0].appearance.checkerboard: missing required key "
                         "'square_size'",
                   bad + ":12:35: error: vehicles[0].links[0].appearance.checkerboard.squares: must be two whole "
                         "numbers [columns, rows] (got [8.5, 6])"}));
}

}  // namespace
}  // namespace hadal::config
