#include "hadal/config/scenario_loader.h"
#include "hadal/config/security_block.h"

#include <gtest/gtest.h>

#include "hadal/geometry/primitive_mesh.h"
#include "hadal/physics/soil_presets.h"
#include "hadal/render/water_presets.h"
#include "hadal/sensors/geomagnetic.h"
#include "hadal/sensors/noise.h"
#include <opencv2/imgcodecs.hpp>

#include "hadal/assets/mesh_generators.h"
#include "hadal/assets/scene_writer.h"
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace hadal::config {
namespace {

namespace fs = std::filesystem;
using Lines = std::vector<std::string>;

// Tolerance for values that went through a few floating-point operations (deg -> rad, normalisation).
constexpr double kTol = 1e-12;

// Each test writes its files into its own temporary directory, removed afterwards.
class ScenarioLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::temp_directory_path() / ("hadal_config_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `text` to dir/relative and returns that path.
  std::string write(const std::string& relative, const std::string& text) {
    const fs::path path = dir_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path.string();
  }

  // The formatted diagnostics of loading `path`; the model must be set exactly when there are none.
  static std::vector<std::string> errors_of(const std::string& path) {
    const LoadResult result = load_scenario_file(path);
    EXPECT_EQ(result.model.has_value(), result.errors.empty());
    std::vector<std::string> lines;
    for (const Diagnostic& diagnostic : result.errors) lines.push_back(diagnostic.format());
    return lines;
  }

  fs::path dir_;
};

// A valid vehicle entry with an inline definition and one thruster. It starts with a newline, so after
// "vehicles:" on line N its "- name: auv" is line N + 1 and its last line ("max_rpm") is N + 14; tests
// append keys after it or place broken entries around it.
constexpr const char* kInlineVehicle = R"(
  - name: auv
    type: auv
    links:
      - name: hull
        mass: 30.0
        inertia: {ixx: 0.09, iyy: 6.4, izz: 6.4}
    thrusters:
      - name: main
        link: hull
        position: [-0.8, 0, 0]
        direction: [2, 0, 0]
        propeller_diameter: 0.1
        thrust_coefficient: 0.4
        max_rpm: 1500
)";

// --- valid input ---------------------------------------------------------------------------------------

TEST_F(ScenarioLoaderTest, DefaultScenarioLoadsWithTypedValues) {
  const std::string path = std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/default.yaml";
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& diagnostic : result.errors) ADD_FAILURE() << diagnostic.format();
  ASSERT_TRUE(result.ok());
  const Model& model = *result.model;

  EXPECT_EQ(model.scenario_file, path);
  EXPECT_EQ(model.world.physics_rate_hz, 500.0);
  EXPECT_EQ(model.world.step_size(), 0.002);
  EXPECT_EQ(model.world.gravity_W, Eigen::Vector3d(0.0, 0.0, -9.80665));
  EXPECT_EQ(model.world.seed, 42u);
  EXPECT_EQ(model.world.frame_id, "world");
  EXPECT_EQ(model.world.clock_rate_hz, 100.0);
  EXPECT_EQ(model.world.status_rate_hz, 10.0);
  EXPECT_EQ(model.world.water.surface_z, 0.0);
  EXPECT_EQ(model.world.water.density, 1025.0);
  EXPECT_EQ(model.world.seabed.type, SeabedType::kProcedural);
  EXPECT_EQ(model.world.seabed.z, -100.0);
  ASSERT_NE(model.world.seabed.mesh, nullptr);
  EXPECT_EQ(model.world.seabed.mesh->num_triangles(), 80000u);  // (400 / 2)^2 cells x 2
  EXPECT_EQ(model.world.seabed.procedural.seed, 42u);             // world.seed
  EXPECT_NEAR(model.world.seabed.procedural.slope, M_PI / 180.0, kTol);
  EXPECT_NEAR(model.world.origin.latitude_rad, 43.0 * M_PI / 180.0, kTol);
  EXPECT_NEAR(model.world.origin.longitude_rad, 5.0 * M_PI / 180.0, kTol);
  EXPECT_EQ(model.world.origin.height_m, 0.0);

  ASSERT_EQ(model.vehicles.size(), 2u);  // the AUV and the lander it looks at
  EXPECT_EQ(model.vehicles[1].name, "lander");
  EXPECT_EQ(model.vehicles[1].type, VehicleType::kLander);
  const VehicleSpec& auv = model.vehicles[0];
  EXPECT_EQ(auv.name, "auv");
  EXPECT_EQ(auv.type, VehicleType::kAuv);
  // The include is resolved relative to the scenario's directory.
  EXPECT_EQ(auv.source_file,
            std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/../vehicles/torpedo_auv.yaml");
  EXPECT_TRUE(
      fs::equivalent(auv.source_file, std::string(HADAL_SOURCE_DIR) + "/configs/vehicles/torpedo_auv.yaml"));
  EXPECT_TRUE(auv.X_WB_initial.isApprox(Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, -96.0)), kTol));
  // The entry adds a camera to the included sensors, and two lights.
  ASSERT_EQ(auv.sensors.size(), 7u);
  EXPECT_EQ(auv.sensors[6].name, "camera");
  EXPECT_EQ(auv.sensors[6].type(), "camera");
  EXPECT_EQ(auv.sensors[6].frame_id, "auv/camera");
  EXPECT_EQ(spec_of<sensors::CameraSensor>(auv.sensors[6]).lens->D()[0], -0.17473019446863114);  // svin2 preset
  EXPECT_EQ(spec_of<sensors::CameraSensor>(auv.sensors[6]).lens->width_px(), 640);
  ASSERT_EQ(auv.lights.size(), 2u);
  EXPECT_EQ(auv.lights[1].name, "light_starboard");
  EXPECT_EQ(model.world.optics.daylight.Kd_per_m[2], render::jerlov_Kd_per_m(render::JerlovType::kIII)[2]);
  EXPECT_EQ(auv.v_WB_initial, Eigen::Vector3d::Zero());
  EXPECT_EQ(auv.command_timeout, 1.0);
  EXPECT_EQ(auv.odometry_rate_hz, 50.0);
  EXPECT_EQ(auv.thruster_state_rate_hz, 20.0);

  ASSERT_EQ(auv.links.size(), 1u);
  const LinkSpec& hull = auv.links[0];
  EXPECT_EQ(hull.name, "hull");
  EXPECT_EQ(hull.mass, 30.0);
  EXPECT_EQ(hull.p_LLcm, Eigen::Vector3d(-0.0082, 0.0, -0.01));
  EXPECT_EQ(hull.I_LLcm_L, Eigen::Vector3d(0.0901, 6.445, 6.445).asDiagonal().toDenseMatrix());
  EXPECT_TRUE(hull.X_BL.isApprox(Eigen::Isometry3d::Identity(), kTol));
  ASSERT_EQ(hull.collisions.size(), 5u);  // capsule hull + four fins
  const CollisionShape& capsule = hull.collisions[0];
  EXPECT_EQ(capsule.type, CollisionShapeType::kCapsule);
  EXPECT_EQ(capsule.radius, 0.0775);
  EXPECT_EQ(capsule.length, 1.445);
  // rpy_deg [0, 90, 0]: the capsule's axis (G's z) lies along body x.
  EXPECT_TRUE((capsule.X_LG.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), kTol));
  EXPECT_EQ(hull.collisions[1].type, CollisionShapeType::kBox);
  EXPECT_EQ(hull.collisions[1].box_size, Eigen::Vector3d(0.15, 0.005, 0.13));
  EXPECT_EQ(auv.fluid.model, FluidModelType::kSurface);
  EXPECT_EQ(auv.fluid.added_mass.model, AddedMassModel::kEllipsoid);
  EXPECT_TRUE(model.world.dynamics.earth_rotation);

  ASSERT_EQ(auv.actuators.size(), 3u);
  EXPECT_EQ(auv.num_controls(), 3u);
  EXPECT_EQ(auv.actuators[0].name, "main");
  EXPECT_EQ(auv.actuators[0].type(), "thruster");
  EXPECT_EQ(auv.actuators[0].link_index, 0);
  const physics::ThrusterActuator::Spec& main = spec_of<physics::ThrusterActuator>(auv.actuators[0]);
  EXPECT_EQ(main.p_LT, Eigen::Vector3d(-0.8, 0.0, 0.0));
  EXPECT_EQ(main.axis_L, Eigen::Vector3d::UnitX());
  EXPECT_EQ(main.propeller_diameter, 0.1);
  EXPECT_EQ(main.thrust_coefficient, 0.4);
  EXPECT_EQ(main.torque_coefficient, 0.05);
  EXPECT_EQ(main.rotor_time_constant_s, 0.1);
  EXPECT_EQ(main.max_rotor_speed_rev_s, 25.0);  // 1500 rpm
  EXPECT_EQ(main.handedness, 1);
  EXPECT_EQ(auv.actuators[1].name, "heave");
  EXPECT_EQ(spec_of<physics::ThrusterActuator>(auv.actuators[1]).axis_L, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(spec_of<physics::ThrusterActuator>(auv.actuators[1]).max_rotor_speed_rev_s, 50.0);
  EXPECT_EQ(auv.actuators[2].name, "sway");
  EXPECT_EQ(spec_of<physics::ThrusterActuator>(auv.actuators[2]).axis_L, Eigen::Vector3d::UnitY());

  EXPECT_EQ(auv.fluid.hydrodynamics.drag, 1.0);
  EXPECT_EQ(auv.fluid.hydrodynamics.skin_friction, 0.004);

  ASSERT_GE(auv.schedule.size(), 2u);
  EXPECT_EQ(auv.schedule.front().time, 0.0);
  EXPECT_EQ(auv.schedule.front().setpoints, (std::vector<double>{0.6, 0.0, 0.0}));
  EXPECT_EQ(auv.schedule.back().setpoints, (std::vector<double>{0.0, 0.0, 0.0}));
  for (const SetpointKeyframe& keyframe : auv.schedule) EXPECT_EQ(keyframe.setpoints.size(), 3u);
}

TEST_F(ScenarioLoaderTest, InlineVehicleGetsDefaultsAndConversions) {
  const std::string path = write("s.yaml", std::string(R"(world: {}
vehicles:
  - name: rov_1
    initial_pose: {position: [1, 2, -3], rpy_deg: [0, 0, 90]}
    type: rov
    links:
      - name: frame
        mass: 100
        inertia: {ixx: 10, iyy: 10, izz: 10, ixy: 1}
        collisions:
          - {shape: box, size: [1, 0.5, 0.4]}
          - {shape: capsule, radius: 0.1, length: 0.3, pose: {position: [0, 0, 1]}}
      - name: arm
        pose: {position: [0.5, 0, 0], rpy_deg: [90, 0, 0]}
        mass: 5
        inertia: {ixx: 0.1, iyy: 0.1, izz: 0.1}
        buoyancy: {volume: 0.004}
    thrusters:
      - {name: t, link: arm, position: [0, 0, 0], direction: [0, 3, 4], propeller_diameter: 0.2,
         thrust_coefficient: 0.5, max_rpm: 600, handedness: left, torque_coefficient: 0, rotor_time_constant_s: 0}
    schedule:
      - {time_s: 1.5, setpoints: [-1]}
      - {time_s: 2, setpoints: [1]}
)"));
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& diagnostic : result.errors) ADD_FAILURE() << diagnostic.format();
  ASSERT_TRUE(result.ok());
  const Model& model = *result.model;
  EXPECT_EQ(model.world.physics_rate_hz, 500.0);
  EXPECT_EQ(model.world.seed, 0u);
  EXPECT_EQ(model.world.seabed.z, -100.0);
  EXPECT_EQ(model.world.clock_rate_hz, 100.0);
  ASSERT_EQ(model.vehicles.size(), 1u);
  const VehicleSpec& rov = model.vehicles[0];
  EXPECT_EQ(rov.type, VehicleType::kRov);
  EXPECT_EQ(rov.source_file, path);
  EXPECT_EQ(rov.odometry_rate_hz, 50.0);
  EXPECT_EQ(rov.command_timeout, 1.0);
  // Yaw 90 deg: body x points along world y.
  EXPECT_TRUE(rov.X_WB_initial.translation().isApprox(Eigen::Vector3d(1, 2, -3), kTol));
  EXPECT_TRUE(
      (rov.X_WB_initial.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), kTol));
  ASSERT_EQ(rov.links.size(), 2u);
  EXPECT_EQ(rov.links[0].I_LLcm_L(0, 1), 1.0);
  EXPECT_EQ(rov.links[0].I_LLcm_L(1, 0), 1.0);
  EXPECT_EQ(rov.links[0].buoyancy.volume, 0.0);
  ASSERT_EQ(rov.links[0].collisions.size(), 2u);
  EXPECT_EQ(rov.links[0].collisions[0].box_size, Eigen::Vector3d(1, 0.5, 0.4));
  EXPECT_EQ(rov.links[0].collisions[1].type, CollisionShapeType::kCapsule);
  EXPECT_EQ(rov.links[0].collisions[1].X_LG.translation(), Eigen::Vector3d(0, 0, 1));
  // Roll 90 deg: link y points along body z.
  EXPECT_TRUE(
      (rov.links[1].X_BL.linear() * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), kTol));
  EXPECT_EQ(rov.links[1].buoyancy.volume, 0.004);
  ASSERT_EQ(rov.actuators.size(), 1u);
  EXPECT_EQ(rov.actuators[0].link_index, 1);
  const physics::ThrusterActuator::Spec& t = spec_of<physics::ThrusterActuator>(rov.actuators[0]);
  EXPECT_TRUE(t.axis_L.isApprox(Eigen::Vector3d(0, 0.6, 0.8), kTol));
  EXPECT_EQ(t.max_rotor_speed_rev_s, 10.0);
  EXPECT_EQ(t.handedness, -1);
  EXPECT_EQ(t.torque_coefficient, 0.0);
  EXPECT_EQ(t.rotor_time_constant_s, 0.0);
  EXPECT_EQ(rov.fluid.linear_damping, Vector6d::Zero());
  ASSERT_EQ(rov.schedule.size(), 2u);
  EXPECT_EQ(rov.schedule[0].time, 1.5);
  EXPECT_EQ(rov.schedule[0].setpoints, std::vector<double>{-1.0});
}

