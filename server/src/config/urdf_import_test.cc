// URDF import (config/urdf_import.h) through the scenario loader: what each element becomes, mesh files by
// package:// and relative paths, the errors at the URDF's element (file:line:col, the element named), and
// the Oberon 7 arm shipped in configs/urdf/ read with its source's masses and limits intact.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/assets/mesh_generators.h"
#include "hadal/assets/scene_writer.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/physics/articulation.h"

namespace hadal::config {
namespace {

// A two-link arm: a base with an inertial turned by rpy (90°, 0, 90°) (its x moment lies along L's y, y along
// z, z along x; the reverse turn would give another order) and
// two collision shapes, a revolute forearm 0.5 m along x whose joint has every attribute set.
constexpr const char* kArm = R"(<?xml version="1.0"?>
<robot name="arm">
  <material name="red"><color rgba="0.8 0.1 0.1 1"/></material>
  <link name="base">
    <inertial>
      <origin xyz="0.1 0.2 0.3" rpy="1.5707963267948966 0 1.5707963267948966"/>
      <mass value="20"/>
      <inertia ixx="1" iyy="2" izz="2.5" ixy="0" ixz="0" iyz="0"/>
    </inertial>
    <visual><geometry><box size="0.4 0.3 0.2"/></geometry><material name="red"/></visual>
    <collision><geometry><box size="0.4 0.3 0.2"/></geometry></collision>
    <collision>
      <origin xyz="0 0 0.2" rpy="1.5707963267948966 0 0"/>
      <geometry><cylinder radius="0.05" length="0.3"/></geometry>
    </collision>
  </link>
  <link name="forearm">
    <inertial>
      <origin xyz="0.25 0 0"/>
      <mass value="4"/>
      <inertia ixx="0.01" iyy="0.09" izz="0.09" ixy="0" ixz="0" iyz="0"/>
    </inertial>
    <collision><origin xyz="0.25 0 0"/><geometry><sphere radius="0.1"/></geometry></collision>
  </link>
  <joint name="elbow" type="revolute">
    <parent link="base"/>
    <child link="forearm"/>
    <origin xyz="0.5 0 0" rpy="0 0 0"/>
    <axis xyz="0 1 0"/>
    <limit lower="0.2" upper="1.5" effort="80" velocity="0.7"/>
    <dynamics damping="3" friction="1.5"/>
  </joint>
  <gazebo reference="forearm"><mu1>0.9</mu1><selfCollide>false</selfCollide></gazebo>
</robot>
)";

std::string vehicle_with(const std::string& urdf_key) {
  return "world: {}\nvehicles:\n  - name: arm\n    type: rov\n" + urdf_key;
}

TEST_F(ScenarioLoaderTest, UrdfLinksJointsAndInertialsBecomeTheVehicles) {
  write("urdf/arm.urdf", kArm);
  const std::string path = write("s.yaml", vehicle_with("    urdf: {file: urdf/arm.urdf}\n"));
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(result.ok());
  const VehicleSpec& v = result.model->vehicles.at(0);
  ASSERT_EQ(v.links.size(), 2u);
  const LinkSpec& base = v.links[0];
  EXPECT_EQ(base.name, "base");
  EXPECT_EQ(base.parent, -1);
  EXPECT_TRUE(base.X_BL.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(base.mass, 20.0);
  EXPECT_TRUE(base.p_LLcm.isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  // I_L = R I R^T: ixx (1) along L's y, iyy (2) along z, izz (2.5) along x.
  EXPECT_NEAR(base.I_LLcm_L(0, 0), 2.5, 1e-12);
  EXPECT_NEAR(base.I_LLcm_L(1, 1), 1.0, 1e-12);
  EXPECT_NEAR(base.I_LLcm_L(2, 2), 2.0, 1e-12);
  EXPECT_NEAR(base.I_LLcm_L(0, 1), 0.0, 1e-12);
  ASSERT_EQ(base.collisions.size(), 2u);
  EXPECT_EQ(base.collisions[0].type, CollisionShapeType::kBox);
  EXPECT_EQ(base.collisions[0].box_size, Eigen::Vector3d(0.4, 0.3, 0.2));
  EXPECT_EQ(base.collisions[1].type, CollisionShapeType::kCylinder);
  EXPECT_EQ(base.collisions[1].radius, 0.05);
  EXPECT_EQ(base.collisions[1].length, 0.3);
  // rpy (90°, 0, 0): the cylinder's axis (G's z) lies along -y of L.
  EXPECT_TRUE((base.collisions[1].X_LG.linear() * Eigen::Vector3d::UnitZ()).isApprox(-Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(base.collisions[1].X_LG.translation().isApprox(Eigen::Vector3d(0, 0, 0.2)));
  ASSERT_TRUE(base.appearance.albedo.has_value());
  EXPECT_TRUE(base.appearance.albedo->isApprox(Eigen::Array3d(0.8, 0.1, 0.1), 1e-6));

  const LinkSpec& forearm = v.links[1];
  EXPECT_EQ(forearm.name, "forearm");
  EXPECT_EQ(forearm.parent, 0);
  EXPECT_TRUE(forearm.X_BL.translation().isApprox(Eigen::Vector3d(0.5, 0, 0)));
  EXPECT_EQ(forearm.mass, 4.0);
  EXPECT_EQ(forearm.friction, 0.9);  // Gazebo's mu1
  EXPECT_EQ(base.friction, 0.5);     // the default
  ASSERT_EQ(forearm.collisions.size(), 1u);
  EXPECT_EQ(forearm.collisions[0].type, CollisionShapeType::kSphere);
  const JointSpec& elbow = forearm.joint;
  EXPECT_EQ(elbow.name, "elbow");
  EXPECT_EQ(elbow.type, JointType::kRevolute);
  EXPECT_EQ(elbow.axis_L, Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(elbow.lower, 0.2);
  EXPECT_EQ(elbow.upper, 1.5);
  EXPECT_EQ(elbow.effort_limit, 80.0);
  EXPECT_EQ(elbow.velocity_limit, 0.7);
  EXPECT_EQ(elbow.damping, 3.0);
  EXPECT_EQ(elbow.friction, 1.5);
  // q = 0 is outside [0.2, 1.5]: the joint starts at its nearer limit.
  EXPECT_EQ(elbow.initial, 0.2);
}

TEST_F(ScenarioLoaderTest, UrdfHangsOnAYamlLinkAtItsPose) {
  write("urdf/arm.urdf", kArm);
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: rov
    type: rov
    links:
      - {name: frame, mass: 100, inertia: {ixx: 10, iyy: 10, izz: 10}}
      - {name: skid, pose: {position: [0, 0, -1], rpy_deg: [0, 0, 180]}, mass: 10, inertia: {ixx: 1, iyy: 1, izz: 1}}
    urdf:
      file: urdf/arm.urdf
      parent: skid
      pose: {position: [1, 0, 0], rpy_deg: [0, 0, 90]}
    joint_controllers:
      - {name: arm, type: position, joints: [elbow], kp: 100, kd: 10}
)");
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(result.ok());
  const VehicleSpec& v = result.model->vehicles.at(0);
  ASSERT_EQ(v.links.size(), 4u);
  EXPECT_EQ(v.links[2].name, "base");
  EXPECT_EQ(v.links[2].parent, 1);
  EXPECT_EQ(v.links[2].joint.type, JointType::kFixed);
  // X_BL(base) = X_B(skid) X_P(root): 1 m along the skid's x (B's -x), turned 180° + 90° about z.
  EXPECT_TRUE(v.links[2].X_BL.translation().isApprox(Eigen::Vector3d(-1, 0, -1)));
  // The forearm 0.5 m along the base's x, which is B's -y.
  EXPECT_TRUE(v.links[3].X_BL.translation().isApprox(Eigen::Vector3d(-1, -0.5, -1)));
  EXPECT_EQ(v.links[3].parent, 2);
  ASSERT_EQ(v.joint_controllers.size(), 1u);
  const physics::Articulation articulation(v.links);
  EXPECT_EQ(articulation.num_dofs(), 1);
}

// A URDF has no initial positions: `initial_deg` (revolute, continuous) and `initial` (prismatic) give them by
// joint name, checked against the imported joints.
TEST_F(ScenarioLoaderTest, UrdfJointsStartWhereTheYamlSays) {
  write("urdf/arm.urdf", kArm);
  const std::string path = write("s.yaml", vehicle_with("    urdf: {file: urdf/arm.urdf, initial_deg: {elbow: 45}}\n"));
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(result.ok());
  EXPECT_NEAR(result.model->vehicles.at(0).links.at(1).joint.initial, 0.25 * 3.14159265358979323846, 1e-15);

  const std::string bad = write("b.yaml", vehicle_with("    urdf:\n      file: urdf/arm.urdf\n"
                                                       "      initial_deg: {elbow: 100, nope: 3}\n"
                                                       "      initial: {elbow: 0.5}\n"));
  EXPECT_EQ(errors_of(bad),
            Lines({bad + ":7:28: error: vehicles[0].urdf.initial_deg.elbow: must be within the joint's limits",
                   bad + ":7:39: error: vehicles[0].urdf.initial_deg.nope: the URDF has no moving joint named 'nope'",
                   bad + ":8:24: error: vehicles[0].urdf.initial.elbow: joint 'elbow' is revolute: its start goes in "
                         "`initial_deg`"}));
}

TEST_F(ScenarioLoaderTest, UrdfMeshesByPackageAndRelativePaths) {
  // A package laid out as ROS's: box_pkg/urdf/box.urdf names package://box_pkg/meshes/hull.glb.
  std::filesystem::create_directories(dir_ / "box_pkg/meshes");
  std::filesystem::create_directories(dir_ / "box_pkg/urdf");
  assets::write_scene(assets::single_mesh_scene(assets::make_box(0.4, 0.2, 0.1)),
                      (dir_ / "box_pkg/meshes/hull.glb").string());
  assets::write_scene(assets::single_mesh_scene(assets::make_box(1.0, 1.0, 1.0)),
                      (dir_ / "box_pkg/urdf/look.stl").string());
  write("box_pkg/urdf/box.urdf", R"(<robot name="box">
  <link name="hull">
    <inertial><mass value="8"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="look.stl" scale="0.5 0.5 0.5"/></geometry></visual>
    <collision>
      <origin xyz="0 0 1"/>
      <geometry><mesh filename="package://box_pkg/meshes/hull.glb"/></geometry>
    </collision>
  </link>
</robot>
)");
  const std::string path = write("s.yaml", vehicle_with("    urdf: {file: box_pkg/urdf/box.urdf}\n"));
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(result.ok());
  const LinkSpec& hull = result.model->vehicles.at(0).links.at(0);
  ASSERT_TRUE(hull.mesh.has_value());
  EXPECT_TRUE(hull.mesh->closed);
  // GLB stores float32 vertices: 1e-6 relative covers their rounding (~6e-8 each).
  EXPECT_NEAR(hull.mesh->volume, 0.4 * 0.2 * 0.1, 1e-6 * 0.008);
  // The collision origin moves the mesh into L; a closed collision mesh displaces its volume.
  EXPECT_TRUE(hull.mesh->p_LMc.isApprox(Eigen::Vector3d(0, 0, 1), 1e-6));
  EXPECT_NEAR(hull.buoyancy.volume, 0.008, 1e-6 * 0.008);
  ASSERT_TRUE(hull.visual.has_value());
  EXPECT_NEAR(hull.visual->volume, 0.125, 1e-12);  // a 1 m cube at scale 0.5
}

// Loads a vehicle whose URDF is `urdf` and returns the diagnostics.
class UrdfErrorTest : public ScenarioLoaderTest {
 protected:
  std::vector<std::string> errors_with(const std::string& urdf, const std::string& key = "    urdf: {file: a.urdf}\n") {
    write("a.urdf", urdf);
    return errors_of(write("s.yaml", vehicle_with(key)));
  }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
};

constexpr const char* kLinkA = R"(  <link name="a">
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
)";
constexpr const char* kLinkB = R"(  <link name="b">
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
)";

TEST_F(UrdfErrorTest, AFloatingJointIsRefusedAtItsElement) {
  const auto errors = errors_with(std::string("<robot name=\"r\">\n") + kLinkA + kLinkB +
                                  "  <joint name=\"free\" type=\"floating\">\n"
                                  "    <parent link=\"a\"/><child link=\"b\"/>\n  </joint>\n</robot>\n");
  EXPECT_EQ(errors, Lines({file("a.urdf") +
                           ":8:3: error: joint 'free': type floating is not supported (fixed, revolute, continuous, "
                           "prismatic); a vehicle's base floats already"}));
}

TEST_F(UrdfErrorTest, AJointNamingAMissingLinkIsNamed) {
  const auto errors = errors_with(std::string("<robot name=\"r\">\n") + kLinkA +
                                  "  <joint name=\"j\" type=\"fixed\">\n"
                                  "    <parent link=\"a\"/><child link=\"nowhere\"/>\n  </joint>\n</robot>\n");
  // urdfdom names the link and the joint; the joint is the element that exists.
  EXPECT_EQ(errors, Lines({file("a.urdf") + ":5:3: error: joint 'j': urdfdom: Failed to build tree: child link "
                                            "[nowhere] of joint [j] not found"}));
}

TEST_F(UrdfErrorTest, ACycleIsRefused) {
  // a -> b -> a: urdfdom finds no root (every link has a parent).
  const auto errors =
      errors_with(std::string("<robot name=\"r\">\n") + kLinkA + kLinkB +
                  "  <joint name=\"ab\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>\n"
                  "  <joint name=\"ba\" type=\"fixed\"><parent link=\"b\"/><child link=\"a\"/></joint>\n"
                  "</robot>\n");
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors[0].find(file("a.urdf") + ":"), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find("urdfdom: "), std::string::npos) << errors[0];
}

TEST_F(UrdfErrorTest, AZeroInertiaIsRefusedAtItsLink) {
  const auto errors = errors_with(
      "<robot name=\"r\">\n  <link name=\"flat\">\n"
      "    <inertial><mass value=\"1\"/><inertia ixx=\"0\" iyy=\"0\" izz=\"0\" ixy=\"0\" ixz=\"0\" "
      "iyz=\"0\"/></inertial>\n"
      "  </link>\n</robot>\n");
  EXPECT_EQ(errors, Lines({file("a.urdf") +
                           ":2:3: error: link 'flat': inertia must be positive definite (principal moments 0, 0, 0)"}));
}

TEST_F(UrdfErrorTest, MalformedXmlIsReportedNotThrown) {
  const auto errors = errors_with("<robot name=\"r\">\n  <link name=\"a\">\n</robot\n");
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors[0].find(file("a.urdf") + ":"), std::string::npos) << errors[0];
}

TEST_F(UrdfErrorTest, GazebosWorldRootAsksForAnotherRoot) {
  const std::string urdf = std::string("<robot name=\"r\">\n  <link name=\"world\"/>\n") + kLinkA +
                           "  <joint name=\"anchor\" type=\"revolute\"><parent link=\"world\"/><child link=\"a\"/>\n"
                           "    <limit effort=\"0\" lower=\"0\" upper=\"0\" velocity=\"0\"/></joint>\n</robot>\n";
  EXPECT_EQ(errors_with(urdf),
            Lines({file("a.urdf") + ":2:3: error: link 'world': the root link has no inertial and its joint 'anchor' "
                                    "moves: it is not part of a vehicle (Gazebo's `world`?); give urdf.root, the link "
                                    "to start at ('a'?)"}));
  // Starting at `a` leaves `world` and the anchor out.
  EXPECT_TRUE(errors_with(urdf, "    urdf: {file: a.urdf, root: a}\n").empty());
  EXPECT_EQ(
      errors_with(urdf, "    urdf: {file: a.urdf, root: b}\n"),
      Lines({file("s.yaml") + ":5:32: error: vehicles[0].urdf.root: no link named 'b' in 'a.urdf' (links: a, world)"}));
}

TEST_F(UrdfErrorTest, MountErrorsAreAtTheirYamlKeys) {
  write("elsewhere/b.urdf", std::string("<robot name=\"r\">\n") + kLinkA + "</robot>\n");
  // A URDF outside the scenario's tree and hadal's configs.
  const std::filesystem::path outside =
      std::filesystem::temp_directory_path() / ("hadal_urdf_outside_" + std::to_string(::getpid()) + ".urdf");
  std::ofstream(outside) << "<robot name=\"r\"/>\n";
  const auto errors = errors_with(std::string("<robot name=\"r\">\n") + kLinkA + "</robot>\n",
                                  "    urdf: {file: " + outside.string() + "}\n");
  std::filesystem::remove(outside);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].rfind(file("s.yaml") + ":5:18: error: vehicles[0].urdf.file: '" + outside.string() +
                                "' lies outside the directories a scenario may name files in",
                            0),
            0u)
      << errors[0];
  EXPECT_EQ(errors_with(std::string("<robot name=\"r\">\n") + kLinkA + "</robot>\n",
                        "    urdf: {file: a.urdf, parent: frame}\n"),
            Lines({file("s.yaml") + ":5:34: error: vehicles[0].urdf.parent: needs `links` (without them the URDF's "
                                    "root is the base link)"}));
}

