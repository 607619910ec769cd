// rt/hadal/scene from the default scenario: the seabed's mesh is the procedural terrain as loaded, each
// vehicle's mesh is its visual surface in B, every sensor and light has its frame (X_BS) and reach, and
// a plane seabed becomes a square around the vehicles. The message survives a CDR round trip.
#include "scene_message.h"

#include "hadal/config/scenario_loader.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/physics/articulation.h"
#include "hadal/physics/ocean.h"
#include "message_conversion.h"

#include <fastdds/rtps/common/SerializedPayload.h>
#include <hadal_msgsPubSubTypes.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace hadal::dds {
namespace {

Model load(const std::string& name) {
  config::LoadResult loaded = config::load_scenario_file(HADAL_SOURCE_DIR "/configs/scenarios/" + name);
  EXPECT_TRUE(loaded.ok());
  return *loaded.model;
}

const hadal_msgs::msg::SceneFrame* find_frame(const hadal_msgs::msg::Scene& msg, const std::string& vehicle,
                                               const std::string& name) {
  for (const auto& frame : msg.frames()) {
    if (frame.vehicle() == vehicle && frame.name() == name) return &frame;
  }
  return nullptr;
}

// The message comes back the same from its CDR bytes.
bool round_trips(hadal_msgs::msg::Scene& msg) {
  hadal_msgs::msg::ScenePubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&msg)());
  hadal_msgs::msg::Scene back;
  return type.serialize(&msg, &payload) && type.deserialize(&payload, &back) && back == msg;
}

TEST(SceneMessageTest, DefaultScenarioHasItsSeabedVehiclesAndFrames) {
  const Model model = load("default.yaml");
  hadal_msgs::msg::Scene msg;
  fill_scene(model, 0.0, msg);
  EXPECT_EQ(msg.scenario(), "default.yaml");
  EXPECT_EQ(msg.header().frame_id(), "world");
  EXPECT_FALSE(msg.seabed_is_plane());
  ASSERT_EQ(msg.meshes().size(), 1 + model.vehicles.size());
  // 400 m x 400 m at 2 m: under kMaxSeabedTriangles, so the loaded mesh itself.
  const auto& seabed = msg.meshes()[0];
  EXPECT_EQ(seabed.name(), "seabed");
  EXPECT_EQ(seabed.indices(), model.world.seabed.mesh->indices);
  EXPECT_EQ(seabed.positions(), model.world.seabed.mesh->positions);
  for (std::size_t v = 0; v < model.vehicles.size(); ++v) {
    const auto& mesh = msg.meshes()[v + 1];
    EXPECT_EQ(mesh.name(), model.vehicles[v].name);
    EXPECT_EQ(mesh.frame_id(), model.vehicles[v].name + "/base_link");
    EXPECT_EQ(mesh.indices(), geometry::vehicle_visual_B(model.vehicles[v]).indices);
    EXPECT_GT(mesh.indices().size(), 0u);
    EXPECT_EQ(msg.vehicle_names()[v], model.vehicles[v].name);
  }
  // torpedo_auv.yaml: the DVL looks down with 30 deg beams reaching max_altitude; the altimeter's beam
  // is x of its frame, which points down.
  const auto* dvl = find_frame(msg, "auv", "dvl");
  ASSERT_NE(dvl, nullptr);
  EXPECT_EQ(dvl->kind(), "dvl");
  EXPECT_EQ(dvl->frame_id(), "auv/dvl");
  EXPECT_NEAR(dvl->half_angle(), 30.0 * M_PI / 180.0, 1e-12);
  const auto* altimeter = find_frame(msg, "auv", "altimeter");
  ASSERT_NE(altimeter, nullptr);
  const auto& q = altimeter->pose().orientation();
  const Eigen::Vector3d x_S_in_B =
      Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()) * Eigen::Vector3d::UnitX();
  EXPECT_LT(x_S_in_B.z(), -0.99);
  std::size_t lights = 0;
  for (const auto& frame : msg.frames()) lights += frame.kind() == "light";
  std::size_t expected_lights = 0;
  for (const auto& vehicle : model.vehicles) expected_lights += vehicle.lights.size();
  EXPECT_EQ(lights, expected_lights);
  EXPECT_GT(lights, 0u);

  EXPECT_TRUE(round_trips(msg));
}