TEST_F(ScenarioLoaderTest, ClockRateDefaultFollowsASlowPhysicsRate) {
  const std::string path =
      write("s.yaml", std::string("world: {physics_rate_hz: 60}\nvehicles:") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.model->world.clock_rate_hz, 60.0);
}

// --- malformed input -------------------------------------------------------------------------------------

TEST_F(ScenarioLoaderTest, MissingScenarioFile) {
  const std::string path = (dir_ / "nope.yaml").string();
  EXPECT_EQ(errors_of(path), (Lines{path + ": error: cannot open scenario file (file not found)"}));
}

TEST_F(ScenarioLoaderTest, EmptyScenarioFile) {
  const std::string path = write("s.yaml", "# nothing here\n");
  EXPECT_EQ(errors_of(path), (Lines{path + ":1:1: error: expected a map (got an empty document)"}));
}

TEST_F(ScenarioLoaderTest, SeveralDocumentsInOneFile) {
  const std::string path = write("s.yaml", "world: {}\n---\nvehicles: []\n");
  EXPECT_EQ(errors_of(path), (Lines{path + ":2:1: error: yaml: expected a single document (found more than one)"}));
}

// Found by the scenario fuzzer (tests/fuzz/scenario_fuzz.cc): a stray flow end made yaml-cpp's LoadAll
// report empty documents forever (hadald took 8 GB and never answered). Now a named error at once.
TEST_F(ScenarioLoaderTest, AStrayFlowEndIsAnErrorNotAHang) {
  const std::string path = write("s.yaml", "# a scenario\n , 0.0]} 1.0\n    odometry_rate_hz: 20\n");
  const Lines errors = errors_of(path);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find(": error: yaml: "), std::string::npos) << errors[0];
}

TEST_F(ScenarioLoaderTest, EmptyValuesAndNonStringKeys) {
  const std::string path = write("s.yaml", R"(world:
  seed:
  ? [1]
  : 2
vehicles:
  - auv
)");
  // An empty value is reported at its key (yaml-cpp marks it at the next token).
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":2:3: error: world.seed: expected a non-negative integer (got null)",
                   path + ":3:5: error: world: keys must be strings (got a list of 1)",
                   path + ":6:5: error: vehicles[0]: expected a map (got 'auv')"}));
}

TEST_F(ScenarioLoaderTest, UnknownKeysWithAndWithoutSuggestion) {
  const std::string path = write("s.yaml", std::string(R"(world:
  physic_rate_hz: 500
  colour: blue
vehicles:)") + kInlineVehicle + "    Mass: 3\n");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":2:3: error: world.physic_rate_hz: unknown key 'physic_rate_hz'; did you "
                          "mean 'physics_rate_hz'?",
                   path + ":3:3: error: world.colour: unknown key 'colour'",
                   path + ":19:5: error: vehicles[0].Mass: unknown key 'Mass'"}));
}

TEST_F(ScenarioLoaderTest, SurfaceFluidModelWithHydrodynamicCoefficients) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - name: hull
        mass: 30.0
        inertia: {ixx: 0.09, iyy: 6.4, izz: 6.4}
        collisions: [{shape: sphere, radius: 0.2}]
    fluid:
      model: surface
      hydrodynamics: {drag: 0.8, skin_friction: 0.003, lift: 0, magnus: 0.01}
  - name: rov
    type: rov
    links:
      - name: hull
        mass: 30.0
        inertia: {ixx: 0.09, iyy: 6.4, izz: 6.4}
        collisions: [{shape: box, size: [1, 1, 1]}]
    fluid: {model: surface}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const FluidSpec& auv = result.model->vehicles[0].fluid;
  EXPECT_EQ(auv.model, FluidModelType::kSurface);
  EXPECT_EQ(auv.hydrodynamics.drag, 0.8);
  EXPECT_EQ(auv.hydrodynamics.skin_friction, 0.003);
  EXPECT_EQ(auv.hydrodynamics.lift, 0.0);
  EXPECT_EQ(auv.hydrodynamics.magnus, 0.01);
  EXPECT_TRUE(auv.hydrodynamics.buoyancy);
  const FluidSpec& rov = result.model->vehicles[1].fluid;
  EXPECT_EQ(rov.model, FluidModelType::kSurface);
  EXPECT_EQ(rov.hydrodynamics.drag, 1.0);  // HydrodynamicCoefficients defaults
  EXPECT_EQ(rov.hydrodynamics.skin_friction, 0.004);
  EXPECT_EQ(rov.hydrodynamics.lift, 1.0);
  EXPECT_EQ(rov.hydrodynamics.magnus, 0.0);
}

TEST_F(ScenarioLoaderTest, DefaultFluidModelFollowsTheGeometry) {
  const std::string path = write("s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + R"(
  - name: boxy
    type: rov
    links:
      - name: hull
        mass: 30.0
        inertia: {ixx: 1, iyy: 1, izz: 1}
        collisions: [{shape: box, size: [1, 1, 1]}]
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  EXPECT_EQ(result.model->vehicles[0].fluid.model, FluidModelType::kLumped);   // no faces
  EXPECT_EQ(result.model->vehicles[0].fluid.added_mass.model, AddedMassModel::kNone);
  EXPECT_EQ(result.model->vehicles[1].fluid.model, FluidModelType::kSurface);  // collision shapes
  EXPECT_EQ(result.model->vehicles[1].fluid.added_mass.model, AddedMassModel::kEllipsoid);
  EXPECT_FALSE(result.model->vehicles[1].fluid.added_mass.semi_axes_E.has_value());
  EXPECT_TRUE(result.model->vehicles[1].fluid.added_mass.coriolis);
  EXPECT_TRUE(result.model->world.dynamics.gyroscopic);
  EXPECT_FALSE(result.model->world.dynamics.earth_rotation);
}

TEST_F(ScenarioLoaderTest, AddedMassAndDynamicsKeys) {
  const std::string path = write("s.yaml", R"(world:
  dynamics: {gyroscopic: false, earth_rotation: true}
vehicles:
  - name: a
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass:
        semi_axes: [0.8, 0.1, 0.1]
        pose: {position: [0.1, 0, 0], rpy_deg: [0, 0, 90]}
        coriolis: false
  - name: b
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass:
        model: matrix
        reference_point: [0, 0, 0.05]
        matrix: [1, 0, 0, 0, 0, 0,  0, 20, 0, 0, 0, 0.5,  0, 0, 20, 0, 0, 0,
                 0, 0, 0, 0.1, 0, 0,  0, 0, 0, 0, 3, 0,  0, 0.5, 0, 0, 0, 3]
  - name: c
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid: {model: lumped, added_mass: {model: none}}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  EXPECT_FALSE(result.model->world.dynamics.gyroscopic);
  EXPECT_TRUE(result.model->world.dynamics.earth_rotation);
  const AddedMassSpec& a = result.model->vehicles[0].fluid.added_mass;
  EXPECT_EQ(a.model, AddedMassModel::kEllipsoid);
  ASSERT_TRUE(a.semi_axes_E.has_value());
  EXPECT_EQ(*a.semi_axes_E, Eigen::Vector3d(0.8, 0.1, 0.1));
  EXPECT_EQ(a.X_BE.translation(), Eigen::Vector3d(0.1, 0, 0));
  EXPECT_NEAR((a.X_BE.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-15);
  EXPECT_FALSE(a.coriolis);
  const AddedMassSpec& b = result.model->vehicles[1].fluid.added_mass;
  EXPECT_EQ(b.model, AddedMassModel::kMatrix);
  EXPECT_EQ(b.p_BR, Eigen::Vector3d(0, 0, 0.05));
  EXPECT_EQ(b.M_A0(1, 1), 20.0);
  EXPECT_EQ(b.M_A0(5, 1), 0.5);
  EXPECT_EQ(b.M_A0(1, 5), 0.5);
  EXPECT_EQ(result.model->vehicles[2].fluid.added_mass.model, AddedMassModel::kNone);
}

TEST_F(ScenarioLoaderTest, AddedMassErrors) {
  const std::string path = write("s.yaml", R"(world:
  dynamics: {gyroscopic: yes, coriolis: true}
vehicles:
  - name: a
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass: {model: ellipsoid, pose: {position: [0, 0, 0]}, matrix: [1]}
  - name: b
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass: {semi_axes: [1, 0, 1], coriolis: 1}
  - name: c
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass:
        model: matrix
        matrix: [1, 2, 0, 0, 0, 0,  0, 1, 0, 0, 0, 0,  0, 0, 1, 0, 0, 0,
                 0, 0, 0, 1, 0, 0,  0, 0, 0, 0, 1, 0,  0, 0, 0, 0, 0, 1]
  - name: d
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass:
        model: matrix
        matrix: [1, 0, 0, 0, 0, 0,  0, -1, 0, 0, 0, 0,  0, 0, 1, 0, 0, 0,
                 0, 0, 0, 1, 0, 0,  0, 0, 0, 0, 1, 0,  0, 0, 0, 0, 0, 1]
  - name: e
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass: {model: matrix}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":2:26: error: world.dynamics.gyroscopic: expected true or false (got 'yes')",
                   path + ":2:31: error: world.dynamics.coriolis: unknown key 'coriolis'",
                   path + ":9:38: error: vehicles[0].fluid.added_mass.pose: key 'pose' needs 'semi_axes' (without them "
                          "the ellipsoid is fitted to the hull, centre and axes included)",
                   path + ":9:67: error: vehicles[0].fluid.added_mass.matrix: key 'matrix' is not used by "
                          "added_mass model 'ellipsoid'",
                   path + ":15:35: error: vehicles[1].fluid.added_mass.semi_axes[1]: must be > 0 (got 0)",
                   path + ":15:52: error: vehicles[1].fluid.added_mass.coriolis: expected true or false (got '1')",
                   path + ":23:17: error: vehicles[2].fluid.added_mass.matrix: must be symmetric (largest "
                          "|M_ij - M_ji| = 2)",
                   path + ":32:17: error: vehicles[3].fluid.added_mass.matrix: must be positive semidefinite "
                          "(an added mass cannot lower the kinetic energy)",
                   path + ":39:19: error: vehicles[4].fluid.added_mass: missing required key 'matrix' (model "
                          "'matrix' needs the 6x6 added-mass matrix)"}));
}

TEST_F(ScenarioLoaderTest, SensorsLoadWithDefaults) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 1000}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
      - {name: mast, mass: 1.0, inertia: {ixx: 1, iyy: 1, izz: 1}, pose: {position: [0, 0, 0.5]}}
    sensors:
      - {name: depth, type: pressure}
      - name: depth_aft
        type: pressure
        link: mast
        pose: {position: [-0.7, 0, 0.1]}
        rate_hz: 200
        frame_id: auv/aft_pressure
        noise_stddev: 50
        resolution: 10
        range_max: 7.0e7
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const std::vector<SensorSpec>& sensors = result.model->vehicles[0].sensors;
  ASSERT_EQ(sensors.size(), 2u);
  EXPECT_EQ(sensors[0].name, "depth");
  EXPECT_EQ(sensors[0].type(), "pressure");
  EXPECT_EQ(sensors[0].link_index, 0);
  EXPECT_EQ(sensors[0].rate_hz, 10.0);
  EXPECT_EQ(sensors[0].frame_id, "auv/depth");
  EXPECT_EQ(spec_of<sensors::PressureSensor>(sensors[0]).noise_stddev, 0.0);
  EXPECT_EQ(sensors[1].link_index, 1);
  EXPECT_EQ(sensors[1].X_LS.translation(), Eigen::Vector3d(-0.7, 0, 0.1));
  EXPECT_EQ(sensors[1].rate_hz, 200.0);
  EXPECT_EQ(sensors[1].frame_id, "auv/aft_pressure");
  EXPECT_EQ(spec_of<sensors::PressureSensor>(sensors[1]).noise_stddev, 50.0);
  EXPECT_EQ(spec_of<sensors::PressureSensor>(sensors[1]).resolution, 10.0);
  EXPECT_EQ(spec_of<sensors::PressureSensor>(sensors[1]).range_max, 7.0e7);
}

