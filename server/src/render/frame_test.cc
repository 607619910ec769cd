// Frames rendered with real Embree against closed forms: the Lambertian wall ratio, a shadow
// where geometry puts it, backscatter in open water, and determinism.
#include "hadal/render/frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <atomic>
#include <functional>
#include <thread>
#include <cstring>
#include <limits>

#include "hadal/core/units.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/render/camera_rays.h"
#include "render_test_support.h"

namespace hadal::render {
namespace {

using geometry::EmbreeScene;
using geometry::TriangleMesh;

using testing::plate;

// A lens with its principal point on pixel (320, 240), so that pixel's ray is the optical axis.
Lens centred_lens() {
  LensSpec spec = lens_from_horizontal_fov(641, 481, 60.0 * kDegToRad);
  return make_lens(spec);
}

Rgb white(const SurfacePoint&) { return Rgb::Ones(); }

std::size_t centre(const Lens& lens) { return static_cast<std::size_t>(240) * lens.width_px() + 320; }

// The determinism tests' scene: a wall 6 m ahead, off-centre; `with_plate` adds a small plate at 3 m
// that shadows it.
EmbreeScene wall_scene(bool with_plate = false) {
  EmbreeScene scene;
  scene.add_static_mesh(plate(6.0f, 0.5f, 0.3f, 2.0f), 0, "wall");
  if (with_plate) scene.add_static_mesh(plate(3.0f, 0.2f, 0.0f, 0.3f), 1, "plate");
  scene.build();
  return scene;
}

// Radiance and depth bit for bit.
void expect_same_frame(const RadianceFrame& a, const RadianceFrame& b) {
  ASSERT_EQ(a.radiance.size(), b.radiance.size());
  ASSERT_EQ(a.depth_m.size(), b.depth_m.size());
  EXPECT_EQ(std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(Rgb)), 0);
  EXPECT_EQ(std::memcmp(a.depth_m.data(), b.depth_m.data(), a.depth_m.size() * sizeof(float)), 0);
}

// Issue 11: a white Lambertian wall facing a co-located light and camera; the centre pixel's ratio at
// two distances is (d1/d2)^2 exp(-2 c (d2 - d1)) per channel, within 2 %. Here without scattering (the
// formula has no backscatter term); float hit distances make it agree to ~1e-6.
TEST(FrameTest, WallRatioFollowsInverseSquareAndTwoWayAttenuation) {
  const Lens lens = centred_lens();
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.45, 0.12, 0.08);
  SpotLight light;  // at the camera (origin), along +x, 40 deg half-angle beam
  light.inner_half_angle_rad = 0.7;
  light.outer_half_angle_rad = 0.8;
  lighting.lights = {light};
  const Eigen::Isometry3d X_WC = X_SC();  // camera at the origin looking along +x
  Rgb L[2];
  const double d[2] = {2.0, 5.0};
  for (int k = 0; k < 2; ++k) {
    EmbreeScene scene;
    scene.add_static_mesh(plate(static_cast<float>(d[k]), 0, 0, 50), 0, "wall");
    scene.build();
    const RadianceFrame frame = render_radiance(scene, lens, X_WC, 0.1f, 100.0f, geometry::kNoHit, lighting, white);
    L[k] = frame.radiance[centre(lens)];
    EXPECT_NEAR(frame.depth_m[centre(lens)], d[k], 1e-5);
  }
  for (int ch = 0; ch < 3; ++ch) {
    const double expected = (d[0] / d[1]) * (d[0] / d[1]) * std::exp(-2.0 * lighting.water.absorption_per_m[ch] * (d[1] - d[0]));
    EXPECT_NEAR(L[1][ch] / L[0][ch], expected, 0.02 * expected) << ch;
    EXPECT_NEAR(L[1][ch] / L[0][ch], expected, 1e-5 * expected) << ch;  // what float arithmetic gives
  }
}

