// The camera kind alone (no Bullet): a capture of a real Embree world rendered on the ray-cast service's
// workers, against closed forms; determinism of its noise; its three messages.
#include "hadal/sensors/camera_sensor.h"

#include <gtest/gtest.h>
#include <sensor_msgs.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <unistd.h>

#include "hadal/core/units.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/render/frame.h"
#include "hadal/render/texture.h"
#include "hadal/assets/scene_writer.h"
#include "hadal/geometry/mesh_import.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::rpy;
using testing::SensorTestWorld;

constexpr double kAltitude = 10.0;  // camera above the plane seabed [m]
// Looking straight down: x_S down.
const Eigen::Isometry3d kX_BS = pose(Eigen::Vector3d::Zero(), rpy(0.0, EIGEN_PI / 2.0, 0.0));

// A world with the vehicle 10 m above a plane seabed, clear water (absorption only), no daylight, and one
// light at the camera pointing down (40 deg beam).
Model lit_world(double scattering_per_m = 0.0) {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -100.0 + kAltitude));
  model.world.optics.water.absorption_per_m = render::Rgb(0.05, 0.03, 0.02);
  model.world.optics.water.scattering_per_m = render::Rgb::Constant(scattering_per_m);
  model.world.optics.seabed_albedo = Eigen::Array3d(0.5, 0.4, 0.3);
  LightSpec light;
  light.name = "lamp";
  light.X_LF = kX_BS;  // at the camera, beam along x_S
  light.inner_half_angle = 40.0 * kDegToRad;
  light.outer_half_angle = 45.0 * kDegToRad;
  light.intensity_W_per_sr = Eigen::Array3d::Constant(2000.0);
  model.vehicles[0].lights = {light};
  return model;
}

CameraSensor::Spec camera_spec(bool noise) {
  CameraSensor::Spec spec;
  CameraSensor::set_lens(spec, render::lens_from_horizontal_fov(161, 121, 60.0 * kDegToRad));
  spec.sensor.sensitivity = Eigen::Array3d::Constant(2.0e5);
  spec.sensor.exposure_s = 0.01;
  spec.sensor.gain_dn_per_e = 0.05;
  spec.sensor.shot_noise = noise;
  spec.sensor.read_noise_e = noise ? 3.0 : 0.0;
  spec.sensor.vignetting = false;
  return spec;
}

// One frame of the vehicle's camera at the world's state, rendered on a 2-worker ray-cast service.
CameraSensor::Capture capture(SensorTestWorld& world, const CameraSensor::Spec& spec, const CameraSensor::State& state,
                              std::uint64_t step = 0) {
  return testing::capture<CameraSensor>(world, spec, state, kX_BS, step);
}

// Looking straight down on the plane: depth = altitude at every pixel (float rays: 1e-4 m); the centre
// pixel's counts are the Lambertian closed form through the sensor without noise:
//   DN = round(gain * sensitivity * exposure * albedo / pi * I / d^2 * exp(-2 c d))  (117, 140, 128 here).
TEST(CameraSensorTest, DownwardFrameFollowsTheClosedForms) {
  SensorTestWorld world(lit_world(), true);
  const CameraSensor::Spec spec = camera_spec(false);
  const CameraSensor::State state = world.initial_state<CameraSensor>(spec, 10.0, "cam");
  const CameraSensor::Capture frame = capture(world, spec, state);
  ASSERT_EQ(frame.depth_m.size(), 161u * 121u);
  ASSERT_EQ(frame.image.size(), 3u * 161u * 121u);
  for (float z : frame.depth_m) ASSERT_NEAR(z, kAltitude, 1e-4);
  const std::size_t centre = 60u * 161u + 80u;
  const LightSpec& light = world.model.vehicles[0].lights[0];
  const OpticsSpec& optics = world.model.world.optics;
  for (int ch = 0; ch < 3; ++ch) {
    const double L = optics.seabed_albedo[ch] / kPi * light.intensity_W_per_sr[ch] / (kAltitude * kAltitude) *
                     std::exp(-2.0 * optics.water.attenuation_per_m()[ch] * kAltitude);
    const double dn = std::round(0.05 * 2.0e5 * 0.01 * L);
    EXPECT_GT(dn, 100.0);
    EXPECT_EQ(frame.image[3 * centre + ch], static_cast<std::uint8_t>(dn)) << "channel " << ch << ", L " << L;
  }
}