TEST_F(ScenarioLoaderTest, SensorErrors) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 500}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: depth, type: barometer}
      - {name: depth, type: pressure, link: fin}
      - {name: fast, type: pressure, rate_hz: 1000, noise_stddev: -1}
      - {type: pressure, colour: red}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":8:29: error: vehicles[0].sensors[0].type: must be one of 'pressure', 'imu', "
                          "'magnetometer', 'gps', 'dvl', 'altimeter', 'profiler', 'camera', 'fls', 'multibeam', "
                          "'sidescan' (got 'barometer')",
                   path + ":9:16: error: vehicles[0].sensors[1].name: duplicate sensor name 'depth' (first "
                          "used by vehicles[0].sensors[0])",
                   path + ":9:45: error: vehicles[0].sensors[1].link: no link named 'fin' in this vehicle "
                          "(links: hull)",
                   path + ":10:47: error: vehicles[0].sensors[2].rate_hz: must be <= world.physics_rate_hz "
                          "(500) (got 1000)",
                   path + ":10:67: error: vehicles[0].sensors[2].noise_stddev: must be >= 0 (got -1)",
                   path + ":11:9: error: vehicles[0].sensors[3]: missing required key 'name'",
                   path + ":11:26: error: vehicles[0].sensors[3].colour: unknown key 'colour'"}));
}

// The profiler (a captured kind): its keys and the common latency_s, which only captured kinds take.
TEST_F(ScenarioLoaderTest, ProfilerKeysAndLatency) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 500}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: scan, type: profiler, rate_hz: 5, latency_s: 0.08, beams: 128, fov_deg: 60, beam_width_deg: 2,
         rays_per_beam: 4, min_range: 1, max_range: 30, noise_stddev: 0.02, resolution: 0.01}
      - {name: plain, type: profiler}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const auto& sensors = result.model->vehicles[0].sensors;
  EXPECT_EQ(sensors[0].type(), "profiler");
  EXPECT_EQ(sensors[0].latency_s, 0.08);
  const sensors::ProfilerSensor::Spec& scan = spec_of<sensors::ProfilerSensor>(sensors[0]);
  EXPECT_EQ(scan.beams, 128);
  EXPECT_DOUBLE_EQ(scan.fov, 60.0 * kDegToRad);
  EXPECT_DOUBLE_EQ(scan.beam_width, 2.0 * kDegToRad);
  EXPECT_EQ(scan.rays_per_beam, 4);
  EXPECT_EQ(scan.min_range, 1.0);
  EXPECT_EQ(scan.max_range, 30.0);
  EXPECT_EQ(scan.noise_stddev, 0.02);
  EXPECT_EQ(scan.resolution, 0.01);
  EXPECT_EQ(sensors[1].latency_s, 0.0);
  EXPECT_EQ(spec_of<sensors::ProfilerSensor>(sensors[1]).beams, sensors::ProfilerSensor::Spec{}.beams);

  const std::string bad = write("bad.yaml", R"(world: {physics_rate_hz: 500}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: scan, type: profiler, beams: 12.5, rays_per_beam: 0, latency_s: -1, max_range: 0.2}
      - {name: depth, type: pressure, latency_s: 0.1}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":8:45: error: vehicles[0].sensors[0].beams: must be a whole number (got 12.5)",
                   bad + ":8:66: error: vehicles[0].sensors[0].rays_per_beam: must be in [1, 64] (got 0)",
                   bad + ":8:80: error: vehicles[0].sensors[0].latency_s: must be in [0, 10] (got -1)",
                   bad + ":8:84: error: vehicles[0].sensors[0].max_range: max_range (0.2 m) must exceed min_range "
                         "(0.5 m)",
                   bad + ":9:39: error: vehicles[0].sensors[1].latency_s: key 'latency_s' is not used by sensor "
                         "type 'pressure' (it samples on the stepping thread, without latency)"}));
}

// A camera (calibration, lens model, clip, sensor figures), a vehicle's lights and world.optics; then
// their errors.
TEST_F(ScenarioLoaderTest, CameraLightsAndOptics) {
  const std::string path = write("s.yaml", R"(world:
  physics_rate_hz: 500
  optics: {absorption: [0.4, 0.07, 0.03], scattering: [0.1, 0.1, 0.1], phase_g: 0.9, forward_scatter_max_angle_deg: 5,
           daylight: {surface_irradiance: [100, 120, 110], jerlov_type: II}, seabed_albedo: [0.2, 0.2, 0.1],
           marine_snow: {density: 50, radius: 0.002}, seabed_pattern: {amplitude: 0.3, scale: 0.5, octaves: 3}}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: cam, type: camera, rate_hz: 5, latency_s: 0.05, width: 320, height: 240, fx: 300, fy: 301,
         cx: 160.5, cy: 119, lens_model: plumb_bob, distortion: [-0.1, 0.02, 0.001, 0, 0], near_clip: 0.2,
         far_clip: 30, encoding: mono8, exposure_s: 0.02, read_noise_e: 2, shot_noise: false}
      - {name: wide, type: camera}
    lights:
      - {name: lamp, link: hull, pose: {position: [0.5, 0.3, 0], rpy_deg: [0, 10, 0]}, inner_half_angle_deg: 30,
         outer_half_angle_deg: 35, intensity_w_per_sr: [300, 310, 320]}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const auto& sensors = result.model->vehicles[0].sensors;
  const sensors::CameraSensor::Spec& cam = spec_of<sensors::CameraSensor>(sensors[0]);
  EXPECT_EQ(sensors[0].latency_s, 0.05);
  EXPECT_EQ(cam.lens->width_px(), 320);
  EXPECT_EQ(cam.lens->spec().fy, 301.0);
  EXPECT_EQ(cam.lens->spec().cx, 160.5);
  EXPECT_EQ(cam.lens->distortion_model(), "plumb_bob");
  EXPECT_EQ(cam.lens->D(), (std::vector<double>{-0.1, 0.02, 0.001, 0.0, 0.0}));
  EXPECT_EQ(cam.near_m, 0.2);
  EXPECT_EQ(cam.far_m, 30.0);
  EXPECT_TRUE(cam.mono);
  EXPECT_EQ(cam.sensor.exposure_s, 0.02);
  EXPECT_FALSE(cam.sensor.shot_noise);
  const sensors::CameraSensor::Spec& wide = spec_of<sensors::CameraSensor>(sensors[1]);
  EXPECT_EQ(wide.lens->width_px(), 640);
  EXPECT_NEAR(2.0 * std::atan(320.0 / wide.lens->spec().fx), 90.0 * kDegToRad, 1e-12);
  EXPECT_EQ(wide.lens->spec().cx, 319.5);
  const LightSpec& lamp = result.model->vehicles[0].lights.at(0);
  EXPECT_EQ(lamp.X_LF.translation(), Eigen::Vector3d(0.5, 0.3, 0.0));
  EXPECT_DOUBLE_EQ(lamp.outer_half_angle, 35.0 * kDegToRad);
  EXPECT_EQ(lamp.intensity_W_per_sr[2], 320.0);
  const OpticsSpec& optics = result.model->world.optics;
  EXPECT_EQ(optics.water.absorption_per_m[1], 0.07);
  EXPECT_EQ(optics.water.phase_g, 0.9);
  EXPECT_DOUBLE_EQ(optics.water.forward_scatter_max_angle_rad, 5.0 * kDegToRad);
  EXPECT_EQ(optics.daylight.surface_irradiance_W_per_m2[0], 100.0);
  EXPECT_EQ(optics.daylight.Kd_per_m[2], render::jerlov_Kd_per_m(render::JerlovType::kII)[2]);
  EXPECT_EQ(optics.seabed_albedo[2], 0.1);
  EXPECT_EQ(optics.marine_snow.density_per_m3, 50.0);
  EXPECT_EQ(optics.marine_snow.radius_m, 0.002);
  EXPECT_EQ(optics.seabed_pattern.amplitude, 0.3);
  EXPECT_EQ(optics.seabed_pattern.scale_m, 0.5);
  EXPECT_EQ(optics.seabed_pattern.octaves, 3);
  EXPECT_EQ(optics.seabed_pattern.seed, result.model->world.seed);
  EXPECT_EQ(optics.marine_snow.max_range_m, render::MarineSnow{}.max_range_m);

  const std::string bad = write("bad.yaml", R"(world:
  optics: {scattering: [0.1, -1, 0], daylight: {jerlov_type: XI}, seabed_pattern: {amplitude: 2, octaves: 0},
           forward_scatter_max_angle_deg: 40}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: a, type: camera, hfov_deg: 60, fx: 300, fy: 300}
      - {name: b, type: camera, distortion: [0.1, 0, 0, 0, 0], near_clip: 3, far_clip: 2}
      - {name: c, type: camera, lens_model: fisheye, width: 0}
      - {name: d, type: camera, lens_model: plumb_bob, distortion: [-0.9, 0, 0, 0, 0]}
    lights:
      - {name: lamp, link: mast, inner_half_angle_deg: 40, outer_half_angle_deg: 30}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":2:30: error: world.optics.scattering[1]: must be in [0, 100] (got -1)",
                   bad + ":2:62: error: world.optics.daylight.jerlov_type: unknown Jerlov water type 'XI' (one of I, "
                         "IA, IB, II, III, 1C, 3C, 5C, 7C, 9C)",
                   bad + ":2:95: error: world.optics.seabed_pattern.amplitude: must be in [0, 1] (got 2)",
                   bad + ":2:107: error: world.optics.seabed_pattern.octaves: must be in [1, 8] (got 0)",
                   bad + ":3:43: error: world.optics.forward_scatter_max_angle_deg: must be in [0, 30] (got 40)",
                   bad + ":10:33: error: vehicles[0].sensors[0].hfov_deg: give either hfov_deg or the calibration fx, "
                         "fy, not both",
                   bad + ":11:33: error: vehicles[0].sensors[1].distortion: a pinhole lens has no distortion (set "
                         "lens_model: plumb_bob or equidistant)",
                   bad + ":11:78: error: vehicles[0].sensors[1].far_clip: far_clip (2 m) must exceed near_clip (3 m)",
                   bad + ":12:45: error: vehicles[0].sensors[2].lens_model: must be one of 'pinhole', 'plumb_bob', "
                         "'radial_tangential', 'equidistant' (got 'fisheye')",
                   bad + ":12:61: error: vehicles[0].sensors[2].width: must be in [1, 8192] (got 0)",
                   bad + ":13:56: error: vehicles[0].sensors[3].distortion: unusable lens: distortion: the "
                         "radial_tangential distortion has no inverse at pixel (0, 0): the lens folds over inside the "
                         "image (monotone up to r = 0.6085806195); check the coefficients' signs and the image size",
                   bad + ":15:28: error: vehicles[0].lights[0].link: no link named 'mast' in this vehicle (links: hull)",
                   bad + ":15:60: error: vehicles[0].lights[0].outer_half_angle_deg: the beam's outer half angle (30 "
                         "deg) must exceed its inner half angle (40 deg)"}));
}

// A camera from a preset (render/camera_presets.h), downscaled; then the preset's errors.
TEST_F(ScenarioLoaderTest, CameraPresetAndDownscale) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: cam, type: camera, preset: svin2_stereo_rig_v2_left, downscale: 2.5}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const render::Lens& lens = *spec_of<sensors::CameraSensor>(result.model->vehicles[0].sensors[0]).lens;
  EXPECT_EQ(lens.width_px(), 640);
  EXPECT_EQ(lens.height_px(), 480);
  EXPECT_DOUBLE_EQ(lens.spec().fx, 1156.5188534683703 / 2.5);
  EXPECT_DOUBLE_EQ(lens.spec().cy, (617.2779853849335 + 0.5) / 2.5 - 0.5);
  EXPECT_EQ(lens.D()[0], -0.17473019446863114);

  const std::string bad = write("bad.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: a, type: camera, preset: gopro}
      - {name: b, type: camera, preset: subpipe_gopro_hero10, fx: 300}
      - {name: c, type: camera, preset: subpipe_gopro_hero10, downscale: 3}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":8:33: error: vehicles[0].sensors[0].preset: unknown camera preset 'gopro' (presets: "
                         "'svin2_stereo_rig_v2_left', 'subpipe_gopro_hero10')",
                   bad + ":9:63: error: vehicles[0].sensors[1].fx: the preset sets the calibration; give either 'fx' "
                         "or 'preset' (use 'downscale' for a smaller image)",
                   bad + ":10:63: error: vehicles[0].sensors[2].downscale: downscale 3 does not divide the "
                         "2704 x 1520 image into whole pixels"}));
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