// A light 1 m left of the camera, a 0.4 m plate 3 m ahead and a wall at 8 m: the plate's shadow on the
// wall is centred where the line from the light through the plate's centre meets the wall. That point
// is dark (no scattering), a point as far on the other side is lit.
TEST(FrameTest, ShadowFallsWhereTheGeometryPutsIt) {
  const Lens lens = centred_lens();
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb::Constant(0.05);
  SpotLight light;
  light.p_WL = Eigen::Vector3d(0.0, 1.0, 0.0);  // y_W is left
  light.inner_half_angle_rad = 0.9;
  light.outer_half_angle_rad = 1.0;
  lighting.lights = {light};
  EmbreeScene scene;
  scene.add_static_mesh(plate(8.0f, 0, 0, 50), 0, "wall");
  scene.add_static_mesh(plate(3.0f, 0.2f, 0, 0.2f), 1, "plate");
  scene.build();
  const RadianceFrame frame = render_radiance(scene, lens, X_SC(), 0.1f, 100.0f, geometry::kNoHit, lighting, white);
  // Light (0, 1, 0) through the plate's centre (3, 0.2, 0) meets x = 8 at y = 1 - 0.8 * 8/3.
  const Eigen::Vector3d shadow_W(8.0, 1.0 - 0.8 * 8.0 / 3.0, 0.0);
  const Eigen::Vector3d lit_W(8.0, -shadow_W.y() + 2.0, 0.0);
  const auto pixel_of = [&](const Eigen::Vector3d& q_W) {
    Eigen::Vector2d uv;
    EXPECT_TRUE(project(lens.spec(), X_SC().inverse() * q_W, &uv));
    return static_cast<std::size_t>(std::lround(uv.y())) * lens.width_px() + static_cast<std::size_t>(std::lround(uv.x()));
  };
  EXPECT_NEAR(frame.depth_m[pixel_of(shadow_W)], 8.0, 1e-4);  // the camera sees the wall there
  EXPECT_TRUE((frame.radiance[pixel_of(shadow_W)] == 0.0).all());
  EXPECT_TRUE((frame.radiance[pixel_of(lit_W)] > 0.0).all());
}

// Open water: no hit, NaN depth, and the only light is backscatter, which grows with b.
TEST(FrameTest, OpenWaterShowsBackscatterOnly) {
  const Lens lens = make_lens(lens_from_horizontal_fov(64, 48, 1.0));
  EmbreeScene scene;
  scene.add_static_mesh(plate(-50.0f, 0, 0, 1), 0, "behind the camera");
  scene.build();
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.3, 0.05, 0.02);
  lighting.water.scattering_per_m = Rgb::Constant(0.02);
  SpotLight light;
  light.p_WL = Eigen::Vector3d(0.0, 0.5, 0.0);
  lighting.lights = {light};
  const RadianceFrame thin = render_radiance(scene, lens, X_SC(), 0.1f, 30.0f, geometry::kNoHit, lighting, white);
  lighting.water.scattering_per_m *= 3.0;
  const RadianceFrame thick = render_radiance(scene, lens, X_SC(), 0.1f, 30.0f, geometry::kNoHit, lighting, white);
  const std::size_t mid = static_cast<std::size_t>(24) * 64 + 32;
  EXPECT_TRUE(std::isnan(thin.depth_m[mid]));
  EXPECT_TRUE((thin.radiance[mid] > 0.0).all());
  EXPECT_TRUE((thick.radiance[mid] > 2.0 * thin.radiance[mid]).all());
}

// Daylight only (no lights): a seabed at 20 m is seen, the same scene at 2000 m is black (Jerlov type I
// Kd: the blue channel, the deepest-reaching, is down by exp(-0.019 * 2000) = 3e-17).
TEST(FrameTest, DaylightFadesToBlackWithDepth) {
  const Lens lens = make_lens(lens_from_horizontal_fov(80, 60, 1.2));
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.35, 0.06, 0.02);
  lighting.water.scattering_per_m = Rgb::Constant(0.01);
  lighting.daylight.surface_irradiance_W_per_m2 = Rgb(120.0, 150.0, 140.0);
  lighting.daylight.Kd_per_m = Rgb(0.36, 0.063, 0.019);
  double brightest[2] = {0.0, 0.0};
  const double depth[2] = {20.0, 2000.0};
  for (int k = 0; k < 2; ++k) {
    const float z = static_cast<float>(-depth[k]);
    EmbreeScene scene;
    TriangleMesh floor;
    floor.positions = {-100, -100, z - 3, 100, -100, z - 3, 100, 100, z - 3, -100, 100, z - 3};
    floor.indices = {0, 1, 2, 0, 2, 3};
    scene.add_static_mesh(floor, 0, "seabed");
    scene.build();
    Eigen::Isometry3d X_WS = Eigen::Isometry3d::Identity();
    X_WS.translation() = Eigen::Vector3d(0.0, 0.0, z);
    X_WS.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()));  // pitched down
    const RadianceFrame frame = render_radiance(scene, lens, X_WS * X_SC(), 0.1f, 500.0f, geometry::kNoHit, lighting, white);
    for (const Rgb& r : frame.radiance) brightest[k] = std::max(brightest[k], r.maxCoeff());
  }
  EXPECT_GT(brightest[0], 1.0);
  EXPECT_LT(brightest[1], 1e-12);
}