// The work-class ROV with its arm: one SceneLink per moving body, parents first, one joint each (every joint
// rt/rov/joint_states names once), and a mesh in K for each body with geometry. What a viewer does with them,
// X_parent_K(q) = pose * motion(axis, q) down the tree, is each body's pose in B from the articulation's own
// kinematics (within 1e-12 m and rad) at joint positions that differ per joint (a wrong axis, sign or order
// shows); the moving meshes and the rigid one together are the whole vehicle's.
TEST(SceneMessageTest, AnArticulatedVehiclesMovingBodiesHaveAMeshAndTheirKinematics) {
  const Model model = load("rov_intervention.yaml");
  const VehicleSpec& rov = model.vehicles.at(0);
  hadal_msgs::msg::Scene msg;
  fill_scene(model, 0.0, msg);
  const physics::Articulation a(rov.links);
  ASSERT_EQ(msg.links().size(), static_cast<std::size_t>(a.num_bodies() - 1));
  const std::vector<std::string> joints = joint_state_layout(rov).names;
  Eigen::VectorXd q(a.num_dofs());
  for (Eigen::Index j = 0; j < q.size(); ++j) q[j] = 0.1 * static_cast<double>(j + 1) * (j % 2 ? -1.0 : 1.0);
  const std::vector<Eigen::Isometry3d> X_BK = a.poses_W(Eigen::Isometry3d::Identity(), q);
  std::map<std::string, Eigen::Isometry3d> posed = {{"base_link", Eigen::Isometry3d::Identity()}};
  std::size_t moving_triangles = 0;
  for (std::size_t i = 0; i < msg.links().size(); ++i) {
    const auto& link = msg.links()[i];
    EXPECT_EQ(link.vehicle(), "rov");
    ASSERT_EQ(posed.count(link.parent()), 1u) << link.name() << ": its parent " << link.parent() << " comes first";
    const auto j = std::find(joints.begin(), joints.end(), link.joint()) - joints.begin();
    ASSERT_LT(j, static_cast<long>(joints.size())) << link.joint();
    const auto& pose = link.pose();
    Eigen::Isometry3d X_PK = Eigen::Isometry3d::Identity();
    X_PK.translation() = Eigen::Vector3d(pose.position().x(), pose.position().y(), pose.position().z());
    X_PK.linear() = Eigen::Quaterniond(pose.orientation().w(), pose.orientation().x(), pose.orientation().y(),
                                       pose.orientation().z())
                        .toRotationMatrix();
    const Eigen::Vector3d axis(link.axis().x(), link.axis().y(), link.axis().z());
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (link.joint_type() == "prismatic") {
      motion.translation() = q[j] * axis;
    } else {
      motion.linear() = Eigen::AngleAxisd(q[j], axis).toRotationMatrix();
    }
    const Eigen::Isometry3d X = posed.at(link.parent()) * X_PK * motion;
    posed[link.name()] = X;
    const Eigen::Isometry3d& expected = X_BK[i + 1];
    EXPECT_LT((X.translation() - expected.translation()).norm(), 1e-12) << link.name();
    EXPECT_LT((X.linear() - expected.linear()).norm(), 1e-12) << link.name();
    for (const auto& mesh : msg.meshes()) {
      if (mesh.name() == "rov/" + link.name()) {
        EXPECT_EQ(mesh.frame_id(), "rov/" + link.name());
        moving_triangles += mesh.indices().size() / 3;
      }
    }
  }
  EXPECT_GT(moving_triangles, 0u);
  // The wrist's force/torque sensor rides on the end effector's body: the frame names it, and its pose in it,
  // carried by the body's pose at q = 0, is the frame's pose in B.
  const auto* wrist = find_frame(msg, "rov", "wrist_ft");
  ASSERT_NE(wrist, nullptr);
  ASSERT_FALSE(wrist->link().empty());
  const auto pose_of = [](const geometry_msgs::msg::Pose& pose) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() = Eigen::Vector3d(pose.position().x(), pose.position().y(), pose.position().z());
    X.linear() = Eigen::Quaterniond(pose.orientation().w(), pose.orientation().x(), pose.orientation().y(),
                                    pose.orientation().z())
                     .toRotationMatrix();
    return X;
  };
  const std::vector<Eigen::Isometry3d> X_BK0 =
      a.poses_W(Eigen::Isometry3d::Identity(), Eigen::VectorXd::Zero(q.size()));
  int body = -1;
  for (int k = 1; k < a.num_bodies(); ++k) {
    if (rov.links[static_cast<std::size_t>(a.body(k).joint_link)].name == wrist->link()) body = k;
  }
  ASSERT_GT(body, 0) << wrist->link();
  const Eigen::Isometry3d X_BS = X_BK0[static_cast<std::size_t>(body)] * pose_of(wrist->link_pose());
  EXPECT_LT((X_BS.matrix() - pose_of(wrist->pose()).matrix()).norm(), 1e-12);
  EXPECT_TRUE(find_frame(msg, "rov", "depth")->link().empty());  // on the frame (B)
  std::vector<std::pair<int, Eigen::Isometry3d>> every_link;
  for (std::size_t l = 0; l < rov.links.size(); ++l) every_link.emplace_back(static_cast<int>(l), rov.links[l].X_BL);
  EXPECT_EQ(geometry::vehicle_visual_B(rov).num_triangles() + moving_triangles,
            geometry::links_visual_A(rov, every_link).num_triangles());

  EXPECT_TRUE(round_trips(msg));
}