// The three sonars from presets and keys, world.acoustics, a link's backscatter_db and the water's pH; then
// their errors: an unknown preset, a window, a ping rate beyond the two-way travel limit, a display window.
TEST_F(ScenarioLoaderTest, SonarsFromPresetsAndKeys) {
  const std::string path = write("s.yaml", R"(world:
  physics_rate_hz: 500
  water: {ph: 7.8}
  acoustics: {seabed_backscatter_db: -30, vehicle_backscatter_db: -12}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, appearance: {backscatter_db: -5}}
    sensors:
      - {name: fls, type: fls, preset: oculus_m750d, beams: 256, latency_s: 0.05}
      - {name: mbes, type: multibeam, preset: r2sonic_2024, rate_hz: 5, speckle: false}
      - {name: sss, type: sidescan, depression_deg: 15, max_range: 100, bins: 1000, image_dtype: float32, rate_hz: 4}
      - {name: plain, type: fls}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const WorldSpec& world = result.model->world;
  EXPECT_EQ(world.water.ph, 7.8);
  EXPECT_EQ(world.acoustics.seabed_backscatter_db, -30.0);
  EXPECT_EQ(world.acoustics.vehicle_backscatter_db, -12.0);
  EXPECT_EQ(*result.model->vehicles[0].links[0].appearance.backscatter_db, -5.0);
  const auto& sensors = result.model->vehicles[0].sensors;
  const sensors::FlsSensor::Spec& fls = spec_of<sensors::FlsSensor>(sensors[0]);
  EXPECT_EQ(fls.beams, 256);  // the file's, over the preset's 512
  EXPECT_EQ(fls.acoustics.frequency_hz, 750e3);
  EXPECT_NEAR(fls.fov, 130.0 * kDegToRad, kTol);
  EXPECT_NEAR(fls.vertical_aperture, 20.0 * kDegToRad, kTol);
  EXPECT_EQ(fls.acoustics.max_range, 40.0);
  EXPECT_EQ(sensors[0].rate_hz, 10.0);  // the preset's
  EXPECT_EQ(sensors[0].latency_s, 0.05);
  ASSERT_TRUE(fls.ping);
  EXPECT_EQ(fls.ping->beams.size(), 256u);
  EXPECT_EQ(fls.ping->rays_u * fls.ping->rays_v, 4 * 512);  // rays_per_cell x bins
  const sensors::MultibeamSensor::Spec& mbes = spec_of<sensors::MultibeamSensor>(sensors[1]);
  EXPECT_EQ(mbes.beams, 256);
  EXPECT_NEAR(mbes.across_beam_width, 0.5 * kDegToRad, kTol);
  EXPECT_EQ(sensors[1].rate_hz, 5.0);  // the file's
  EXPECT_FALSE(mbes.acoustics.speckle);
  const sensors::SidescanSensor::Spec& sss = spec_of<sensors::SidescanSensor>(sensors[2]);
  EXPECT_NEAR(sss.depression, 15.0 * kDegToRad, kTol);
  EXPECT_EQ(sss.acoustics.bins, 1000);
  EXPECT_TRUE(sss.encoding.float32);
  EXPECT_EQ(sss.ping->beams.size(), 2u);
  EXPECT_EQ(spec_of<sensors::FlsSensor>(sensors[3]).beams, sensors::FlsSensor::Spec{}.beams);

  const std::string bad = write("bad.yaml", R"(world: {physics_rate_hz: 500, acoustics: {seabed_backscatter_db: 3}}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: a, type: fls, preset: blueview}
      - {name: b, type: multibeam, rate_hz: 20, max_range: 100}
      - {name: c, type: sidescan, min_range: 30, max_range: 20, display_min_db: 150, display_max_db: 120}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":1:66: error: world.acoustics.seabed_backscatter_db: must be in [-80, 0] (got 3)",
                   bad + ":8:30: error: vehicles[0].sensors[0].preset: unknown forward-looking sonar preset 'blueview' "
                         "(presets: 'oculus_m750d', 'oculus_m750d_1200khz', 'gemini_720is', 'aris_explorer_3000')",
                   bad + ":9:36: error: vehicles[0].sensors[1].rate_hz: a ping every 0.05 s (rate_hz 20) is shorter "
                         "than the echoes' two-way travel time over max_range 100 m: rate_hz must be <= 8 "
                         "(1600 m/s / (2 max_range))",
                   bad + ":10:50: error: vehicles[0].sensors[2].max_range: max_range (20 m) must exceed min_range "
                         "(30 m)",
                   bad + ":10:86: error: vehicles[0].sensors[2].display_max_db: display_max_db (120) must exceed "
                         "display_min_db (150)"}));
}

TEST_F(ScenarioLoaderTest, DvlAndAltimeterFromPresetAndKeys) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 500}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: dvl, type: dvl, preset: nortek_dvl1000_4000m}
      - name: dvl2
        type: dvl
        rate_hz: 4
        preset: teledyne_workhorse_navigator_600
        beam_tilt_deg: 20
        first_beam_azimuth_deg: 0
        max_altitude: 60
        dropout_probability: 0.05
        assumed_sound_speed: 1480
        water_track: false
        water_track_layer_near: 1
        water_track_layer_far: 9
        beam_velocity_noise_stddev: 0.01
        range_noise_stddev: 0.05
        velocity_resolution: 0.001
        bias: {initial: [0.001, 0, 0], initial_stddev: 0.002, drift_rate: [0, 1.0e-7, 0], random_walk: 1.0e-5}
      - {name: alt, type: altimeter, min_range: 0.5, max_range: 50, noise_stddev: 0.02, resolution: 0.01,
         field_of_view_deg: 10}
      - {name: alt2, type: altimeter}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const std::vector<SensorSpec>& sensors = result.model->vehicles[0].sensors;
  ASSERT_EQ(sensors.size(), 4u);
  // The preset sets the rate (8 Hz), the window and the per-ping noise at that rate.
  EXPECT_EQ(sensors[0].type(), "dvl");
  EXPECT_EQ(sensors[0].rate_hz, 8.0);
  const sensors::DvlParams& nortek = spec_of<sensors::DvlSensor>(sensors[0]).params;
  EXPECT_DOUBLE_EQ(nortek.beam_tilt, 25.0 * M_PI / 180.0);
  EXPECT_EQ(nortek.min_altitude, 0.2);
  EXPECT_EQ(nortek.max_altitude, 75.0);
  EXPECT_DOUBLE_EQ(nortek.beam_velocity_noise.noise.white_noise_density, 0.005 * std::sqrt(1.0 / 8.0));
  EXPECT_DOUBLE_EQ(nortek.water_track_velocity_noise.noise.white_noise_density, 0.015 * std::sqrt(1.0 / 8.0));
  // Keys override the preset; noise per ping at the given 4 Hz.
  EXPECT_EQ(sensors[1].rate_hz, 4.0);
  const sensors::DvlParams& p = spec_of<sensors::DvlSensor>(sensors[1]).params;
  EXPECT_DOUBLE_EQ(p.beam_tilt, 20.0 * M_PI / 180.0);
  EXPECT_EQ(p.first_beam_azimuth, 0.0);
  EXPECT_EQ(p.min_altitude, 0.7);
  EXPECT_EQ(p.max_altitude, 60.0);
  EXPECT_EQ(p.dropout_probability, 0.05);
  EXPECT_EQ(p.assumed_sound_speed, 1480.0);
  EXPECT_FALSE(p.water_track);
  EXPECT_EQ(p.water_track_layer_near, 1.0);
  EXPECT_EQ(p.water_track_layer_far, 9.0);
  EXPECT_DOUBLE_EQ(p.beam_velocity_noise.noise.white_noise_density, 0.01 * 0.5);
  EXPECT_DOUBLE_EQ(p.range_noise.noise.white_noise_density, 0.05 * 0.5);
  EXPECT_EQ(p.beam_velocity_noise.lsb, 0.001);
  EXPECT_EQ(p.bias.initial, Eigen::Vector3d(0.001, 0, 0));
  EXPECT_EQ(p.bias.initial_sigma, 0.002);
  EXPECT_EQ(p.bias.drift_rate, Eigen::Vector3d(0, 1e-7, 0));
  EXPECT_EQ(p.bias.random_walk_density, 1e-5);
  const sensors::AltimeterSensor::Spec& alt = spec_of<sensors::AltimeterSensor>(sensors[2]);
  EXPECT_EQ(sensors[2].type(), "altimeter");
  EXPECT_EQ(alt.min_range, 0.5);
  EXPECT_EQ(alt.max_range, 50.0);
  EXPECT_EQ(alt.noise_stddev, 0.02);
  EXPECT_EQ(alt.resolution, 0.01);
  EXPECT_DOUBLE_EQ(alt.field_of_view, 10.0 * M_PI / 180.0);
  EXPECT_EQ(spec_of<sensors::AltimeterSensor>(sensors[3]).max_range, sensors::AltimeterSensor::Spec{}.max_range);
  EXPECT_EQ(sensors[3].rate_hz, 10.0);
}

TEST_F(ScenarioLoaderTest, DvlAndAltimeterErrors) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 500}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: a, type: dvl, preset: rdi_600}
      - {name: b, type: dvl, min_altitude: 100, beam_tilt_deg: 75}
      - {name: c, type: dvl, assumed_sound_speed: 340, water_track_layer_near: 8, water_track_layer_far: 4}
      - {name: d, type: dvl, bias: {drift: 1}, dropout_probability: 1.5}
      - {name: e, type: altimeter, min_range: 10, max_range: 5, gyro: {}}
      - {name: f, type: pressure, max_altitude: 3}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":8:30: error: vehicles[0].sensors[0].preset: unknown DVL preset 'rdi_600' (presets: "
                          "'teledyne_workhorse_navigator_600', 'teledyne_explorer_1000', 'nortek_dvl1000_4000m', "
                          "'nortek_dvl500_300m', 'sonardyne_syrinx_600', 'water_linked_a50')",
                   path + ":9:30: error: vehicles[0].sensors[1].min_altitude: max_altitude (90 m) must exceed "
                          "min_altitude (100 m)",
                   path + ":9:64: error: vehicles[0].sensors[1].beam_tilt_deg: must be in [1, 60] (got 75)",
                   path + ":10:30: error: vehicles[0].sensors[2].assumed_sound_speed: assumed_sound_speed must be "
                          "0 (measured) or in [1300, 1700] m/s, got 340",
                   path + ":10:83: error: vehicles[0].sensors[2].water_track_layer_far: the water-track layer "
                          "must have near < far (got 8 m to 4 m)",
                   path + ":11:37: error: vehicles[0].sensors[3].bias.drift: unknown key 'drift'",
                   path + ":11:69: error: vehicles[0].sensors[3].dropout_probability: must be in [0, 1] (got 1.5)",
                   path + ":12:51: error: vehicles[0].sensors[4].max_range: max_range (5 m) must exceed min_range "
                          "(10 m)",
                   path + ":12:65: error: vehicles[0].sensors[4].gyro: key 'gyro' is not used by sensor type "
                          "'altimeter'",
                   path + ":13:35: error: vehicles[0].sensors[5].max_altitude: key 'max_altitude' is not used by "
                          "sensor type 'pressure'"}));
}

TEST_F(ScenarioLoaderTest, ImuFromPresetAndFigures) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 500}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    thrusters:
      - {name: main, link: hull, position: [-0.8, 0, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
         thrust_coefficient: 0.4, max_rpm: 1500}
    sensors:
      - name: imu
        type: imu
        rate_hz: 100
        preset: honeywell_hg1700
        gyro: {arw_deg_per_sqrt_h: 0.2, range_deg_per_s: 400}
        accel: {range_g: 10, resolution_mg: 0.1}
        temperature: {reference_degc: 15, accel_mg_per_degc: 0.05}
        vibration: {thruster: main, blades: 4, accel_mg: 2}
      - {name: plain, type: imu, white_noise_only: true, preset: honeywell_hg1700}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const sensors::ImuSensor::Spec& imu = spec_of<sensors::ImuSensor>(result.model->vehicles[0].sensors[0]);
  EXPECT_EQ(result.model->vehicles[0].sensors[0].type(), "imu");
  EXPECT_DOUBLE_EQ(imu.gyro.axes[0].white_noise_density, sensors::arw_to_noise_density(0.2));  // override
  EXPECT_FALSE(imu.gyro.axes[0].gauss_markov.empty());  // the preset's bias instability
  EXPECT_DOUBLE_EQ(imu.gyro.max, 400.0 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(imu.gyro.min, -400.0 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(imu.accel.max, 10.0 * 9.80665);
  EXPECT_DOUBLE_EQ(imu.accel.lsb, 1e-4 * 9.80665);
  EXPECT_EQ(imu.temperature_reference, 15.0);
  EXPECT_DOUBLE_EQ(imu.accel_temperature_coefficient, 0.05e-3 * 9.80665);
  EXPECT_EQ(imu.vibration_thruster, 0);
  EXPECT_EQ(imu.vibration_blades, 4);
  EXPECT_DOUBLE_EQ(imu.accel_vibration_amplitude, 2e-3 * 9.80665);
  const sensors::ImuSensor::Spec& plain = spec_of<sensors::ImuSensor>(result.model->vehicles[0].sensors[1]);
  EXPECT_TRUE(plain.gyro.axes[0].gauss_markov.empty());
  EXPECT_GT(plain.gyro.axes[0].white_noise_density, 0.0);
  EXPECT_EQ(plain.gyro.scale_factor_sigma, 0.0);
}

TEST_F(ScenarioLoaderTest, ImuErrors) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 500}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: a, type: imu, preset: stim999, noise_stddev: 3}
      - {name: b, type: imu, gyro: {arw: 1}, vibration: {thruster: main}}
      - {name: c, type: pressure, preset: honeywell_hg1700}
)");
  const std::vector<std::string> errors = errors_of(path);
  ASSERT_EQ(errors.size(), 5u);
  EXPECT_NE(errors[0].find(":8:30: error: vehicles[0].sensors[0].preset: unknown IMU preset 'stim999' (presets: "),
            std::string::npos) << errors[0];
  EXPECT_NE(errors[1].find(":8:47: error: vehicles[0].sensors[0].noise_stddev: key 'noise_stddev' is not used by "
                           "sensor type 'imu'"), std::string::npos) << errors[1];
  EXPECT_NE(errors[2].find(":9:37: error: vehicles[0].sensors[1].gyro.arw: unknown key 'arw'"), std::string::npos)
      << errors[2];
  EXPECT_NE(errors[3].find(":9:68: error: vehicles[0].sensors[1].vibration.thruster: no thruster named 'main' in this "
                           "vehicle (it has none)"),
            std::string::npos) << errors[3];
  EXPECT_NE(errors[4].find(":10:35: error: vehicles[0].sensors[2].preset: key 'preset' is not used by sensor "
                           "type 'pressure'"), std::string::npos) << errors[4];
}