// Shadow rays the height-field test proves clear are not cast and change nothing: a bumpy seabed with
// a box floating over it (a body, casting shadows), two lights beside the camera and daylight; the
// frame with the seabed declared a height field is the frame without, bit for bit, from fewer rays.
TEST(FrameTest, ProvablyClearShadowRaysAreNotCastAndChangeNothing) {
  TriangleMesh seabed;
  const int n = 80;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float x = -20.0f + 0.5f * i, y = -20.0f + 0.5f * j;
      seabed.positions.insert(seabed.positions.end(), {x, y, -10.0f + 0.3f * std::sin(0.7f * x) * std::cos(0.5f * y)});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = static_cast<std::uint32_t>(j * (n + 1) + i), b = a + 1, c = a + n + 1, d = c + 1;
      seabed.indices.insert(seabed.indices.end(), {a, b, d, a, d, c});  // counter-clockwise from above
    }
  }
  TriangleMesh cube = plate(0.0f, 0.0f, 0.0f, 0.4f);  // a square plate on a body, tilted below
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.3, 0.06, 0.03);
  lighting.water.scattering_per_m = Rgb::Constant(0.05);
  lighting.daylight.surface_irradiance_W_per_m2 = Rgb(120.0, 150.0, 140.0);
  lighting.daylight.Kd_per_m = Rgb(0.36, 0.063, 0.019);
  lighting.daylight.surface_z_m = 5.0;
  for (double y : {-0.5, 0.5}) {
    SpotLight light;
    light.p_WL = Eigen::Vector3d(-3.0, y, -4.0);
    light.axis_W = Eigen::Vector3d(0.5, 0.0, -1.0).normalized();
    light.inner_half_angle_rad = 0.5;
    light.outer_half_angle_rad = 0.7;
    lighting.lights.push_back(light);
  }
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translate(Eigen::Vector3d(0.5, 0.2, -8.5));
  X_WB.rotate(Eigen::AngleAxisd(1.2, Eigen::Vector3d(0.3, 1.0, 0.2).normalized()));
  Eigen::Isometry3d X_WS = Eigen::Isometry3d::Identity();
  X_WS.translation() = Eigen::Vector3d(-3.0, 0.0, -4.0);
  X_WS.rotate(Eigen::AngleAxisd(0.9, Eigen::Vector3d::UnitY()));  // pitched down
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 1.3));
  RadianceFrame frames[2];
  for (int k = 0; k < 2; ++k) {
    EmbreeScene scene;
    scene.add_static_mesh(seabed, 0, "seabed", k == 0 ? geometry::StaticShape::kHeightField : geometry::StaticShape::kAny);
    scene.add_body_mesh(0, cube, 1, "plate");
    scene.build();
    scene.set_body_poses({X_WB});
    frames[k] = render_radiance(scene, lens, X_WS * X_SC(), 0.1f, 60.0f, geometry::kNoHit, lighting, white);
  }
  expect_same_frame(frames[0], frames[1]);
  EXPECT_LT(frames[0].shadow_rays, frames[1].shadow_rays / 2);
  // The plate shadows the seabed in this frame: seabed pixels (same depth without the plate) that are
  // darker with it; they are lit by whichever shadow rays were still cast.
  EmbreeScene bare;
  bare.add_static_mesh(seabed, 0, "seabed", geometry::StaticShape::kHeightField);
  bare.build();
  const RadianceFrame unshadowed = render_radiance(bare, lens, X_WS * X_SC(), 0.1f, 60.0f, geometry::kNoHit, lighting, white);
  std::size_t shadowed = 0;
  for (std::size_t i = 0; i < unshadowed.radiance.size(); ++i) {
    if (frames[0].depth_m[i] == unshadowed.depth_m[i] && frames[0].radiance[i].sum() < 0.8 * unshadowed.radiance[i].sum()) {
      ++shadowed;
    }
  }
  EXPECT_GT(shadowed, 100u);
}