TEST_F(UrdfErrorTest, AMeshOutsideTheRootsIsRefused) {
  const auto errors = errors_with(
      "<robot name=\"r\">\n  <link name=\"a\">\n"
      "    <inertial><mass value=\"1\"/><inertia ixx=\"0.1\" iyy=\"0.1\" izz=\"0.1\" ixy=\"0\" ixz=\"0\" "
      "iyz=\"0\"/></inertial>\n"
      "    <collision><geometry><mesh filename=\"file:///etc/hostname\"/></geometry></collision>\n"
      "  </link>\n</robot>\n");
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].rfind(file("a.urdf") + ":2:3: error: link 'a': mesh 'file:///etc/hostname' lies outside", 0), 0u)
      << errors[0];
}

TEST_F(UrdfErrorTest, AJointWithoutMotorCannotBeDriven) {
  // <limit effort="0">: a joint without a motor (the Oberon 7's finger tips); a controller may not list it.
  const std::string urdf = std::string("<robot name=\"r\">\n") + kLinkA + kLinkB +
                           "  <joint name=\"tip\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n"
                           "    <limit effort=\"0\" lower=\"-1\" upper=\"1\" velocity=\"1\"/></joint>\n</robot>\n";
  EXPECT_TRUE(errors_with(urdf).empty());
  EXPECT_EQ(errors_with(urdf,
                        "    urdf: {file: a.urdf}\n    joint_controllers:\n"
                        "      - {name: tips, type: effort, joints: [tip]}\n"),
            Lines({file("s.yaml") + ":7:45: error: vehicles[0].joint_controllers[0].joints[0]: joint 'tip' has no "
                                    "motor (its effort limit is 0)"}));
}