TEST_F(ScenarioLoaderTest, MagnetometerDateAndDipoles) {
  const std::string path = write("s.yaml", R"(world:
  date: "2027-07-02"
  magnetic_dipoles: [{position: [100, 0, -90], moment: [0, 5000, 0], radius: 5}]
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - name: mag
        type: magnetometer
        rate_hz: 20
        noise_stddev_nt: 40
        resolution_nt: 5
        range_ut: 800
        hard_iron: [{position: [-0.7, 0, 0], moment: [0.1, 0, 0]}]
        soft_iron: [1.02, 0.01, 0, 0.01, 0.98, 0, 0, 0, 1]
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  EXPECT_DOUBLE_EQ(result.model->world.start_decimal_year, sensors::decimal_year_from_date(2027, 7, 2));
  ASSERT_EQ(result.model->world.magnetic_dipoles_W.size(), 1u);
  EXPECT_EQ(result.model->world.magnetic_dipoles_W[0].radius_m, 5.0);
  const sensors::MagnetometerParams& p = spec_of<sensors::MagnetometerSensor>(result.model->vehicles[0].sensors[0]).params;
  EXPECT_TRUE(p.dipoles_W.empty());  // the world's dipoles stay the world's
  ASSERT_EQ(p.dipoles_B.size(), 1u);
  EXPECT_EQ(p.dipoles_B[0].p_FD, Eigen::Vector3d(-0.7, 0, 0));
  EXPECT_EQ(p.soft_iron_S(0, 1), 0.01);
  EXPECT_DOUBLE_EQ(p.noise.axes[0].white_noise_density, 40e-9 / std::sqrt(20.0));
  EXPECT_DOUBLE_EQ(p.noise.lsb, 5e-9);
  EXPECT_DOUBLE_EQ(p.noise.max, 800e-6);
}

TEST_F(ScenarioLoaderTest, WorldDateErrors) {
  const std::string bad_form = write("a.yaml", "world: {date: 2026-13-01}\nvehicles: []\n");
  const std::string out_of_model = write("b.yaml", "world: {date: \"2031-01-01\"}\nvehicles: []\n");
  const std::vector<std::string> a = errors_of(bad_form), b = errors_of(out_of_model);
  ASSERT_FALSE(a.empty());
  EXPECT_NE(a[0].find(":1:15: error: world.date: expected a date YYYY-MM-DD (got '2026-13-01')"), std::string::npos)
      << a[0];
  ASSERT_FALSE(b.empty());
  EXPECT_NE(b[0].find(":1:15: error: world.date: must be within 2025-01-01 .. 2029-12-31, the World Magnetic "
                      "Model 2025's validity (got 2031-01-01)"),
            std::string::npos) << b[0];
}

TEST_F(ScenarioLoaderTest, FluidKeysArePerModel) {
  const std::string surface = write("surface.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle +
                                                        R"(    fluid:
      model: surface
      linear_damping: [1, 1, 1, 1, 1, 1]
      hydrodynamics: {drag: -1, magnus: -0.5}
)");
  EXPECT_EQ(errors_of(surface),
            (Lines{surface + ":18:14: error: vehicles[0].fluid.model: fluid model 'surface' needs a hydrodynamic "
                             "mesh: no link has a 'mesh' or 'collisions'",
                   surface + ":19:7: error: vehicles[0].fluid.linear_damping: key 'linear_damping' is not used "
                             "by fluid model 'surface'",
                   surface + ":20:29: error: vehicles[0].fluid.hydrodynamics.drag: must be >= 0 (got -1)",
                   surface + ":20:41: error: vehicles[0].fluid.hydrodynamics.magnus: must be >= 0 (got -0.5)"}));
  const std::string lumped = write("lumped.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle +
                                                      R"(    fluid:
      quadratic_damping: [1, 1, 1, 1, 1, 1]
      hydrodynamics: {drag: 1}
)");
  EXPECT_EQ(errors_of(lumped),
            (Lines{lumped + ":19:7: error: vehicles[0].fluid.hydrodynamics: key 'hydrodynamics' is not used by "
                            "fluid model 'lumped' (the default for a vehicle without a mesh or collision shapes)"}));
}

TEST_F(ScenarioLoaderTest, WrongTypes) {
  const std::string path = write("s.yaml", R"(world:
  gravity: down
  seed: 1.5
  water: [1025]
vehicles:
  - name: auv
    type: auv
    links: hull
    fluid:
      linear_damping: [1, 2, 3]
      quadratic_damping: [1, 2, 3, 4, 5, "6"]
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":2:12: error: world.gravity: expected a list of 3 numbers (got 'down')",
                   path + ":3:9: error: world.seed: expected a non-negative integer (got '1.5')",
                   path + ":4:10: error: world.water: expected a map (got a list of 1)",
                   path + ":8:12: error: vehicles[0].links: expected a list (got 'hull')",
                   path + ":10:23: error: vehicles[0].fluid.linear_damping: expected a list of 6 "
                          "numbers (got a list of 3)",
                   path + ":11:42: error: vehicles[0].fluid.quadratic_damping[5]: expected a number "
                          "(got the string \"6\")"}));
}

TEST_F(ScenarioLoaderTest, MissingRequiredKeysAreReportedAtTheMap) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - name: hull
        inertia: {ixx: 1, izz: 1}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":6:9: error: vehicles[0].links[0]: missing required key 'mass'",
                   path + ":7:18: error: vehicles[0].links[0].inertia: missing required key 'iyy'"}));
}

TEST_F(ScenarioLoaderTest, MissingTopLevelSections) {
  const std::string path = write("s.yaml", "wrld: {}\n");
  EXPECT_EQ(errors_of(path), (Lines{path + ":1:1: error: wrld: unknown key 'wrld'; did you mean 'world'?",
                                    path + ":1:1: error: missing required key 'world'",
                                    path + ":1:1: error: missing required key 'vehicles'"}));
}

TEST_F(ScenarioLoaderTest, OutOfRangeValues) {
  const std::string path = write("s.yaml", R"(world:
  physics_rate_hz: 20
  water: {density: 0}
  origin: {latitude_deg: 91}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    thrusters:
      - {name: main, link: hull, position: [0, 0, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
         thrust_coefficient: 0.4, max_rpm: -5}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":2:20: error: world.physics_rate_hz: must be in [50, 100000] (got 20)",
                   path + ":3:20: error: world.water.density: must be in (0, 2000] (got 0)",
                   path + ":4:26: error: world.origin.latitude_deg: must be in [-90, 90] (got 91)",
                   path + ":9:28: error: vehicles[0].links[0].mass: must be > 0 (got 0)",
                   path + ":12:44: error: vehicles[0].thrusters[0].max_rpm: must be > 0 (got -5)"}));
}

TEST_F(ScenarioLoaderTest, WaterDefaults) {
  const std::string path = write("s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const WaterSpec& water = result.model->world.water;
  EXPECT_EQ(water.density_model, DensityModel::kConstant);
  EXPECT_EQ(water.density, 1025.0);
  EXPECT_EQ(water.temperature, 4.0);
  EXPECT_EQ(water.salinity, 35.0);
  EXPECT_EQ(water.atmospheric_pressure, 101325.0);
  EXPECT_EQ(water.bulk_modulus, 2.2e9);
  EXPECT_EQ(water.rho0, 1025.0);
  EXPECT_EQ(water.pycnocline_depth, 1000.0);
  EXPECT_EQ(water.pycnocline_density_increase, 3.075);
  EXPECT_TRUE(water.ctd.empty());
  EXPECT_EQ(water.current.uniform_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(water.current.gauss_markov_sigma_W, Eigen::Vector3d::Zero());
}

TEST_F(ScenarioLoaderTest, WaterRampAndCurrentLoad) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water:
    surface_z: 2
    density_model: ramp
    rho0: 1024
    pycnocline_depth: 800
    pycnocline_density_increase: 4
    temperature_degc: 3.5
    salinity: 34.5
    atmospheric_pressure: 100000
    bulk_modulus: 2.3e9
    current:
      uniform: [0.1, 0.2, 0]
      shear: {surface: [0.3, 0, 0], decay_depth: 25}
      gauss_markov: {sigma: [0.01, 0.02, 0], time_constant_s: 300}
vehicles:)") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const WaterSpec& water = result.model->world.water;
  EXPECT_EQ(water.surface_z, 2.0);
  EXPECT_EQ(water.density_model, DensityModel::kRamp);
  EXPECT_EQ(water.rho0, 1024.0);
  EXPECT_EQ(water.density, 1024.0);  // the lumped model sees the surface density
  EXPECT_EQ(water.pycnocline_depth, 800.0);
  EXPECT_EQ(water.pycnocline_density_increase, 4.0);
  EXPECT_EQ(water.temperature, 3.5);
  EXPECT_EQ(water.salinity, 34.5);
  EXPECT_EQ(water.atmospheric_pressure, 100000.0);
  EXPECT_EQ(water.bulk_modulus, 2.3e9);
  EXPECT_EQ(water.current.uniform_W, Eigen::Vector3d(0.1, 0.2, 0.0));
  EXPECT_EQ(water.current.shear_surface_W, Eigen::Vector3d(0.3, 0.0, 0.0));
  EXPECT_EQ(water.current.shear_decay_depth, 25.0);
  EXPECT_EQ(water.current.gauss_markov_sigma_W, Eigen::Vector3d(0.01, 0.02, 0.0));
  EXPECT_EQ(water.current.gauss_markov_time_constant, 300.0);
}

TEST_F(ScenarioLoaderTest, SoilPresetOverridesAndSeabedContact) {
  // No soil block: the deep-sea ooze preset; a vehicle meets the seabed rigidly unless it says soil.
  const auto plain = load_scenario_file(write("plain.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle));
  ASSERT_TRUE(plain.model) << plain.errors.front().format();
  EXPECT_EQ(plain.model->world.soil.preset, "deep_sea_ooze");
  EXPECT_EQ(plain.model->world.soil.parameters.k_phi, physics::find_soil_preset("deep_sea_ooze")->soil.k_phi);
  EXPECT_EQ(plain.model->vehicles[0].seabed_contact, SeabedContact::kRigid);

  const std::string path = write("s.yaml", R"(world:
  soil:
    preset: dry_sand
    cohesion: 1500
    friction_angle_deg: 30
    damping: 5000
vehicles:
  - name: crawler
    type: crawler
    seabed_contact: soil
    links:
      - name: body
        mass: 300.0
        inertia: {ixx: 50, iyy: 80, izz: 100}
        collisions: [{shape: box, size: [2.0, 1.2, 0.6]}]
)");
  const auto result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << result.errors.front().format();
  const SoilSpec& soil = result.model->world.soil;
  const physics::SoilParameters& sand = physics::find_soil_preset("dry_sand")->soil;
  EXPECT_EQ(soil.preset, "dry_sand");
  EXPECT_EQ(soil.parameters.sinkage_exponent, sand.sinkage_exponent);
  EXPECT_EQ(soil.parameters.k_c, sand.k_c);
  EXPECT_EQ(soil.parameters.k_phi, sand.k_phi);
  EXPECT_EQ(soil.parameters.cohesion, 1500.0);
  EXPECT_NEAR(soil.parameters.friction_angle, 30.0 * kDegToRad, kTol);
  EXPECT_EQ(soil.parameters.shear_deformation_modulus, sand.shear_deformation_modulus);
  EXPECT_EQ(soil.parameters.damping, 5000.0);
  EXPECT_EQ(result.model->vehicles[0].seabed_contact, SeabedContact::kSoil);
}

TEST_F(ScenarioLoaderTest, SoilErrors) {
  const std::string path = write("s.yaml", R"(world:
  soil:
    preset: quicksand
    sinkage_exponent: 0
    k_c: 0
    k_phi: 0
    friction_angle_deg: 75
    shear_deformation_modulus: -0.01
    porosity: 0.4
vehicles:
  - name: crawler
    type: crawler
    seabed_contact: sticky
    links:
      - name: body
        mass: 300.0
        inertia: {ixx: 50, iyy: 80, izz: 100}
  - name: sled
    type: crawler
    seabed_contact: soil
    links:
      - name: body
        mass: 300.0
        inertia: {ixx: 50, iyy: 80, izz: 100}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":3:13: error: world.soil.preset: unknown soil preset 'quicksand' (one of " +
                       physics::soil_preset_names() + ")",
                   path + ":4:23: error: world.soil.sinkage_exponent: must be in (0, 3] (got 0)",
                   path + ":6:5: error: world.soil.k_phi: k_c and k_phi are both 0: the soil would bear nothing",
                   path + ":7:25: error: world.soil.friction_angle_deg: must be in [0, 60] (got 75)",
                   path + ":8:32: error: world.soil.shear_deformation_modulus: must be in (0, 1] (got -0.01)",
                   path + ":9:5: error: world.soil.porosity: unknown key 'porosity'",
                   path + ":13:21: error: vehicles[0].seabed_contact: must be one of 'rigid', 'soil' (got 'sticky')",
                   path + ":20:5: error: vehicles[1].seabed_contact: soil contact presses on the vehicle's "
                          "surface, and no link has a mesh or collision shapes"}));
}

