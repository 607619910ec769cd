// The scenario loader: files, YAML, the scenario's root and what every table shares (unknown, duplicate,
// missing and wrong keys, all errors at file:line:col, in order), the files a scenario may reach, the
// security block. Each subsystem's keys are tested beside it (physics/water_spec_test.cc, ...).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/config/key_doc.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/config/vehicle_keys.h"
#include "hadal/config/security_block.h"
#include "hadal/geometry/triangle_mesh.h"
#include "hadal/render/water_presets.h"

namespace hadal::config {
namespace {

namespace fs = std::filesystem;

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
  // The entry adds a camera and a forward-looking sonar to the included sensors, and two lights.
  ASSERT_EQ(auv.sensors.size(), 8u);
  EXPECT_EQ(auv.sensors[7].name, "fls");
  EXPECT_EQ(auv.sensors[7].type(), "fls");
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
  EXPECT_EQ(auv.actuator_state_rate_hz, 20.0);

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
                   path + ":3:20: error: world.water.density: must be in [900, 1300] (got 0)",
                   path + ":4:26: error: world.origin.latitude_deg: must be in [-90, 90] (got 91)",
                   path + ":9:28: error: vehicles[0].links[0].mass: must be > 0 (got 0)",
                   path + ":12:44: error: vehicles[0].thrusters[0].max_rpm: must be > 0 (got -5)"}));
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

TEST_F(ScenarioLoaderTest, YamlSyntaxError) {
  const std::string path = write("s.yaml", R"(world:
  seed: 1
   frame_id: map
vehicles: []
)");
  EXPECT_EQ(errors_of(path), (Lines{path + ":3:12: error: yaml: illegal map value"}));
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

// Presets are data with their sources (config/preset.h): every `preset` key of every table names, for
// each of its choices, the product and where its figures come from, and the reference shows both.
TEST(PresetTest, EveryPresetNamesItsProductAndSource) {
  std::vector<const TableDoc*> tables = all_tables(scenario_keys().doc());
  for (const TableDoc* table : all_tables(definition_keys().doc())) tables.push_back(table);
  std::vector<std::string> with_presets;
  std::set<const TableDoc*> seen;  // a sensor table is reached from both roots
  for (const TableDoc* table : tables) {
    const KeyDoc* preset = table->find("preset");
    if (preset == nullptr || !seen.insert(table).second) continue;
    with_presets.push_back(table->id);
    ASSERT_EQ(preset->type, KeyType::kChoice) << table->id;
    ASSERT_FALSE(preset->choices.empty()) << table->id;
    const std::string reference = reference_table(*table);
    for (const KeyChoice& choice : preset->choices) {
      EXPECT_FALSE(choice.doc.empty()) << table->id << " preset " << choice.name << " names no product";
      EXPECT_FALSE(choice.source.empty()) << table->id << " preset " << choice.name << " gives no source";
      EXPECT_NE(reference.find("| `" + choice.name + "` | " + choice.doc + " | " + choice.source + " |"),
                std::string::npos)
          << table->id << " preset " << choice.name << " is not in the reference's preset table";
    }
  }
  // Soil (the world's and each region's), IMU, DVL, camera, the three sonars and the acoustic modem.
  EXPECT_EQ(with_presets.size(), 9u) << ::testing::PrintToString(with_presets);
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

// ---------------------------------------------------------------------------------------------------
// Command-line overrides (LoadOptions::overrides, hadald --set; docs/configuration.md, "Overrides"): each
// sets one key as if the file said so, checked by the same keys and messages, reported at the override.


// A scenario without world.water.current and with two vehicles: the inline `auv` and `lander`, which
// includes lander.yaml (a 30 kg box) from beside the scenario.
constexpr const char* kLander = R"(type: lander
links:
  - name: frame
    mass: 30.0
    inertia: {ixx: 1, iyy: 1, izz: 1}
)";

class OverridesTest : public ScenarioLoaderTest {
 protected:
  std::string scenario(const std::string& more_vehicles = "") {
    write("lander.yaml", kLander);
    return write("s.yaml", std::string("world:\n  seed: 3\nvehicles:") + kInlineVehicle +
                               "  - name: lander\n    include: lander.yaml\n" + more_vehicles);
  }
  static LoadResult load(const std::string& path, const std::vector<std::string>& overrides) {
    LoadOptions options;
    options.overrides = overrides;
    return load_scenario_file(path, options);
  }
  static std::vector<std::string> errors(const std::string& path, const std::vector<std::string>& overrides) {
    const LoadResult result = load(path, overrides);
    EXPECT_EQ(result.model.has_value(), result.errors.empty());
    std::vector<std::string> lines;
    for (const Diagnostic& diagnostic : result.errors) lines.push_back(diagnostic.format());
    return lines;
  }
};

// A key the file has takes the override's value; a key it lacks (world.water and its current are not in
// the file) is added, maps on the way and all.
TEST_F(OverridesTest, AnOverrideSetsAKeyTheFileHasAndOneItLacks) {
  const LoadResult result = load(scenario(), {"world.seed=9", "world.water.current.uniform=[0.4, -0.1, 0]"});
  ASSERT_TRUE(result.ok()) << (result.errors.empty() ? "" : result.errors[0].format());
  EXPECT_EQ(result.model->world.seed, 9u);
  EXPECT_EQ(result.model->world.water.current.uniform_W, Eigen::Vector3d(0.4, -0.1, 0.0));
  const LoadResult plain = load(scenario(), {});
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain.model->world.seed, 3u);
  EXPECT_EQ(plain.model->world.water.current.uniform_W, Eigen::Vector3d::Zero());
}