TEST(FrameTest, SameInputsGiveTheSameFrame) {
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 1.2));
  const EmbreeScene scene = wall_scene();
  FrameLighting lighting;
  lighting.water.scattering_per_m = Rgb::Constant(0.05);
  lighting.lights = {SpotLight{}};
  const RadianceFrame a = render_radiance(scene, lens, X_SC(), 0.1f, 50.0f, geometry::kNoHit, lighting, white);
  const RadianceFrame b = render_radiance(scene, lens, X_SC(), 0.1f, 50.0f, geometry::kNoHit, lighting, white);
  expect_same_frame(a, b);
}

// Bands, backscatter rows and forward-scatter rows as tasks on two threads, or backwards on one: the same frame bit for bit
// (render/frame.h: a function of its inputs whatever the threads).
TEST(FrameTest, SameFrameWhateverTheThreads) {
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 1.2));
  const EmbreeScene scene = wall_scene(true);
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.3, 0.06, 0.03);
  lighting.water.scattering_per_m = Rgb::Constant(0.08);
  lighting.water.forward_scatter_max_angle_rad = 0.15;  // the spread's row tasks too
  SpotLight left, right;
  left.p_WL = Eigen::Vector3d(0.0, 0.4, 0.0);
  right.p_WL = Eigen::Vector3d(0.0, -0.4, 0.0);
  lighting.lights = {left, right};
  const RadianceFrame serial = render_radiance(scene, lens, X_SC(), 0.1f, 50.0f, geometry::kNoHit, lighting, white);
  const ParallelFor backwards = [](std::size_t count, const std::function<void(std::size_t)>& task) {
    for (std::size_t i = count; i-- > 0;) task(i);
  };
  const ParallelFor two_threads = [](std::size_t count, const std::function<void(std::size_t)>& task) {
    std::atomic<std::size_t> next{0};
    const auto work = [&] {
      for (std::size_t i = next++; i < count; i = next++) task(i);
    };
    std::thread helper(work);
    work();
    helper.join();
  };
  for (const ParallelFor& parallel : {backwards, two_threads}) {
    const RadianceFrame frame = render_radiance(scene, lens, X_SC(), 0.1f, 50.0f, geometry::kNoHit, lighting, white, parallel);
    expect_same_frame(frame, serial);
    EXPECT_EQ(frame.shadow_rays, serial.shadow_rays);
  }
  EXPECT_GT(serial.shadow_rays, 0u);
}

// A frame as scene work on the ray-cast workers (how a camera renders in the simulation): the same
// frame on 1 and 2 workers, and the same as on the test's own thread.
TEST(FrameTest, SameFrameOnTheRayCastWorkers) {
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 1.2));
  const EmbreeScene scene = wall_scene();
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.3, 0.06, 0.03);
  lighting.water.scattering_per_m = Rgb::Constant(0.08);
  lighting.lights = {SpotLight{}};
  const RadianceFrame here = render_radiance(scene, lens, X_SC(), 0.1f, 50.0f, geometry::kNoHit, lighting, white);
  for (int threads : {1, 2}) {
    geometry::RaycastService service(scene.view(), {threads});
    RadianceFrame frame;
    service.submit({}, [&](const EmbreeScene& posed, const ParallelFor& parallel) {
      frame = render_radiance(posed, lens, X_SC(), 0.1f, 50.0f, geometry::kNoHit, lighting, white, parallel);
    }).get();
    SCOPED_TRACE(threads);
    expect_same_frame(frame, here);
  }
}