// world.soil.regions placed by world.soil.map: an 8-bit image of region numbers next to the scenario.
// A schedule keyframe is a control vector: each actuator's own check applies at load (a drop weight's
// command is 0 or 1), as for a client's command at run time; a fin turned beyond its stall is a warning.
TEST_F(ScenarioLoaderTest, ScheduleKeyframesPassEachActuatorsCheck) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: lander
    type: lander
    links:
      - name: frame
        mass: 100.0
        inertia: {ixx: 10, iyy: 10, izz: 10}
        collisions: [{shape: box, size: [1, 1, 1]}]
    fins:
      - {name: tail, link: frame, position: [-0.5, 0, 0], hinge_axis: [0, 1, 0], area: 0.02, aspect_ratio: 2,
         max_angle_deg: 35}
    drop_weights:
      - {name: weight, link: frame, position: [0, 0, -0.5], mass: 20}
    schedule:
      - {time_s: 0.0, setpoints: [0.5, 0.0]}
      - {time_s: 5.0, setpoints: [0.0, 0.5]}
      - {time_s: 6.0, setpoints: [0.0]}
)");
  const LoadResult result = load_scenario_file(path);
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":17:34: error: vehicles[0].schedule[1].setpoints: setpoint[1] = 0.5 is not 0 (hold) or "
                          "1 (release) (weight)",
                   path + ":18:34: error: vehicles[0].schedule[2].setpoints: expected 2 setpoints, one per actuator "
                          "(tail, weight) (got 1)"}));
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0].format(),
            path + ":11:9: warning: vehicles[0].fins[0]: max_angle_deg 35 is beyond stall_angle_deg 30: full "
                   "deflection stalls the fin and gives less lift than a smaller one");
}

TEST_F(ScenarioLoaderTest, SoilRegionsByMap) {
  // 2 x 3 pixels, 5 m each, centred on (10, 0): row 0 (north) is [0, 1, 2], row 1 [2, 2, 0].
  cv::Mat image(2, 3, CV_8UC1, cv::Scalar(0));
  image.at<std::uint8_t>(0, 1) = 1;
  image.at<std::uint8_t>(0, 2) = 2;
  image.at<std::uint8_t>(1, 0) = 2;
  image.at<std::uint8_t>(1, 1) = 2;
  fs::create_directories(dir_ / "maps");
  ASSERT_TRUE(cv::imwrite((dir_ / "maps" / "soil.png").string(), image));
  const std::string path = write("scenarios/s.yaml", std::string(R"(world:
  soil:
    preset: deep_sea_ooze
    regions:
      - {preset: dry_sand}
      - {preset: clayey_soil, cohesion: 5000}
    map: {file: ../maps/soil.png, meters_per_pixel: 5, center: [10, 0]}
vehicles:)") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(result.ok());
  const SoilSpec& soil = result.model->world.soil;
  ASSERT_EQ(soil.regions.size(), 2u);
  EXPECT_EQ(soil.regions[0].preset, "dry_sand");
  EXPECT_EQ(soil.regions[1].parameters.cohesion, 5000.0);
  EXPECT_EQ(soil.regions[1].parameters.k_phi, physics::find_soil_preset("clayey_soil")->soil.k_phi);
  ASSERT_NE(soil.map, nullptr);
  const physics::SoilLayout layout = soil.layout();
  ASSERT_EQ(layout.soils.size(), 3u);
  // Cells: x in [-5, 0), [0, 5), [5, 10) ... from the west edge at 10 - 7.5 = 2.5; y north half [0, 5).
  EXPECT_EQ(layout.region_at(3.0, 2.0), 0u);    // row 0, column 0
  EXPECT_EQ(layout.region_at(9.0, 2.0), 1u);    // row 0, column 1
  EXPECT_EQ(layout.region_at(16.0, 4.9), 2u);   // row 0, column 2
  EXPECT_EQ(layout.region_at(3.0, -2.0), 2u);   // row 1, column 0
  EXPECT_EQ(layout.region_at(16.0, -2.0), 0u);  // row 1, column 2
  EXPECT_EQ(layout.region_at(2.4, 0.0), 0u);    // off the map: the world's soil
  EXPECT_EQ(layout.region_at(9.0, 5.1), 0u);
}

TEST_F(ScenarioLoaderTest, SoilMapErrors) {
  cv::Mat image(2, 2, CV_8UC1, cv::Scalar(0));
  image.at<std::uint8_t>(1, 0) = 3;
  ASSERT_TRUE(cv::imwrite((dir_ / "three.png").string(), image));
  ASSERT_TRUE(cv::imwrite((dir_ / "colour.png").string(), cv::Mat(2, 2, CV_8UC3, cv::Scalar(0, 0, 0))));
  const std::string beyond = write("a.yaml", std::string(R"(world:
  soil:
    regions: [{preset: dry_sand}, {preset: lunar_soil}]
    map: {file: three.png, meters_per_pixel: 1}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(beyond),
            (Lines{beyond + ":4:17: error: world.soil.map.file: " + (dir_ / "three.png").string() +
                   ": pixel (row 1, column 0) names region 3, but there are 2 regions (0 is the world's soil)"}));
  const std::string colour = write("b.yaml", std::string(R"(world:
  soil:
    regions: [{preset: dry_sand}]
    map: {file: colour.png, meters_per_pixel: 0}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(colour),
            (Lines{colour + ":4:47: error: world.soil.map.meters_per_pixel: must be in (0, 1000000] (got 0)"}));
  const std::string colour2 = write("c.yaml", std::string(R"(world:
  soil:
    regions: [{preset: dry_sand}]
    map: {file: colour.png, meters_per_pixel: 2}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(colour2),
            (Lines{colour2 + ":4:17: error: world.soil.map.file: " + (dir_ / "colour.png").string() +
                   ": a soil map is an 8-bit single-channel image of region numbers (this one has 3 channel(s) of "
                   "8 bits)"}));
  const std::string unplaced = write("d.yaml", std::string(R"(world:
  soil:
    regions: [{preset: dry_sand, porosity: 1}, {preset: basalt}]
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(unplaced),
            (Lines{unplaced + ":3:5: error: world.soil.regions: regions need a `map` that says where each one is",
                   unplaced + ":3:34: error: world.soil.regions[0].porosity: unknown key 'porosity'",
                   unplaced + ":3:57: error: world.soil.regions[1].preset: unknown soil preset 'basalt' (one of " +
                       physics::soil_preset_names() + ")"}));
  const std::string no_regions = write("e.yaml", std::string(R"(world:
  soil:
    map: {file: three.png, meters_per_pixel: 1}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(no_regions),
            (Lines{no_regions + ":3:5: error: world.soil.map: a soil map places `regions`, and there are none"}));
}

TEST_F(ScenarioLoaderTest, WaterCtdLoads) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water:
    density_model: ctd
    ctd:
      - {depth: 0, temperature_degc: 20, salinity: 35}
      - {depth: 1000, temperature_degc: 4, salinity: 34.6}
vehicles:)") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const WaterSpec& water = result.model->world.water;
  EXPECT_EQ(water.density_model, DensityModel::kCtd);
  ASSERT_EQ(water.ctd.size(), 2u);
  EXPECT_EQ(water.ctd[1].depth, 1000.0);
  EXPECT_EQ(water.ctd[1].temperature, 4.0);
  EXPECT_EQ(water.ctd[1].salinity, 34.6);
  // EOS-80 at S = 35, T68 = 20.0048 degC, p = 0: 1024.76 kg/m^3 (UNESCO 1983 tables, T = 20: 1024.763).
  EXPECT_NEAR(water.density, 1024.76, 0.01);
}

TEST_F(ScenarioLoaderTest, WaterErrors) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water:
    density_model: ramp
    density: 1030
    ctd: []
    rho0: 0
    current:
      shear: {surface: [1, 0, 0]}
      gauss_markov: {sigma: [0.1, -0.1, 0], time_constant_s: 0.5}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":4:5: error: world.water.density: key 'density' is not used by density_model 'ramp'",
                   path + ":5:5: error: world.water.ctd: key 'ctd' is not used by density_model 'ramp'",
                   path + ":6:11: error: world.water.rho0: must be in (0, 2000] (got 0)",
                   path + ":8:14: error: world.water.current.shear: missing required key 'decay_depth'",
                   path + ":9:35: error: world.water.current.gauss_markov.sigma[1]: must be >= 0 (got -0.1)",
                   path + ":9:62: error: world.water.current.gauss_markov.time_constant_s: must be in [1, "
                          "10000000] (got 0.5)"}));
}

TEST_F(ScenarioLoaderTest, WaterCtdErrors) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water:
    density_model: ctd
    temperature_degc: 4
    ctd:
      - {depth: 0, temperature_degc: 20, salinity: 35}
      - {depth: 500, temperature_degc: 41, salinity: 35}
      - {depth: 500, temperature_degc: 4, salinity: 43}
      - {temperature_degc: 2, salinity: 34}
  seed: 1
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":4:5: error: world.water.temperature_degc: key 'temperature_degc' is not used by "
                          "density_model 'ctd'",
                   path + ":7:40: error: world.water.ctd[1].temperature_degc: must be in [-2.5, 40] (got 41)",
                   path + ":8:17: error: world.water.ctd[2].depth: must be greater than the previous row's "
                          "depth (500)",
                   path + ":8:53: error: world.water.ctd[2].salinity: must be in [0, 42] (got 43)",
                   path + ":9:9: error: world.water.ctd[3]: missing required key 'depth'"}));
}

TEST_F(ScenarioLoaderTest, WaterCtdNeedsTwoRows) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water: {density_model: ctd, ctd: [{depth: 0, temperature_degc: 20, salinity: 35}]}
  origin: {altitude: 0}
vehicles:)") + kInlineVehicle);
  const std::string path2 = write("t.yaml", std::string(R"(world:
  water: {density_model: ctd, density_modle: 1}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(path), (Lines{path + ":2:36: error: world.water.ctd: needs at least 2 rows (got 1)"}));
  EXPECT_EQ(errors_of(path2),
            (Lines{path2 + ":2:10: error: world.water: missing required key 'ctd' (needed by density_model 'ctd')",
                   path2 + ":2:31: error: world.water.density_modle: unknown key 'density_modle'; did you mean "
                           "'density_model'?"}));
}

TEST_F(ScenarioLoaderTest, NonFiniteNumbers) {
  const std::string path = write("s.yaml", std::string(R"(world:
  gravity: [0, .nan, -.inf]
  seabed: {z: 1e999}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":2:16: error: world.gravity[1]: must be a finite number (got .nan)",
                   path + ":2:22: error: world.gravity[2]: must be a finite number (got -.inf)",
                   path + ":3:15: error: world.seabed.z: must be a finite number (got 1e999)"}));
}

TEST_F(ScenarioLoaderTest, DuplicateKeys) {
  const std::string path = write("s.yaml", std::string(R"(world:
  seed: 1
  frame_id: map
  seed: 2
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":4:3: error: world.seed: duplicate key 'seed' (first defined at line 2)"}));
}

TEST_F(ScenarioLoaderTest, DuplicateAndInvalidVehicleNames) {
  const std::string path = write(
      "s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + kInlineVehicle + R"(  - name: 2nd-auv
    include: x.yaml
)");
  write("x.yaml", "type: auv\nlinks: [{name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}]\n");
  EXPECT_EQ(
      errors_of(path),
      (Lines{path + ":18:11: error: vehicles[1].name: duplicate vehicle name 'auv' (first used by "
                    "vehicles[0])",
             path + ":32:11: error: vehicles[2].name: must match [A-Za-z][A-Za-z0-9_]* (got '2nd-auv')"}));
}

TEST_F(ScenarioLoaderTest, ThrusterOnMissingLink) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
      - {name: fin, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
    thrusters:
      - name: main
        link: nope
        position: [0, 0, 0]
        direction: [0, 0, 0]
        propeller_diameter: 0.1
        thrust_coefficient: 0.4
        max_rpm: 100
        handedness: clockwise
)");
  EXPECT_EQ(
      errors_of(path),
      (Lines{path + ":10:15: error: vehicles[0].thrusters[0].link: no link named 'nope' in this vehicle "
                    "(links: hull, fin)",
             path + ":12:20: error: vehicles[0].thrusters[0].direction: must be non-zero (got [0, 0, 0])",
             path + ":16:21: error: vehicles[0].thrusters[0].handedness: must be one of 'right', 'left' (got "
                    "'clockwise')"}));
}

TEST_F(ScenarioLoaderTest, DuplicateLinkAndThrusterNames) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
      - {name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
    thrusters:
      - {name: t, link: hull, position: [0, 0, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
         thrust_coefficient: 0.4, max_rpm: 100}
      - {name: t, link: hull, position: [0, 0, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
         thrust_coefficient: 0.4, max_rpm: 100}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":7:16: error: vehicles[0].links[1].name: duplicate link name 'hull' (first "
                          "used by vehicles[0].links[0])",
                   path + ":11:16: error: vehicles[0].thrusters[1].name: duplicate thruster name 't' "
                          "(first used by vehicles[0].thrusters[0])"}));
}