// Same seed and capture step: the same image; another step draws other noise. With the seabed beyond
// the far clip the camera looks into open water: black in clear water, lit by backscatter when the
// water scatters.
TEST(CameraSensorTest, NoiseIsSeededPerFrameAndOpenWaterShowsBackscatter) {
  SensorTestWorld world(lit_world(), true);
  const CameraSensor::Spec spec = camera_spec(true);
  const CameraSensor::State state = world.initial_state<CameraSensor>(spec, 10.0, "cam");
  const CameraSensor::Capture a = capture(world, spec, state, 5);
  EXPECT_EQ(a.image, capture(world, spec, state, 5).image);
  EXPECT_NE(a.image, capture(world, spec, state, 6).image);

  CameraSensor::Spec short_sighted = camera_spec(false);
  short_sighted.far_clip = 5.0;
  const std::size_t centre = 60u * 161u + 80u;
  const CameraSensor::Capture clear_water = capture(world, short_sighted, state);
  EXPECT_TRUE(std::isnan(clear_water.depth_m[centre]));
  for (std::uint8_t count : clear_water.image) ASSERT_EQ(count, 0);
  SensorTestWorld turbid(lit_world(0.2), true);
  const CameraSensor::Capture turbid_water = capture(turbid, short_sighted, state);
  for (int ch = 0; ch < 3; ++ch) EXPECT_GT(turbid_water.image[3 * centre + ch], 0) << ch;
}

// The light rides on the camera's vehicle: its backscatter table is made for the first frame and kept
// (render::BackscatterTableCache), whatever the vehicle's pose; a frame rendered with the kept table is
// the same as the first one.
TEST(CameraSensorTest, BackscatterTableOfOwnLightsIsMadeOnce) {
  SensorTestWorld world(lit_world(0.2), true);
  CameraSensor::Spec spec = camera_spec(false);
  spec.far_clip = 5.0;
  const CameraSensor::State state = world.initial_state<CameraSensor>(spec, 10.0, "cam");
  const CameraSensor::Capture first = capture(world, spec, state, 1);
  ASSERT_NE(spec.backscatter_cache, nullptr);
  EXPECT_EQ(spec.backscatter_cache->tables_made(), 1u);
  world.state.vehicles[0].body.X_WB = pose(Eigen::Vector3d(3.0, -2.0, -95.0), rpy(0.1, 0.2, 0.3));
  capture(world, spec, state, 2);
  world.state.vehicles[0].body.X_WB = pose(Eigen::Vector3d(0.0, 0.0, -100.0 + kAltitude), rpy(0.0, 0.0, 0.0));
  EXPECT_EQ(capture(world, spec, state, 1).image, first.image);
  EXPECT_EQ(spec.backscatter_cache->tables_made(), 1u);
}