// A camera whose lights ride with it keeps its backscatter table (BackscatterTableCache): the cache
// makes one table for the same inputs and a new one when a light moves relative to the camera, and a
// frame given the kept table is the frame that makes its own (bit for bit), here with the camera posed
// away from the world origin (the table lives in the camera frame).
TEST(FrameTest, KeptBackscatterTableGivesTheSameFrame) {
  const auto lens = std::make_shared<const Lens>(make_lens(lens_from_horizontal_fov(160, 120, 1.2)));
  const EmbreeScene scene = wall_scene();
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.3, 0.06, 0.03);
  lighting.water.scattering_per_m = Rgb::Constant(0.08);
  Eigen::Isometry3d X_WC = X_SC();
  X_WC.pretranslate(Eigen::Vector3d(0.5, -0.25, 0.125));
  std::vector<SpotLight> lights_C(2);
  lights_C[0].p_WL = Eigen::Vector3d(0.5, 0.0, 0.0);
  lights_C[1].p_WL = Eigen::Vector3d(-0.5, 0.0, 0.0);
  lights_C[0].axis_W = lights_C[1].axis_W = Eigen::Vector3d::UnitZ();
  for (const SpotLight& light : lights_C) {
    SpotLight world = light;
    world.p_WL = X_WC * light.p_WL;
    world.axis_W = X_WC.linear() * light.axis_W;
    lighting.lights.push_back(world);
  }
  // render_radiance's own table: the world lights taken into the camera frame, which rounds; the kept
  // table from lights_C made the same way so that the two frames can be compared bit for bit.
  std::vector<SpotLight> lights_C_as_rendered = lighting.lights;
  for (SpotLight& light : lights_C_as_rendered) {
    light.p_WL = X_WC.inverse() * light.p_WL;
    light.axis_W = X_WC.inverse().linear() * light.axis_W;
  }
  const RadianceFrame own = render_radiance(scene, *lens, X_WC, 0.1f, 50.0f, geometry::kNoHit, lighting, white);

  BackscatterTableCache cache;
  const auto table = cache.get(lighting, lights_C_as_rendered, lens, 0.1f, 50.0f, serial_for);
  ASSERT_NE(table, nullptr);
  EXPECT_EQ(cache.get(lighting, lights_C_as_rendered, lens, 0.1f, 50.0f, serial_for), table);
  EXPECT_EQ(cache.tables_made(), 1u);
  FrameLighting with_table = lighting;
  with_table.backscatter = table;
  expect_same_frame(render_radiance(scene, *lens, X_WC, 0.1f, 50.0f, geometry::kNoHit, with_table, white), own);

  // The exact camera-frame lights give a table within float rounding of it: the same picture.
  const auto exact = cache.get(lighting, lights_C, lens, 0.1f, 50.0f, serial_for);
  EXPECT_EQ(cache.tables_made(), lights_C[0].p_WL == lights_C_as_rendered[0].p_WL ? 1u : 2u);
  with_table.backscatter = exact;
  const RadianceFrame from_exact = render_radiance(scene, *lens, X_WC, 0.1f, 50.0f, geometry::kNoHit, with_table, white);
  for (std::size_t i = 0; i < own.radiance.size(); ++i) {
    ASSERT_NEAR((from_exact.radiance[i] - own.radiance[i]).abs().maxCoeff(), 0.0, 1e-5 * own.radiance[i].maxCoeff() + 1e-12);
  }
  // A light moved relative to the camera, another far clip, another water: new tables.
  std::vector<SpotLight> moved = lights_C;
  moved[1].p_WL.x() = -0.75;
  const std::size_t made = cache.tables_made();
  EXPECT_NE(cache.get(lighting, moved, lens, 0.1f, 50.0f, serial_for), exact);
  EXPECT_NE(cache.get(lighting, moved, lens, 0.1f, 40.0f, serial_for), nullptr);
  FrameLighting clearer = lighting;
  clearer.water.scattering_per_m = Rgb::Constant(0.02);
  EXPECT_NE(cache.get(clearer, moved, lens, 0.1f, 40.0f, serial_for), nullptr);
  EXPECT_EQ(cache.tables_made(), made + 3);
  // No scattering: no table.
  clearer.water.scattering_per_m = Rgb::Zero();
  EXPECT_EQ(cache.get(clearer, moved, lens, 0.1f, 40.0f, serial_for), nullptr);
}

}  // namespace
}  // namespace hadal::render