// configs/urdf/oberon7_arm.urdf against its source, uuvsimulator/uuv_manipulators'
// oberon7_description/models/oberon7/model.urdf: every mass, and every joint's limits, as the source gives them.
TEST_F(ScenarioLoaderTest, Oberon7ArmImportsWithItsSourcesMassesAndLimits) {
  const std::string path = write("s.yaml", vehicle_with(std::string("    urdf: {file: ") + HADAL_SOURCE_CONFIGS_DIR +
                                                        "/urdf/oberon7_arm.urdf}\n"));
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& d : result.errors) ADD_FAILURE() << d.format();
  ASSERT_TRUE(result.ok());
  const std::vector<LinkSpec>& links = result.model->vehicles.at(0).links;
  const struct {
    const char* link;
    double mass;
  } masses[] = {
      {"base", 9.67467717018},          {"shoulder_link", 6.72225246901},   {"upper_arm", 12.4443999072},
      {"elbow_link", 10.3145088675},    {"forearm", 8.54626175585},         {"wrist_link", 3.9024235777},
      {"end_effector", 3.46114581082},  {"finger_left", 0.879770511849},    {"finger_tip_left", 1.12550524054},
      {"finger_right", 0.879770511849}, {"finger_tip_right", 1.12550524054}};
  ASSERT_EQ(links.size(), std::size(masses));
  for (const auto& expected : masses) {
    const auto it =
        std::find_if(links.begin(), links.end(), [&](const LinkSpec& l) { return l.name == expected.link; });
    ASSERT_NE(it, links.end()) << expected.link;
    EXPECT_EQ(it->mass, expected.mass) << expected.link;
  }
  const double inf = std::numeric_limits<double>::infinity();
  const struct {
    const char* joint;
    JointType type;
    double lower, upper, effort, velocity;
  } joints[] = {{"azimuth", JointType::kRevolute, -1.04719758, 1.04719758, 200, 0.17},
                {"shoulder", JointType::kRevolute, -1.57079637, 1.57079637, 5000, 0.17},
                {"elbow", JointType::kRevolute, -1.57079637, 1.04719758, 300, 0.13},
                {"roll", JointType::kRevolute, -2.356194555, 2.356194555, 200, 0.085},
                {"pitch", JointType::kRevolute, -1.57079637, 1.57079637, 200, 0.26},
                {"wrist", JointType::kContinuous, -inf, inf, inf, inf},
                {"finger_left_joint", JointType::kRevolute, 0, 1.04709283144, 30, 0.15},
                {"finger_tip_left_joint", JointType::kRevolute, 0, 0, 0, 0},
                {"finger_right_joint", JointType::kRevolute, 0, 1.04709283144, 30, 0.15},
                {"finger_tip_right_joint", JointType::kRevolute, 0, 0, 0, 0}};
  for (const auto& expected : joints) {
    const auto it =
        std::find_if(links.begin(), links.end(), [&](const LinkSpec& l) { return l.joint.name == expected.joint; });
    ASSERT_NE(it, links.end()) << expected.joint;
    // A joint whose limits meet is loaded fixed at its lock, its own type kept (geometry::lock_joints).
    const bool locked = expected.lower == expected.upper;
    EXPECT_EQ(locked ? it->joint.locked_type : it->joint.type, expected.type) << expected.joint;
    EXPECT_EQ(it->joint.type == JointType::kFixed, locked) << expected.joint;
    EXPECT_EQ(it->joint.lower, expected.lower) << expected.joint;
    EXPECT_EQ(it->joint.upper, expected.upper) << expected.joint;
    EXPECT_EQ(it->joint.effort_limit, expected.effort) << expected.joint;
    EXPECT_EQ(it->joint.velocity_limit, expected.velocity) << expected.joint;
  }
  // The shoulder's friction and damping, and the elbow's origin 0.55616 m along the upper arm.
  const auto upper = std::find_if(links.begin(), links.end(), [](const LinkSpec& l) { return l.name == "upper_arm"; });
  const auto elbow = std::find_if(links.begin(), links.end(), [](const LinkSpec& l) { return l.name == "elbow_link"; });
  EXPECT_EQ(upper->joint.friction, 120.0);
  EXPECT_EQ(upper->joint.damping, 50.0);
  EXPECT_NEAR((upper->X_BL.inverse() * elbow->X_BL).translation().x(), 0.55616, 1e-12);
  const physics::Articulation articulation(links);
  EXPECT_EQ(articulation.num_dofs(), 8);  // the finger tips locked
}

}  // namespace
}  // namespace hadal::config