TEST(SceneMessageTest, PlaneSeabedIsASquareAroundTheVehicles) {
  const Model model = load("glider.yaml");
  ASSERT_EQ(model.world.seabed.type, SeabedType::kPlane);
  hadal_msgs::msg::Scene msg;
  fill_scene(model, 0.0, msg);
  EXPECT_TRUE(msg.seabed_is_plane());
  const auto& seabed = msg.meshes()[0];
  ASSERT_EQ(seabed.positions().size(), 12u);
  EXPECT_EQ(seabed.indices().size(), 6u);
  float x_min = 1e9f, x_max = -1e9f;
  for (int i = 0; i < 4; ++i) {
    EXPECT_FLOAT_EQ(seabed.positions()[3 * i + 2], static_cast<float>(model.world.seabed.z));
    x_min = std::min(x_min, seabed.positions()[3 * i]);
    x_max = std::max(x_max, seabed.positions()[3 * i]);
  }
  EXPECT_FLOAT_EQ(x_max - x_min, static_cast<float>(kPlaneSide));
  const double x0 = model.vehicles[0].X_WB_initial.translation().x();
  EXPECT_NEAR(0.5 * (x_min + x_max), x0, 1e-3);
}

// With waves the scene carries the simulation's own sea: the Ocean's components and build-up time, from which
// eta = r(t) sum a cos(k (x cos b + y sin b) - w t + phi) is the surface the physics sees (to the bit, computed the
// same way); without waves none. It round-trips through CDR.
TEST(SceneMessageTest, WithWavesItCarriesTheSeaStateComponents) {
  const Model model = load("vessel_waves.yaml");
  hadal_msgs::msg::Scene msg;
  fill_scene(model, 0.0, msg);
  const physics::Ocean ocean(model.world);
  const physics::Waves& waves = ocean.waves();
  ASSERT_EQ(msg.wave_components().size(), waves.components().size());
  EXPECT_EQ(msg.wave_components().size(), 128u);
  EXPECT_EQ(msg.wave_ramp_time_s(), 16.0);
  for (const double t : {3.0, 40.0}) {
    const double x = 12.0, y = -7.0, r = waves.ramp(t);
    double eta = 0.0;
    for (const hadal_msgs::msg::WaveComponent& c : msg.wave_components()) {
      eta += c.amplitude_m() * std::cos(c.wave_number_rad_per_m() * std::cos(c.direction_rad()) * x +
                                        c.wave_number_rad_per_m() * std::sin(c.direction_rad()) * y -
                                        c.omega_rad_per_s() * t + c.phase_rad());
    }
    EXPECT_EQ(msg.water_surface_z() + r * eta, waves.surface_height(x, y, t)) << t;
  }
  EXPECT_TRUE(round_trips(msg));
  hadal_msgs::msg::Scene calm;
  fill_scene(load("vessel.yaml"), 0.0, calm);
  EXPECT_TRUE(calm.wave_components().empty());
  EXPECT_EQ(calm.wave_ramp_time_s(), 0.0);
}