// A link mesh with two glTF materials (a red and a blue plate) as the camera sees it: rays cast through
// the world scene hit triangles whose material code names the link and the mesh material, and the
// albedo is that material's base colour factor; a YAML appearance albedo on the link wins over it; the
// seabed is the seabed's albedo.
TEST(CameraSensorTest, GltfBaseColourIsTheAlbedoOfAMeshedLink) {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -90.0));
  LinkSpec target;
  target.name = "target";
  target.mass = 1.0;
  auto mesh = std::make_shared<geometry::TriangleMesh>();
  // Two 1 m plates facing +x at x = 5 m: material 0 at y in [0, 1], material 1 at y in [-1, 0].
  mesh->positions = {5, 0, -0.5, 5, 1, -0.5, 5, 1, 0.5, 5, 0, 0.5, 5, -1, -0.5, 5, 0, -0.5, 5, 0, 0.5, 5, -1, 0.5};
  mesh->indices = {0, 2, 1, 0, 3, 2, 4, 6, 5, 4, 7, 6};
  mesh->triangle_materials = {0, 0, 1, 1};
  mesh->materials.resize(2);
  mesh->materials[0].base_color = {0.9f, 0.1f, 0.1f, 1.0f};
  mesh->materials[1].base_color = {0.1f, 0.2f, 0.9f, 1.0f};
  LinkMesh link_mesh;
  link_mesh.mesh = mesh;
  target.mesh = link_mesh;
  model.vehicles[0].links.push_back(target);
  const geometry::TriangleMesh surface = geometry::vehicle_surface_B(model.vehicles[0]);
  ASSERT_EQ(surface.triangle_materials.back(), geometry::link_material(1, 1));

  geometry::EmbreeScene scene = geometry::build_world_scene(model);
  scene.build();
  const std::vector<Eigen::Isometry3d> X_WB = {model.vehicles[0].X_WB_initial};
  scene.set_body_poses(X_WB);
  geometry::RayBatch rays;
  const Eigen::Vector3f from(0.0f, 0.0f, -90.0f);
  rays.add_ray(from, Eigen::Vector3f(5.0f, 0.5f, 0.0f).normalized());   // red plate
  rays.add_ray(from, Eigen::Vector3f(5.0f, -0.5f, 0.0f).normalized());  // blue plate
  rays.add_ray(from, Eigen::Vector3f(0.0f, 0.0f, -1.0f));                // seabed
  geometry::RayHits hits;
  hits.resize(rays.size());
  scene.intersect(rays, 0, rays.size(), geometry::QueryPath::kSingle, hits);
  const geometry::RayBodies bodies(model);
  const auto albedo = [&](std::size_t i) {
    const Eigen::Vector3d p = from.cast<double>() + hits.distance[i] * Eigen::Vector3d(rays.d_W_x[i], rays.d_W_y[i], rays.d_W_z[i]);
    return surface_albedo(model, bodies, X_WB, render::SurfacePoint{hits.material[i], hits.body[i], p, hits.tex_u[i], hits.tex_v[i]});
  };
  ASSERT_TRUE(hits.hit(0) && hits.hit(1) && hits.hit(2));
  EXPECT_TRUE(albedo(0).isApprox(Eigen::Array3d(0.9, 0.1, 0.1), 1e-6)) << albedo(0).transpose();
  EXPECT_TRUE(albedo(1).isApprox(Eigen::Array3d(0.1, 0.2, 0.9), 1e-6)) << albedo(1).transpose();
  EXPECT_TRUE(albedo(2).isApprox(model.world.optics.seabed_albedo)) << albedo(2).transpose();
  model.vehicles[0].links[1].appearance.albedo = Eigen::Array3d(0.5, 0.5, 0.5);
  EXPECT_TRUE(albedo(0).isApprox(Eigen::Array3d(0.5, 0.5, 0.5)));
}

// A link whose mesh is a real GLB (the asset tools' textured quad: a 1 m quad, texture coordinates over
// [0, 1]^2, base colour factor (1, 0.5, 0.25) times an 8 x 4 test texture), imported as a scenario
// would: a ray's hit samples the texture at the hit's texture coordinates, sRGB-decoded, times the
// factor. Rays aimed at texel centres see that texel exactly (bilinear weights 1 and 0, to float
// rounding: 1e-5).
TEST(CameraSensorTest, GltfBaseColourTextureIsSampledAtTheHit) {
  const std::string dir = ::testing::TempDir() + "/camera_texture_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/quad.glb";
  ASSERT_EQ(assets::write_scene(assets::textured_quad_scene(8, 4), path), "");
  const geometry::ImportResult imported = geometry::import_mesh(path);
  ASSERT_TRUE(imported.mesh) << imported.error;
  ASSERT_EQ(imported.mesh->textures.size(), 1u);

  Model model = testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -90.0));
  LinkSpec target;
  target.name = "target";
  target.mass = 1.0;
  // The quad (in the xy-plane, facing +z) stood up 5 m ahead, facing the vehicle: x_L = -z_M.
  target.X_BL = pose(Eigen::Vector3d(5.0, 0.0, 0.0), rpy(0.0, -EIGEN_PI / 2.0, 0.0));
  LinkMesh link_mesh;
  link_mesh.mesh = std::make_shared<geometry::TriangleMesh>(*imported.mesh);
  target.mesh = link_mesh;
  model.vehicles[0].links.push_back(target);
  geometry::EmbreeScene scene = geometry::build_world_scene(model);
  scene.build();
  const std::vector<Eigen::Isometry3d> X_WB = {model.vehicles[0].X_WB_initial};
  scene.set_body_poses(X_WB);

  const Eigen::Isometry3d X_WL = X_WB[0] * target.X_BL;
  const Eigen::Vector3f from(0.0f, 0.0f, -90.0f);
  geometry::RayBatch rays;
  std::vector<std::pair<int, int>> texels;
  for (int row = 0; row < 4; ++row) {
    for (int column = 0; column < 8; ++column) {
      // Texel (column, row)'s centre: u = (column + 1/2) / 8, v = 1 - (row + 1/2) / 4; on the quad
      // p_M = (u - 1/2, v - 1/2, 0).
      const double u = (column + 0.5) / 8.0, v = 1.0 - (row + 0.5) / 4.0;
      const Eigen::Vector3d p_W = X_WL * Eigen::Vector3d(u - 0.5, v - 0.5, 0.0);
      rays.add_ray(from, (p_W.cast<float>() - from).normalized());
      texels.emplace_back(column, row);
    }
  }
  geometry::RayHits hits;
  hits.resize(rays.size());
  scene.intersect(rays, 0, rays.size(), geometry::QueryPath::kAuto, hits);
  const Eigen::Array3d factor(1.0, 0.5, 0.25);
  const geometry::RayBodies bodies(model);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_TRUE(hits.hit(i));
    const Eigen::Vector3d p = from.cast<double>() + hits.distance[i] * Eigen::Vector3d(rays.d_W_x[i], rays.d_W_y[i], rays.d_W_z[i]);
    const Eigen::Array3d albedo =
        surface_albedo(model, bodies, X_WB, render::SurfacePoint{hits.material[i], hits.body[i], p, hits.tex_u[i], hits.tex_v[i]});
    const auto rgb = assets::test_texture_pixel(texels[i].first, texels[i].second);
    const Eigen::Array3d expected = factor * Eigen::Array3d(render::srgb_to_linear(rgb[0] / 255.0),
                                                            render::srgb_to_linear(rgb[1] / 255.0),
                                                            render::srgb_to_linear(rgb[2] / 255.0));
    EXPECT_TRUE(((albedo - expected).abs() < 1e-5).all())
        << "texel " << texels[i].first << ", " << texels[i].second << ": " << albedo.transpose() << " vs "
        << expected.transpose();
  }
  std::filesystem::remove_all(dir);
}