// A list's entry by its name or by its index; the last of two overrides of one key wins.
TEST_F(OverridesTest, AListEntryIsNamedOrIndexedAndTheLastOverrideWins) {
  const LoadResult result = load(scenario(), {"vehicles.auv.initial_pose.position=[1, 2, -3]",
                                              "vehicles.1.command_timeout_s=2.5", "vehicles.lander.command_timeout_s=4"});
  ASSERT_TRUE(result.ok()) << (result.errors.empty() ? "" : result.errors[0].format());
  EXPECT_EQ(result.model->vehicles[0].X_WB_initial.translation(), Eigen::Vector3d(1.0, 2.0, -3.0));
  EXPECT_EQ(result.model->vehicles[1].command_timeout, 4.0);
  EXPECT_EQ(result.model->vehicles[0].command_timeout, 1.0);
}

// Through an entry with `include`, a definition key reaches into the included file, for that entry alone:
// a second entry including the same file keeps the file's mass.
TEST_F(OverridesTest, AnOverrideReachesIntoAnIncludedFileForItsEntryAlone) {
  const std::string path = scenario("  - name: lander2\n    include: lander.yaml\n");
  const LoadResult result = load(path, {"vehicles.lander.links.frame.mass=40"});
  ASSERT_TRUE(result.ok()) << (result.errors.empty() ? "" : result.errors[0].format());
  EXPECT_EQ(result.model->vehicles[1].links.at(0).mass, 40.0);
  EXPECT_EQ(result.model->vehicles[2].links.at(0).mass, 30.0);
}

// Every error is the file's own check, reported at the override: "--set TEXT:1:column", the column in
// TEXT, the path as the file would be read; the load fails and nothing else is reported.
TEST_F(OverridesTest, ErrorsAreTheFilesChecksReportedAtTheOverride) {
  const std::string path = scenario();
  EXPECT_EQ(errors(path, {"world.seed=abc"}),
            Lines{"--set world.seed=abc:1:12: error: world.seed: expected a non-negative integer (got 'abc')"});
  EXPECT_EQ(errors(path, {"world.water.current.unifrm=[0.4, 0, 0]"}),
            Lines{"--set world.water.current.unifrm=[0.4, 0, 0]:1:21: error: world.water.current.unifrm: unknown key "
                  "'unifrm'; did you mean 'uniform'?"});
  EXPECT_EQ(errors(path, {"world.water.current.uniform=[0.4, 0]"}),
            Lines{"--set world.water.current.uniform=[0.4, 0]:1:29: error: world.water.current.uniform: expected a "
                  "list of 3 numbers (got a list of 2)"});
  EXPECT_EQ(errors(path, {"vehicles.rov.command_timeout_s=2"}),
            Lines{"--set vehicles.rov.command_timeout_s=2:1:10: error: vehicles: no entry 'rov' in vehicles (its "
                  "entries: auv, lander)"});
  EXPECT_EQ(errors(path, {"vehicles.lander.links.frame.mass=-1"}),
            Lines{"--set vehicles.lander.links.frame.mass=-1:1:34: error: links[0].mass: must be > 0 (got -1)"});
  EXPECT_EQ(errors(path, {"world.seed"}),
            Lines{"--set world.seed:1:1: error: expected KEY.PATH=VALUE, as world.water.current.uniform=[0.4, 0, 0] "
                  "(got 'world.seed')"});
  EXPECT_EQ(errors(path, {"world..seed=1"}), Lines{"--set world..seed=1:1:7: error: world..seed: an empty key in the path"});
  EXPECT_EQ(errors(path, {"world.water.current.uniform=[0.4, 0"}),
            Lines{"--set world.water.current.uniform=[0.4, 0:1:29: error: world.water.current.uniform: the value does not "
                  "read as YAML (end of sequence flow not found)"});
}

// An included file read again for an entry's overrides reports its own errors once, not once per read.
TEST_F(OverridesTest, AnIncludedFilesOwnErrorIsReportedOnce) {
  const std::string path = scenario();
  write("lander.yaml", std::string(kLander) + "    colour: red\n");
  const std::vector<std::string> found = errors(path, {"vehicles.lander.links.frame.mass=40"});
  ASSERT_EQ(found.size(), 1u) << ::testing::PrintToString(found);
  EXPECT_NE(found[0].find("lander.yaml:6:"), std::string::npos) << found[0];
}

}  // namespace
}  // namespace hadal::config