TEST_F(ScenarioLoaderTest, OneMistakeGivesOneError) {
  const std::string path = write("s.yaml", R"(world: {physics_rate_hz: 1}
vehicles:
  - name: a
    odometry_rate_hz: 1000
    type: auv
    links:
      - {nmae: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
    thrusters:
      - {name: t, link: hull, position: [0, 0, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
         thrust_coefficient: 0.4, max_rpm: 100}
  - name: b
    type: auv
    links: [{name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}]
    thrusters: {name: t}
    schedule: [{time_s: 0, setpoints: [1, 1]}]
)");
  // Not reported: rates against an invalid physics rate, a thruster naming the link whose name is
  // misspelt, setpoint counts of a vehicle whose thruster list is unusable.
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":1:26: error: world.physics_rate_hz: must be in [50, 100000] (got 1)",
                   path + ":7:9: error: vehicles[0].links[0]: missing required key 'name'",
                   path + ":7:10: error: vehicles[0].links[0].nmae: unknown key 'nmae'; did you mean 'name'?",
                   path + ":14:16: error: vehicles[1].thrusters: expected a list (got a map)"}));
}

TEST_F(ScenarioLoaderTest, IncludeFileMissing) {
  const std::string path = write("scenarios/s.yaml", R"(world: {}
vehicles:
  - name: auv
    include: ../vehicles/nope.yaml
    schedule:
      - {time_s: 0, setpoints: [1, 1]}
)");
  // The setpoint count cannot be checked without the vehicle: no further error.
  EXPECT_EQ(errors_of(path), (Lines{path + ":4:14: error: vehicles[0].include: cannot open '" +
                                    dir_.string() + "/scenarios/../vehicles/nope.yaml' (file not found)"}));
}

// An entry with `include` may add sensors and lights to the included definition; their names must not
// repeat the included ones, and their links are the included vehicle's.
TEST_F(ScenarioLoaderTest, IncludedVehicleExtendedWithSensorsAndLights) {
  write("v.yaml", R"(type: auv
links:
  - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
sensors:
  - {name: depth, type: pressure}
)");
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: a
    include: v.yaml
    sensors:
      - {name: cam, type: camera, link: hull}
    lights:
      - {name: lamp, link: hull}
  - name: b
    include: v.yaml
    sensors:
      - {name: depth, type: pressure, link: mast}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":12:16: error: vehicles[1].sensors[0].name: duplicate sensor name 'depth' (first used by " +
                       dir_.string() + "/v.yaml)",
                   path + ":12:45: error: vehicles[1].sensors[0].link: no link named 'mast' in this vehicle (links: "
                          "hull)"}));
  const std::string good = write("good.yaml", R"(world: {}
vehicles:
  - name: a
    include: v.yaml
    sensors:
      - {name: cam, type: camera, link: hull}
    lights:
      - {name: lamp, link: hull}
  - name: b
    include: v.yaml
)");
  const LoadResult loaded = load_scenario_file(good);
  ASSERT_TRUE(loaded.model) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  ASSERT_EQ(loaded.model->vehicles[0].sensors.size(), 2u);
  EXPECT_EQ(loaded.model->vehicles[0].sensors[1].name, "cam");
  EXPECT_EQ(loaded.model->vehicles[0].lights.size(), 1u);
  EXPECT_EQ(loaded.model->vehicles[1].sensors.size(), 1u);  // the include itself is unchanged
  EXPECT_TRUE(loaded.model->vehicles[1].lights.empty());
}

TEST_F(ScenarioLoaderTest, IncludeAndInlineDefinitionBothOrNeither) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: a
    include: v.yaml
    type: auv
    fluid: {}
  - name: b
    odometry_rate_hz: 10
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":4:5: error: vehicles[0].include: cannot be combined with an inline definition "
                          "(found 'type', 'fluid'; an entry with 'include' may only add 'sensors' and 'lights')",
                   path + ":7:5: error: vehicles[1]: needs either 'include' or an inline definition ('type', "
                          "'links', ...)"}));
}

TEST_F(ScenarioLoaderTest, ScheduleSetpointCountUsesTheIncludedVehicle) {
  write("vehicles/v.yaml", R"(type: auv
links: [{name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}]
thrusters:
  - {name: left, link: hull, position: [0, 1, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
     thrust_coefficient: 0.4, max_rpm: 100}
  - {name: right, link: hull, position: [0, -1, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
     thrust_coefficient: 0.4, max_rpm: 100}
)");
  const std::string path = write("scenarios/s.yaml", R"(world: {}
vehicles:
  - name: auv
    include: ../vehicles/v.yaml
    schedule:
      - {time_s: 0, setpoints: [0.5, 0.5]}
      - {time_s: 10, setpoints: [0.5]}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":7:33: error: vehicles[0].schedule[1].setpoints: expected 2 setpoints, one "
                          "per actuator (left, right) (got 1)"}));
}

TEST_F(ScenarioLoaderTest, ScheduleTimesMustIncreaseAndSetpointsStayInRange) {
  const std::string path =
      write("s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + R"(    schedule:
      - {time_s: 0, setpoints: [0.5]}
      - {time_s: 10, setpoints: [1.5]}
      - {time_s: 10, setpoints: [-1]}
      - {time_s: -1, setpoints: [0]}
      - {setpoints: [0]}
)");
  EXPECT_EQ(
      errors_of(path),
      (Lines{path + ":19:34: error: vehicles[0].schedule[1].setpoints[0]: must be in [-1, 1] (got 1.5)",
             path + ":20:18: error: vehicles[0].schedule[2].time_s: must be greater than the previous time_s "
                    "(10) (got 10)",
             path + ":21:18: error: vehicles[0].schedule[3].time_s: must be >= 0 (got -1)",
             path + ":22:9: error: vehicles[0].schedule[4]: missing required key 'time_s'"}));
}

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

TEST_F(ScenarioLoaderTest, YamlSyntaxError) {
  const std::string path = write("s.yaml", R"(world:
  seed: 1
   frame_id: map
vehicles: []
)");
  EXPECT_EQ(errors_of(path), (Lines{path + ":3:12: error: yaml: illegal map value"}));
}

TEST_F(ScenarioLoaderTest, ErrorsInsideAnIncludedFileNameThatFile) {
  const std::string vehicle = write("vehicles/v.yaml", R"(type: auv
links:
  - name: hull
    mass: 1
    inertia: {ixx: 1, iyy: 1, izz: 1}
thrusters:
  - name: main
    link: hull
    position: [0, 0, 0]
    direction: [1, 0, 0]
    propeller_diameter: 0.1
    thrust_coefficient: 0.4
    max_rpm: -5
    colour: red
)");
  // Two vehicles include the same file: its errors are reported once.
  const std::string path = write("scenarios/s.yaml", R"(world: {}
vehicles:
  - {name: a, include: ../vehicles/v.yaml}
  - {name: b, include: ../vehicles/v.yaml, odometry_rate_hz: 0}
)");
  const std::string included = dir_.string() + "/scenarios/../vehicles/v.yaml";
  EXPECT_EQ(errors_of(path), (Lines{path + ":4:62: error: vehicles[1].odometry_rate_hz: must be > 0 (got 0)",
                                    included + ":13:14: error: thrusters[0].max_rpm: must be > 0 (got -5)",
                                    included + ":14:5: error: thrusters[0].colour: unknown key 'colour'"}));
}

TEST_F(ScenarioLoaderTest, SyntaxErrorInsideAnIncludedFile) {
  write("v.yaml", "type: auv\nlinks: [\n");
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - {name: a, include: v.yaml, schedule: [{time_s: 0, setpoints: [1]}]}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{dir_.string() + "/v.yaml:3:1: error: yaml: end of sequence flow not found"}));
}