TEST(CameraSensorTest, Messages) {
  SensorTestWorld world(lit_world(), true);
  CameraSensor::Spec spec = camera_spec(false);
  CameraSensor::State state = world.initial_state<CameraSensor>(spec, 10.0, "cam");
  const std::string frame_id = "auv/cam";
  const MessageHeader header{12.5, frame_id, 10.0};
  CameraSensor::Capture frame = capture(world, spec, state);
  state.image = frame.image;  // what deliver() does (the simulation's tests cover it)
  state.depth_m = frame.depth_m;

  sensor_msgs::msg::Image image;
  CameraSensor::ImageRawTopic::fill(spec, state, header, image);
  EXPECT_EQ(image.header().frame_id(), "auv/cam_optical");
  EXPECT_EQ(image.header().stamp().sec(), 12);
  EXPECT_EQ(image.header().stamp().nanosec(), 500000000u);
  EXPECT_EQ(image.width(), 161u);
  EXPECT_EQ(image.height(), 121u);
  EXPECT_EQ(image.encoding(), "rgb8");
  EXPECT_EQ(image.step(), 3u * 161u);
  EXPECT_EQ(image.data(), state.image);

  sensor_msgs::msg::Image depth;
  CameraSensor::DepthTopic::fill(spec, state, header, depth);
  EXPECT_EQ(depth.encoding(), "32FC1");
  EXPECT_EQ(depth.step(), 4u * 161u);
  ASSERT_EQ(depth.data().size(), 4u * 161u * 121u);
  float z = 0.0f;
  std::memcpy(&z, depth.data().data() + 4 * (60 * 161 + 80), 4);
  EXPECT_NEAR(z, kAltitude, 1e-4);

  sensor_msgs::msg::CameraInfo info;
  CameraSensor::CameraInfoTopic::fill(spec, state, header, info);
  EXPECT_EQ(info.distortion_model(), "plumb_bob");
  EXPECT_EQ(info.d(), spec.lens->D());
  EXPECT_EQ(info.k(), spec.lens->K());
  EXPECT_EQ(info.p(), spec.lens->P());
  EXPECT_EQ(info.width(), 161u);

  // mono8: the luma of the same counts.
  CameraSensor::Spec mono = spec;
  mono.mono = true;
  CameraSensor::State mono_state = state;
  mono_state.image = capture(world, mono, mono_state).image;
  ASSERT_EQ(mono_state.image.size(), 161u * 121u);
  const std::size_t centre = 60u * 161u + 80u;
  EXPECT_EQ(mono_state.image[centre], static_cast<std::uint8_t>(std::lround(
                                          0.299 * state.image[3 * centre] + 0.587 * state.image[3 * centre + 1] +
                                          0.114 * state.image[3 * centre + 2])));
  sensor_msgs::msg::Image mono_image;
  CameraSensor::ImageRawTopic::fill(mono, mono_state, header, mono_image);
  EXPECT_EQ(mono_image.encoding(), "mono8");
  EXPECT_EQ(mono_image.step(), 161u);
}

}  // namespace
}  // namespace hadal::sensors