// A seabed of more than kMaxSeabedTriangles goes as its top surface resampled on a grid: the slope
// z = 0.1 x - 50 over 300 m x 150 m, 300 x 300 cells, comes back at most kSeabedGrid cells along x with
// its vertices on the slope (float rounding: 1e-4 m at 80 m).
TEST(SceneMessageTest, LargeSeabedIsResampledOnAGrid) {
  Model model = load("glider.yaml");
  auto mesh = std::make_shared<geometry::TriangleMesh>();
  const int n = 300;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float x = static_cast<float>(i), y = 0.5f * static_cast<float>(j);
      mesh->positions.insert(mesh->positions.end(), {x, y, 0.1f * x - 50.0f});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      mesh->indices.insert(mesh->indices.end(), {a, b, c, a, c, d});
    }
  }
  ASSERT_GT(mesh->num_triangles(), kMaxSeabedTriangles);
  model.world.seabed.type = SeabedType::kMesh;
  model.world.seabed.mesh = mesh;
  hadal_msgs::msg::Scene msg;
  fill_scene(model, 0.0, msg);
  const auto& seabed = msg.meshes()[0];
  const std::size_t vertices = seabed.positions().size() / 3;
  EXPECT_EQ(vertices, static_cast<std::size_t>((kSeabedGrid + 1) * (kSeabedGrid / 2 + 1)));
  EXPECT_EQ(seabed.indices().size(), static_cast<std::size_t>(6 * kSeabedGrid * (kSeabedGrid / 2)));
  for (std::size_t k = 0; k < vertices; ++k) {
    const float x = seabed.positions()[3 * k], z = seabed.positions()[3 * k + 2];
    ASSERT_NEAR(z, 0.1 * x - 50.0, 1e-4) << "vertex " << k;
  }
}


// The ROV's finger tips (the Oberon 7's zero-range joints) are locked: fixed at 0 in the tree, and reported
// after the moving joints in JointState at their locks, rate and effort zero (robot_state_publisher needs
// every non-fixed URDF joint).
TEST(SceneMessageTest, JointStateReportsTheLockedJointsAtTheirLocks) {
  const Model model = load("rov_intervention.yaml");
  const VehicleSpec& rov = model.vehicles.at(0);
  const JointStateLayout layout = joint_state_layout(rov);
  const std::vector<std::string> expected = {"azimuth", "shoulder", "elbow", "roll", "pitch", "wrist",
                                             "finger_left_joint", "finger_right_joint", "finger_tip_left_joint",
                                             "finger_tip_right_joint"};
  ASSERT_EQ(layout.names, expected);
  VehicleState vehicle;
  for (int j = 0; j < 8; ++j) {
    vehicle.joint_positions.push_back(0.1 * (j + 1));
    vehicle.joint_velocities.push_back(-0.01 * (j + 1));
    vehicle.joint_efforts.push_back(3.0 * (j + 1));
  }
  sensor_msgs::msg::JointState msg;
  fill_joint_state(layout, "rov", 1.5, vehicle, msg);
  EXPECT_EQ(msg.name(), expected);
  ASSERT_EQ(msg.position().size(), 10u);
  ASSERT_EQ(msg.velocity().size(), 10u);
  ASSERT_EQ(msg.effort().size(), 10u);
  for (std::size_t j = 0; j < 8; ++j) {
    EXPECT_EQ(msg.position()[j], vehicle.joint_positions[j]);
    EXPECT_EQ(msg.velocity()[j], vehicle.joint_velocities[j]);
    EXPECT_EQ(msg.effort()[j], vehicle.joint_efforts[j]);
  }
  for (std::size_t j = 8; j < 10; ++j) {
    EXPECT_EQ(msg.position()[j], 0.0);
    EXPECT_EQ(msg.velocity()[j], 0.0);
    EXPECT_EQ(msg.effort()[j], 0.0);
  }
}
}  // namespace
}  // namespace hadal::dds