TEST_F(ScenarioLoaderTest, RatesAboveThePhysicsRate) {
  const std::string path = write("s.yaml", std::string(R"(world:
  physics_rate_hz: 100
  clock_rate_hz: 200
vehicles:)") + kInlineVehicle + "    thruster_state_rate_hz: 1000\n");
  EXPECT_EQ(
      errors_of(path),
      (Lines{path + ":3:18: error: world.clock_rate_hz: must be <= world.physics_rate_hz (100) (got 200)",
             path + ":19:29: error: vehicles[0].thruster_state_rate_hz: must be <= world.physics_rate_hz "
                    "(100) (got 1000)"}));
}

TEST_F(ScenarioLoaderTest, SeveralErrorsInOneFileAreAllReportedInOrder) {
  const std::string path = write("s.yaml", R"(vehicles:
  - name: auv
    type: submarine
    links:
      - name: hull
        mass: heavy
        inertia: {ixx: 1, iyy: 1, izz: 1}
        buoyancy: {volume: -0.1, centre: [0, 0, 0]}
    command_timeout_s: 0
world:
  seed: -1
  frame_id: ""
  seabed: {type: mesh}
)");
  EXPECT_EQ(
      errors_of(path),
      (Lines{path +
                 ":3:11: error: vehicles[0].type: must be one of 'auv', 'rov', 'lander', 'surface_vessel', "
                 "'glider', 'crawler' (got 'submarine')",
             path + ":6:15: error: vehicles[0].links[0].mass: expected a number (got 'heavy')",
             path + ":8:28: error: vehicles[0].links[0].buoyancy.volume: must be >= 0 (got -0.1)",
             path + ":8:34: error: vehicles[0].links[0].buoyancy.centre: unknown key 'centre'; did you mean "
                    "'center'?",
             path + ":9:24: error: vehicles[0].command_timeout_s: must be > 0 (got 0)",
             path + ":11:9: error: world.seed: expected a non-negative integer (got '-1')",
             path + ":12:13: error: world.frame_id: must not be empty",
             path + ":13:11: error: world.seabed: missing required key 'file' (needed by seabed type 'mesh')"}));
}

TEST_F(ScenarioLoaderTest, SeabedTypesBuildTheirSurface) {
  // A 3 x 2 pixel 16-bit heightmap next to the scenario; 2 m per pixel.
  cv::Mat image(2, 3, CV_16UC1, cv::Scalar(0));
  image.at<std::uint16_t>(0, 2) = 65535;
  fs::create_directories(dir_ / "maps");
  ASSERT_TRUE(cv::imwrite((dir_ / "maps" / "h.png").string(), image));
  const std::string heightmap = write("scenarios/h.yaml", std::string(R"(world:
  seabed: {type: heightmap, file: ../maps/h.png, meters_per_pixel: 2, height_range: [-120, -100]}
vehicles:)") + kInlineVehicle);
  const LoadResult h = load_scenario_file(heightmap);
  for (const Diagnostic& d : h.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(h.ok());
  const SeabedSpec& seabed = h.model->world.seabed;
  ASSERT_NE(seabed.mesh, nullptr);
  EXPECT_EQ(seabed.mesh->num_vertices(), 6u);
  EXPECT_EQ(seabed.mesh->num_triangles(), 4u);
  EXPECT_EQ(seabed.heightmap.height_min, -120.0);
  // Pixel (row 0, col 2) is the north-east corner: x = +2, y = +1, z = height_max.
  EXPECT_EQ(seabed.mesh->positions[3 * 5 + 0], 2.0f);
  EXPECT_EQ(seabed.mesh->positions[3 * 5 + 1], 1.0f);
  EXPECT_EQ(seabed.mesh->positions[3 * 5 + 2], -100.0f);

  const std::string procedural = write("p.yaml", std::string(R"(world:
  seed: 5
  seabed: {type: procedural, z: -80, size: [100, 50], resolution: 5, seed: 9}
vehicles:)") + kInlineVehicle);
  const LoadResult p = load_scenario_file(procedural);
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p.model->world.seabed.procedural.seed, 9u);  // its own seed wins over world.seed
  EXPECT_EQ(p.model->world.seabed.procedural.z_datum, -80.0);
  EXPECT_EQ(p.model->world.seabed.mesh->num_triangles(), 20u * 10u * 2u);

  const std::string plane = write("q.yaml", std::string("world: {seabed: {z: -30}}\nvehicles:") + kInlineVehicle);
  const LoadResult q = load_scenario_file(plane);
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(q.model->world.seabed.mesh, nullptr);  // a plane needs no mesh
}

TEST_F(ScenarioLoaderTest, SeabedKeysAndFilesAreChecked) {
  const std::string keys = write("k.yaml", R"(world:
  seabed:
    type: procedural
    file: x.png
    size: [0, 10]
    slope_deg: 60
vehicles: [])");
  const std::vector<std::string> key_errors = errors_of(keys);
  ASSERT_GE(key_errors.size(), 3u);
  EXPECT_EQ(key_errors[0], keys + ":4:5: error: world.seabed.file: key 'file' is not used by seabed type 'procedural'");
  EXPECT_EQ(key_errors[1], keys + ":5:12: error: world.seabed.size[0]: must be in (0, 100000] (got 0)");
  EXPECT_EQ(key_errors[2], keys + ":6:16: error: world.seabed.slope_deg: must be in [0, 60) (got 60)");

  const std::string range = write("r.yaml", R"(world:
  seabed: {type: heightmap, file: h.png, meters_per_pixel: 1, height_range: [0, -5]}
vehicles: [])");
  EXPECT_EQ(errors_of(range)[0],
            range + ":2:77: error: world.seabed.height_range: must be [min, max] with max > min (got [0, -5])");

  const std::string missing = write("m.yaml", R"(world:
  seabed: {type: heightmap, file: nowhere.png, meters_per_pixel: 1, height_range: [-5, 0]}
vehicles: [])");
  EXPECT_EQ(errors_of(missing)[0], missing + ":2:35: error: world.seabed.file: " + (dir_ / "nowhere.png").string() +
                                       ": cannot open heightmap (file not found)");

  const std::string mesh = write("n.yaml", R"(world:
  seabed: {type: mesh, file: nowhere.glb, scale: 0.001, up_axis: y}
vehicles: [])");
  const std::vector<std::string> mesh_errors = errors_of(mesh);
  ASSERT_FALSE(mesh_errors.empty());
  // The importer's message names the file; the loader places it at the file key's value.
  EXPECT_EQ(mesh_errors[0].rfind(mesh + ":2:30: error: world.seabed.file: " + (dir_ / "nowhere.glb").string() + ": ", 0),
            0u)
      << mesh_errors[0];

  const std::string huge = write("g.yaml", R"(world:
  seabed: {type: procedural, size: [100000, 100000], resolution: 1}
vehicles: [])");
  EXPECT_EQ(errors_of(huge)[0], huge + ":2:11: error: world.seabed: size / resolution gives 1.00002e+10 height "
                                       "samples; at most 16777216 are allowed");
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

TEST_F(ScenarioLoaderTest, RaycastThreadsIsAWholeNumberInRange) {
  const std::string good = write("g.yaml", std::string("world: {raycast_threads: 3}\nvehicles:") + kInlineVehicle);
  const LoadResult g = load_scenario_file(good);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(g.model->world.raycast_threads, 3);
  EXPECT_EQ(g.model->world.threads, 0);  // default: one per hardware thread
  EXPECT_GE(g.model->world.effective_threads(), 1);
  const std::string one = write("one.yaml", std::string("world: {threads: 1}\nvehicles:") + kInlineVehicle);
  EXPECT_EQ(load_scenario_file(one).model->world.threads, 1);
  EXPECT_EQ(load_scenario_file(one).model->world.effective_threads(), 1);
  const std::string many = write("many.yaml", "world:\n  threads: 300\nvehicles: []\n");
  EXPECT_EQ(errors_of(many)[0], many + ":2:12: error: world.threads: must be in [0, 256] (got 300)");
  const std::string bad = write("b.yaml", "world:\n  raycast_threads: 1.5\nvehicles: []\n");
  EXPECT_EQ(errors_of(bad)[0], bad + ":2:20: error: world.raycast_threads: must be a whole number (got 1.5)");
  const std::string negative = write("n.yaml", "world:\n  raycast_threads: -1\nvehicles: []\n");
  EXPECT_EQ(errors_of(negative)[0], negative + ":2:20: error: world.raycast_threads: must be in [0, 256] (got -1)");
}

// Files a scenario may reach (docs/ARCHITECTURE.md): only inside its tree, hadal's configs and the configured
// asset roots, symlinks resolved; what an error says never repeats a file that is not YAML.
TEST_F(ScenarioLoaderTest, FilesOutsideTheScenariosTreeAreRefusedByName) {
  const std::string tree = fs::canonical(dir_ / "").string();
  write("v.yaml", "type: auv\nlinks:\n  - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}\n");
  const std::string roots = " lies outside the directories a scenario may name files in (";
  const std::string configs = fs::canonical(HADAL_SOURCE_DIR "/configs").string();
  // /etc/passwd: refused before it is read; nothing of it is quoted.
  const std::string passwd = write("a/p.yaml", "world: {}\nvehicles:\n  - {name: x, include: /etc/passwd}\n");
  EXPECT_EQ(errors_of(passwd),
            (Lines{passwd + ":3:24: error: vehicles[0].include: '/etc/passwd'" + roots + tree + "/a, " + configs +
                   "; symlinks resolved); hadald --asset-root DIR or $HADAL_ASSET_ROOTS adds one"}));
  // A '..' out of the tree (a/ holds the scenario; its tree is a/).
  const std::string up = write("a/u.yaml", "world: {}\nvehicles:\n  - {name: x, include: ../v.yaml}\n");
  const auto up_errors = errors_of(up);
  ASSERT_EQ(up_errors.size(), 1u);
  EXPECT_NE(up_errors[0].find(up + ":3:24: error: vehicles[0].include: '../v.yaml'" + roots), std::string::npos)
      << up_errors[0];
  // ... which an asset root allows, from the command line or the environment.
  LoadOptions options;
  options.asset_roots = {dir_.string()};
  const LoadResult allowed = load_scenario_file(up, options);
  for (const Diagnostic& d : allowed.errors) ADD_FAILURE() << d.format();
  EXPECT_TRUE(allowed.ok());
  ::setenv("HADAL_ASSET_ROOTS", ("/nonexistent-hadal-root:" + dir_.string()).c_str(), 1);
  const LoadResult from_env = load_scenario_file(up);
  ::unsetenv("HADAL_ASSET_ROOTS");
  EXPECT_EQ(from_env.errors.size(), 1u);
  ASSERT_FALSE(from_env.errors.empty());
  EXPECT_EQ(from_env.errors[0].format(),
            up + ": error: asset root '/nonexistent-hadal-root' ($HADAL_ASSET_ROOTS) is not a directory");
  // A symlink inside the tree to a file outside it is outside; meshes and maps are held to the same.
  fs::create_symlink(dir_ / "v.yaml", dir_ / "a" / "link.yaml");
  const std::string link = write("a/l.yaml", R"(world:
  seabed: {type: heightmap, file: /etc/hostname, meters_per_pixel: 2, height_range: [-120, -100]}
  soil: {regions: [{preset: dry_sand}], map: {file: ../../map.png, meters_per_pixel: 1}}
vehicles:
  - {name: x, include: link.yaml}
  - name: y
    type: rov
    links: [{name: frame, visual: {file: /usr/share/mesh.glb}, mass: 1.0, inertia: {ixx: 1, iyy: 1, izz: 1}}]
)");
  const auto link_errors = errors_of(link);
  ASSERT_EQ(link_errors.size(), 4u) << ::testing::PrintToString(link_errors);
  EXPECT_NE(link_errors[0].find(":2:35: error: world.seabed.file: '/etc/hostname'" + roots),
            std::string::npos)
      << link_errors[0];
  EXPECT_NE(link_errors[1].find(":3:53: error: world.soil.map.file: '../../map.png'" + roots),
            std::string::npos)
      << link_errors[1];
  EXPECT_NE(link_errors[2].find(":5:24: error: vehicles[0].include: 'link.yaml'" + roots),
            std::string::npos)
      << link_errors[2];
  EXPECT_NE(link_errors[3].find(":8:42: error: vehicles[1].links[0].visual.file: '/usr/share/mesh.glb'" + roots),
            std::string::npos) << link_errors[3];
  // The scenarios/ layout of configs/: the tree is the directory holding scenarios/.
  const std::string layout = write("scenarios/s.yaml", "world: {}\nvehicles:\n  - {name: x, include: ../v.yaml}\n");
  EXPECT_EQ(errors_of(layout), Lines{});
}

TEST_F(ScenarioLoaderTest, WhatIsNotYamlOrNotAFileIsNeverQuotedOrRead) {
  // Like /etc/passwd: one block of plain text.
  write("passwd.txt", "root:x:0:0:root:/root:/bin/bash\nlp:x:7:7:lp:/var/spool/lpd:/usr/sbin/nologin\n");
  const std::string text = write("t.yaml", "world: {}\nvehicles:\n  - {name: x, include: passwd.txt}\n");
  const std::string plain = ":1:1: error: expected a map (got a document that is plain text, not keys and values)";
  EXPECT_EQ(errors_of(text), (Lines{(dir_ / "passwd.txt").string() + plain}));
  EXPECT_EQ(errors_of((dir_ / "passwd.txt").string()), (Lines{(dir_ / "passwd.txt").string() + plain}));
  // Like /etc/shadow: each line ends in ':', so YAML reads a map whose keys are the lines. Keys that are no
  // names are reported without their text, in the messages and in the paths.
  write("shadow.txt", "root:$y$j9T$secret-hash:19000:0:99999:7:::\nline two:\n");
  const std::string shadow = write("s.yaml", "world: {}\nvehicles:\n  - {name: x, include: shadow.txt}\n");
  const std::string file = (dir_ / "shadow.txt").string();
  EXPECT_EQ(errors_of(shadow), (Lines{file + ":1:1: error: unknown key that is not a name (its text is not shown)",
                                      file + ":1:1: error: missing required key 'type'",
                                      file + ":1:1: error: missing required key 'links'",
                                      file + ":2:1: error: unknown key that is not a name (its text is not shown)"}));
  // A directory and a pipe (which would block a reader forever) are not files.
  fs::create_directories(dir_ / "sub");
  ASSERT_EQ(::mkfifo((dir_ / "pipe").c_str(), 0600), 0);
  const std::string special = write("d.yaml", R"(world: {}
vehicles:
  - {name: x, include: sub}
  - {name: y, include: pipe}
)");
  EXPECT_EQ(errors_of(special), (Lines{special + ":3:24: error: vehicles[0].include: 'sub' is not a regular file",
                                       special + ":4:24: error: vehicles[1].include: 'pipe' is not a regular file"}));
}

TEST(DiagnosticTest, FormatsPositionAndPath) {
  Diagnostic diagnostic{"a.yaml", 12, 14, "vehicles[0].thrusters[1].max_rpm", "must be > 0 (got -5)"};
  EXPECT_EQ(diagnostic.format(),
            "a.yaml:12:14: error: vehicles[0].thrusters[1].max_rpm: must be > 0 (got -5)");
  diagnostic.path.clear();
  EXPECT_EQ(diagnostic.format(), "a.yaml:12:14: error: must be > 0 (got -5)");
  diagnostic.line = 0;
  EXPECT_EQ(diagnostic.format(), "a.yaml: error: must be > 0 (got -5)");
}

}  // namespace
}  // namespace hadal::config

namespace hadal::config {
namespace {

// The `security:` block (config/security_block.h): six files relative to the file holding it, each readable;
// in a scenario, inside the scenario's tree like every file it names; as a file of its own (hadald --security,
// the clients), anywhere.
TEST_F(ScenarioLoaderTest, ASecurityBlockNamesSixReadableFiles) {
  for (const char* file : {"ca.pem", "permissions_ca.pem", "governance.p7s", "permissions.p7s", "me/cert.pem",
                           "me/key.pem"}) {
    write(std::string("sec/") + file, "not checked here: Fast DDS reads them");
  }
  const std::string block = R"(security:
  identity_ca: ca.pem
  certificate: me/cert.pem
  private_key: me/key.pem
  permissions_ca: permissions_ca.pem
  governance: governance.p7s
  permissions: permissions.p7s
)";
  const std::string scenario = write("sec/s.yaml", std::string("world: {}\n") + block + "vehicles:" + kInlineVehicle);
  const LoadResult loaded = load_scenario_file(scenario);
  for (const Diagnostic& d : loaded.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(loaded.ok());
  EXPECT_TRUE(loaded.model->security.enabled());
  EXPECT_EQ(loaded.model->security.private_key, (dir_ / "sec/me/key.pem").string());
  EXPECT_EQ(loaded.model->security.governance, (dir_ / "sec/governance.p7s").string());
  // No block: security off.
  EXPECT_FALSE(load_scenario_file(write("sec/plain.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle))
                   .model->security.enabled());

  // The same block as a file of its own.
  const std::string own = write("sec/me.yaml", block);
  EXPECT_EQ(load_security_file(own).certificate, (dir_ / "sec/me/cert.pem").string());

  // Every key is required; a misspelt one is named; a file must be readable; a scenario's stay in its tree.
  const std::string partial = write("sec/partial.yaml", "security:\n  identity_ca: ca.pem\n  certificat: me/cert.pem\n");
  try {
    load_security_file(partial);
    ADD_FAILURE() << "an incomplete block was accepted";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(partial + ":3:3: error: security.certificat: unknown key 'certificat'; did you mean "
                                  "'certificate'?"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find(partial + ":2:3: error: security: missing required key 'private_key'"), std::string::npos)
        << what;
  }
  std::string missing = block;
  missing.replace(missing.find("me/key.pem"), 10, "me/nokey.pem");
  const std::string missing_file = write("sec/missing.yaml", missing);
  EXPECT_THROW(
      {
        try {
          load_security_file(missing_file);
        } catch (const std::runtime_error& e) {
          EXPECT_EQ(std::string(e.what()), missing_file + ":4:16: error: security.private_key: cannot read "
                                                           "'me/nokey.pem' (No such file or directory)");
          throw;
        }
      },
      std::runtime_error);
  std::string outside = block;
  outside.replace(outside.find("me/key.pem"), 10, "/etc/passwd");
  const std::string leaking =
      write("sec/leak.yaml", std::string("world: {}\n") + outside + "vehicles:" + kInlineVehicle);
  const auto leak_errors = errors_of(leaking);
  ASSERT_EQ(leak_errors.size(), 1u);
  EXPECT_EQ(leak_errors[0].rfind(leaking + ":5:16: error: security.private_key: '/etc/passwd' lies outside", 0), 0u)
      << leak_errors[0];
}

}  // namespace
}  // namespace hadal::config
