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
  EXPECT_EQ(std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(Rgbf)), 0);
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
    L[k] = frame.radiance[centre(lens)].cast<double>();
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
    for (const Rgbf& r : frame.radiance) brightest[k] = std::max(brightest[k], static_cast<double>(r.maxCoeff()));
  }
  EXPECT_GT(brightest[0], 1.0);
  EXPECT_LT(brightest[1], 1e-12);
}

// A bumpy seabed around z = -10 over [-20, 20] m at 0.5 m spacing, two triangles per cell facing up;
// with `ridge`, the ground beyond x = 15 climbs 8 m in 5 m (slope 1.6), out of the tests' view.
TriangleMesh bumpy_seabed(bool ridge) {
  TriangleMesh seabed;
  const int n = 80;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float x = -20.0f + 0.5f * i, y = -20.0f + 0.5f * j;
      const float rise = ridge ? 1.6f * std::clamp(x - 15.0f, 0.0f, 5.0f) : 0.0f;
      seabed.positions.insert(seabed.positions.end(), {x, y, -10.0f + 0.3f * std::sin(0.7f * x) * std::cos(0.5f * y) + rise});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = static_cast<std::uint32_t>(j * (n + 1) + i), b = a + 1, c = a + n + 1, d = c + 1;
      seabed.indices.insert(seabed.indices.end(), {a, b, d, a, d, c});  // counter-clockwise from above
    }
  }
  return seabed;
}

// The shadow tests' lighting: oceanic water, daylight from a surface 5 m above, two lights beside a
// camera 6 m above the seabed, aimed down and forward.
FrameLighting seabed_lighting() {
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
  return lighting;
}

// The shadow tests' camera: 6 m above the seabed, pitched down; and the pose of the plate body that
// floats over the seabed in its view, tilted.
Eigen::Isometry3d seabed_camera() {
  Eigen::Isometry3d X_WS = Eigen::Isometry3d::Identity();
  X_WS.translation() = Eigen::Vector3d(-3.0, 0.0, -4.0);
  X_WS.rotate(Eigen::AngleAxisd(0.9, Eigen::Vector3d::UnitY()));
  return X_WS * X_SC();
}

Eigen::Isometry3d floating_plate_pose() {
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translate(Eigen::Vector3d(0.5, 0.2, -8.5));
  X_WB.rotate(Eigen::AngleAxisd(1.2, Eigen::Vector3d(0.3, 1.0, 0.2).normalized()));
  return X_WB;
}

// Shadow rays the height-field test proves clear are not cast and change nothing: a bumpy seabed with
// a steep ridge out of view (its slope, 1.6, would prove no light's ray clear: the test takes the
// slope of the ground under the band's rays, render/frame.h), a plate body floating over it casting
// shadows, two lights beside the camera and daylight; the frame with the seabed declared a height
// field is the frame without, bit for bit, from fewer rays.
TEST(FrameTest, ProvablyClearShadowRaysAreNotCastAndChangeNothing) {
  const TriangleMesh seabed = bumpy_seabed(true);
  const TriangleMesh cube = plate(0.0f, 0.0f, 0.0f, 0.4f);  // a square plate on a body, tilted below
  const FrameLighting lighting = seabed_lighting();
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 1.3));
  RadianceFrame frames[2];
  for (int k = 0; k < 2; ++k) {
    EmbreeScene scene;
    scene.add_static_mesh(seabed, 0, "seabed", k == 0 ? geometry::StaticShape::kHeightField : geometry::StaticShape::kAny);
    scene.add_body_mesh(0, cube, 1, "plate");
    scene.build();
    scene.set_body_poses({floating_plate_pose()});
    if (k == 0) {
      EXPECT_GT(*scene.static_height_field_max_slope(), 1.6);  // the ridge, and the bumps on it
    }
    frames[k] = render_radiance(scene, lens, seabed_camera(), 0.1f, 60.0f, geometry::kNoHit, lighting, white);
  }
  expect_same_frame(frames[0], frames[1]);
  EXPECT_LT(frames[0].shadow_rays, frames[1].shadow_rays / 4);
  // The plate shadows the seabed in this frame: seabed pixels (same depth without the plate) that are
  // darker with it; they are lit by whichever shadow rays were still cast.
  EmbreeScene bare;
  bare.add_static_mesh(seabed, 0, "seabed", geometry::StaticShape::kHeightField);
  bare.build();
  const RadianceFrame unshadowed = render_radiance(bare, lens, seabed_camera(), 0.1f, 60.0f, geometry::kNoHit, lighting, white);
  std::size_t shadowed = 0;
  for (std::size_t i = 0; i < unshadowed.radiance.size(); ++i) {
    if (frames[0].depth_m[i] == unshadowed.depth_m[i] && frames[0].radiance[i].sum() < 0.8f * unshadowed.radiance[i].sum()) {
      ++shadowed;
    }
  }
  EXPECT_GT(shadowed, 100u);
}

// The frame's single-precision passes against render/optics.h's per-ray physics in double precision,
// pixel by pixel: the same rays cast one at a time, each light's candidate test and shadow ray, the
// Lambertian and daylight terms, the backscatter table's value and daylight's path radiance. A
// patterned albedo, a body and shadows on the seabed. Within 1e-4 of the pixel's radiance plus 1e-6 of
// the frame's brightest (single precision's rounding over a few dozen operations, and the table's
// float log: ~1e-6); a pixel whose shadow ray grazes an edge may go either way in single precision,
// so up to 0.2 % of the pixels may differ by more.
TEST(FrameTest, MatchesThePerPixelPhysicsInDoublePrecision) {
  const TriangleMesh seabed = bumpy_seabed(false);
  EmbreeScene scene;
  scene.add_static_mesh(seabed, 0, "seabed", geometry::StaticShape::kHeightField);
  scene.add_body_mesh(0, plate(0.0f, 0.0f, 0.0f, 0.4f), 1, "plate");
  scene.build();
  scene.set_body_poses({floating_plate_pose()});
  const FrameLighting lighting = seabed_lighting();
  const auto albedo = [](const SurfacePoint& hit) {
    return hit.body == 0 ? Rgb(0.9, 0.2, 0.1) : Rgb(0.5 + 0.3 * std::sin(2.0 * hit.p_W.x()), 0.4, 0.3 + 0.2 * std::cos(hit.p_W.y()));
  };
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 1.3));
  const Eigen::Isometry3d X_WC = seabed_camera();
  const float near_clip = 0.1f, far_clip = 60.0f;
  const RadianceFrame frame = render_radiance(scene, lens, X_WC, near_clip, far_clip, geometry::kNoHit, lighting, albedo);

  std::vector<SpotLight> lights_C = lighting.lights;
  for (SpotLight& light : lights_C) {
    light.p_WL = X_WC.inverse() * light.p_WL;
    light.axis_W = X_WC.linear().transpose() * light.axis_W;
  }
  const auto table = make_backscatter_table(lighting, lights_C, lens, near_clip, far_clip, serial_for);
  ASSERT_TRUE(table);
  const Rgb c = lighting.water.attenuation_per_m();
  const Daylight& sun = lighting.daylight;
  const Rgb E_camera = sun.irradiance_at(static_cast<float>(X_WC.translation().z()));
  const auto blocked = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& to_unit, double length) {
    geometry::RayBatch one;
    one.add_ray(from.cast<float>(), to_unit.cast<float>(), 0.0f, static_cast<float>(length));
    std::vector<std::uint8_t> out(1);
    scene.occluded(one, 0, 1, out);
    return out[0] != 0;
  };
  float brightest = 0.0f;
  for (const Rgbf& L : frame.radiance) brightest = std::max(brightest, L.maxCoeff());
  std::size_t checked = 0, outliers = 0, lit = 0;
  for (int v = 0; v < lens.height_px(); v += 3) {
    for (int u = 0; u < lens.width_px(); u += 3) {
      const std::size_t i = static_cast<std::size_t>(v) * lens.width_px() + u;
      geometry::RayBatch ray;
      const Eigen::Vector3f d_f = (X_WC.linear().cast<float>() * lens.ray_C(u, v)).normalized();
      ray.add_ray(X_WC.translation().cast<float>(), d_f, near_clip, far_clip);
      geometry::RayHits hit;
      hit.resize(1);
      scene.intersect(ray, 0, 1, geometry::QueryPath::kSingle, hit);
      const Eigen::Vector3d o = X_WC.translation().cast<float>().cast<double>(), d = d_f.cast<double>();
      Rgb expected = Rgb::Zero();
      double s_end = far_clip;
      if (hit.hit(0)) {
        s_end = hit.distance[0];
        const Eigen::Vector3d p = o + s_end * d;
        Eigen::Vector3d n(hit.n_W_x[0], hit.n_W_y[0], hit.n_W_z[0]);
        if (n.dot(d) > 0.0) n = -n;
        const Rgb a = albedo(SurfacePoint{hit.material[0], hit.body[0], p, hit.tex_u[0], hit.tex_v[0]});
        const Eigen::Vector3d origin = p + lighting.shadow_bias_m * n;
        for (const SpotLight& spot : lighting.lights) {
          const LightBeam beam(spot);
          const Eigen::Vector3d to_light = spot.p_WL - origin;
          const double distance = to_light.norm();
          if (!(distance > lighting.shadow_bias_m) || n.dot(to_light) <= 0.0) continue;
          if (-spot.axis_W.dot(to_light) <= beam.cos_outer * distance) continue;
          if (blocked(origin, to_light / distance, distance - lighting.shadow_bias_m)) continue;
          expected += lambertian_radiance(a, beam, p, n, c, s_end);
          ++lit;
        }
        if (n.z() > -1.0 && !blocked(origin, Eigen::Vector3d::UnitZ(), std::max(0.0, sun.surface_z_m - p.z()))) {
          expected += daylight_surface_radiance(a, sun, p, n, c, s_end);
        }
      }
      expected += table->at(u, v, s_end);
      expected += daylight_path_radiance(lighting.water, sun, E_camera, o, d, static_cast<double>(near_clip), s_end);  // s0: the near clip
      expected += surface_from_below_radiance(lighting.water, sun, o, d, s_end);
      const Rgb got = frame.radiance[i].cast<double>();
      ++checked;
      if (((got - expected).abs() > 1e-4 * expected.abs() + 1e-6 * brightest).any()) ++outliers;
    }
  }
  EXPECT_GT(lit, checked / 2);  // most of the view is lit by the lights
  EXPECT_LE(outliers, checked / 500) << outliers << " of " << checked;
}

// Negligible daylight (frame.h): given a negligible radiance F, daylight is left out of the bands where
// its bound is below F / 2, and no pixel differs from the exact frame by F or more. F = 0 computes it
// everywhere (the exact frame, bit for bit), a huge F nowhere (the frame without daylight, bit for bit),
// and F around daylight's own largest share leaves it out of some bands only. Murky water (forward
// scatter carries more light than the unscattered beam: b_f d > 1) and a shallow camera (bright path
// radiance), so that each of the bound's terms matters.
TEST(FrameTest, NegligibleDaylightChangesNoPixelByTheNegligibleRadiance) {
  EmbreeScene scene;
  scene.add_static_mesh(bumpy_seabed(false), 0, "seabed", geometry::StaticShape::kHeightField);
  scene.add_body_mesh(0, plate(0.0f, 0.0f, 0.0f, 0.4f), 1, "plate");
  scene.build();
  scene.set_body_poses({floating_plate_pose()});
  const auto albedo = [](const SurfacePoint& hit) {
    return hit.body == 0 ? Rgb(0.9, 0.8, 0.7) : Rgb(0.3 + 0.2 * std::sin(2.0 * hit.p_W.x()), 0.4, 0.2 + 0.1 * std::cos(hit.p_W.y()));
  };
  FrameLighting lighting = seabed_lighting();
  lighting.water.scattering_per_m = Rgb::Constant(0.4);
  lighting.water.forward_scatter_max_angle_rad = 0.5;
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 1.3));
  const auto render = [&](const FrameLighting& l) {
    return render_radiance(scene, lens, seabed_camera(), 0.1f, 60.0f, geometry::kNoHit, l, albedo);
  };
  const auto largest_difference = [](const RadianceFrame& a, const RadianceFrame& b) {
    Rgb largest = Rgb::Zero();
    for (std::size_t i = 0; i < a.radiance.size(); ++i) {
      largest = largest.max((a.radiance[i] - b.radiance[i]).abs().cast<double>());
    }
    return largest;
  };
  const RadianceFrame exact = render(lighting);
  FrameLighting dark = lighting;
  dark.daylight.surface_irradiance_W_per_m2 = Rgb::Zero();
  const RadianceFrame without = render(dark);
  const Rgb daylight = largest_difference(exact, without);  // daylight's largest share of a pixel
  ASSERT_TRUE((daylight > 0.0).all());

  for (const Rgb& bad : {Rgb(-1e-3, 0.0, 0.0), Rgb(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0)}) {
    lighting.negligible_radiance_W_per_m2_sr = bad;
    EXPECT_THROW(render(lighting), std::invalid_argument);
  }
  lighting.negligible_radiance_W_per_m2_sr = Rgb::Constant(1e-30);
  expect_same_frame(render(lighting), exact);
  lighting.negligible_radiance_W_per_m2_sr = Rgb::Constant(1e30);
  expect_same_frame(render(lighting), without);
  int mixed = 0;
  for (double scale : {0.5, 1.0, 2.0, 4.0, 8.0}) {
    lighting.negligible_radiance_W_per_m2_sr = scale * daylight;
    const RadianceFrame frame = render(lighting);
    const Rgb change = largest_difference(frame, exact);
    EXPECT_TRUE((change < scale * daylight).all()) << "scale " << scale << ": " << change.transpose() << " against "
                                                   << (scale * daylight).transpose();
    if ((change > 0.0).any() && (largest_difference(frame, without) > 0.0).any()) ++mixed;
  }
  EXPECT_GE(mixed, 2);
}

// Daylight's path radiance alone (open water, level and rising rays; no forward scatter, so a pixel
// changes only by its own band's daylight): bands whose bound is below F / 2 are left out, and the
// bound is near the band's brightest path radiance here, so a finer sweep of F finds bands left out
// that lose almost F / 2, and none that lose more.
TEST(FrameTest, NegligiblePathRadianceIsBoundedBandByBand) {
  EmbreeScene scene;
  scene.add_static_mesh(plate(30.0f, 0.0f, -4.0f, 1.0f), 0, "plate");  // something to hit, far ahead
  scene.build();
  FrameLighting lighting = seabed_lighting();
  lighting.lights.clear();
  lighting.water.scattering_per_m = Rgb::Constant(0.1);
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 1.3));
  Eigen::Isometry3d X_WS = Eigen::Isometry3d::Identity();
  X_WS.translation() = Eigen::Vector3d(0.0, 0.0, -4.0);
  X_WS.rotate(Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()));  // pitched up a little
  const auto render = [&](const FrameLighting& l) {
    return render_radiance(scene, lens, X_WS * X_SC(), 0.1f, 60.0f, geometry::kNoHit, l, white);
  };
  const RadianceFrame exact = render(lighting);
  Rgb brightest = Rgb::Zero();
  for (const Rgbf& r : exact.radiance) brightest = brightest.max(r.cast<double>());
  double closest = 0.0;  // the largest change found, as a fraction of F / 2
  for (int step = 1; step <= 40; ++step) {
    const Rgb negligible = brightest * (0.05 * step);
    lighting.negligible_radiance_W_per_m2_sr = negligible;
    const RadianceFrame frame = render(lighting);
    for (std::size_t i = 0; i < frame.radiance.size(); ++i) {
      const Rgb change = (frame.radiance[i] - exact.radiance[i]).abs().cast<double>();
      ASSERT_TRUE((change < 0.5 * negligible).all()) << "pixel " << i << ": " << change.transpose();
      closest = std::max(closest, (change / (0.5 * negligible)).maxCoeff());
    }
  }
  EXPECT_GT(closest, 0.8);
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

// Bands, backscatter rows, forward-scatter rows and marine snow's slabs as tasks on two threads, or
// backwards on one: the same frame bit for bit
// (render/frame.h: a function of its inputs whatever the threads).
TEST(FrameTest, SameFrameWhateverTheThreads) {
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 1.2));
  const EmbreeScene scene = wall_scene(true);
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.3, 0.06, 0.03);
  lighting.water.scattering_per_m = Rgb::Constant(0.08);
  lighting.water.forward_scatter_max_angle_rad = 0.15;  // the spread's row tasks too
  lighting.marine_snow.density_per_m3 = 300.0;         // and marine snow's slabs
  lighting.marine_snow.max_range = 5.0;
  lighting.marine_snow.seed = 3;
  SpotLight left, right;
  left.p_WL = Eigen::Vector3d(0.0, 0.4, 0.0);
  right.p_WL = Eigen::Vector3d(0.0, -0.4, 0.0);
  lighting.lights = {left, right};
  const RadianceFrame serial = render_radiance(scene, lens, X_SC(), 0.1f, 50.0f, geometry::kNoHit, lighting, white);
  const ParallelFor backwards = [](std::size_t count, const std::function<void(std::size_t)>& task) {
    for (std::size_t i = count; i-- > 0;) task(i);
  };
  const ParallelFor two_threads = testing::two_threads;
  for (const ParallelFor& parallel : {backwards, two_threads}) {
    const RadianceFrame frame = render_radiance(scene, lens, X_SC(), 0.1f, 50.0f, geometry::kNoHit, lighting, white, parallel);
    expect_same_frame(frame, serial);
    EXPECT_EQ(frame.shadow_rays, serial.shadow_rays);
    EXPECT_EQ(frame.snow_particles, serial.snow_particles);
  }
  EXPECT_GT(serial.shadow_rays, 0u);
  EXPECT_GT(serial.snow_particles, 100u);
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
    ASSERT_NEAR((from_exact.radiance[i] - own.radiance[i]).abs().maxCoeff(), 0.0, 1e-5f * own.radiance[i].maxCoeff() + 1e-12f);
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


// The surface seen from below (render/optics.h surface_from_below_radiance): a fisheye looking straight up from 5 m
// under a flat surface in clear, daylit water sees Snell's window, the bright disc of the sky refracted in, whose edge
// is at asin(1 / n) from the zenith: 48.6 deg for n = 1.333 (fresh water; seawater's 1.34 gives 48.3). The frame
// matches the per-ray physics in double precision (1e-4 relative plus 1e-6 of the brightest pixel, as above; not
// within 0.5 deg of the edge, where the transmittance's slope is unbounded), is over 10x brighter 1 deg inside the edge
// than 1 deg outside it (measured 15x: Fresnel's transmittance is already down to 0.66 there, and total internal
// reflection outside shows only the dim upwelling water), and the sky's radiance falls to half the zenith's within
// 1 deg inside the critical angle.
// Tilting the surface 10 deg (a wave's slope) tilts the window with it: its brightest point, along the surface's
// normal (Fresnel's transmittance and the path to the surface are best there), moves 10 deg along the row (within two
// pixels).
TEST(FrameTest, UnderTheSurfaceACameraSeesSnellsWindow) {
  EmbreeScene scene;
  scene.add_static_mesh(plate(200.0f, 0.0f, 0.0f, 1.0f), 0, "far");  // out of view: the scene needs something
  scene.build();
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.05, 0.02, 0.03);
  lighting.water.scattering_per_m = Rgb::Constant(0.01);
  lighting.water.phase_g = 0.0;  // isotropic: no forward-scattered glow around the zenith (the default's 0.92 has one)
  lighting.daylight.surface_irradiance_W_per_m2 = Rgb(120.0, 150.0, 140.0);
  lighting.daylight.Kd_per_m = Rgb(0.04, 0.02, 0.025);  // below c = a + b, as in real water
  lighting.daylight.surface_z_m = 0.0;
  lighting.daylight.refractive_index = 1.333;
  LensSpec spec;  // equidistant, 201 px square, the edge 80 deg off the axis
  spec.model = LensModel::kEquidistant;
  spec.width_px = spec.height_px = 201;
  spec.cx = spec.cy = 100.0;
  spec.fx = spec.fy = 100.0 / (80.0 * M_PI / 180.0);
  const Lens lens = make_lens(spec);
  const auto render = [&](const FrameLighting& l) {
    Eigen::Isometry3d X_WC = Eigen::Isometry3d::Identity();  // C's axes W's: the optical axis z straight up
    X_WC.translation() = Eigen::Vector3d(0.0, 0.0, -5.0);
    return std::make_pair(render_radiance(scene, lens, X_WC, 0.05f, 500.0f, geometry::kNoHit, l,
                                          [](const SurfacePoint&) { return Rgb(0.5, 0.5, 0.5); }),
                          X_WC);
  };
  const auto [frame, X_WC] = render(lighting);
  const double critical = std::asin(1.0 / 1.333);
  EXPECT_NEAR(critical * 180.0 / M_PI, 48.6, 0.05);
  const Eigen::Vector3d o = X_WC.translation().cast<float>().cast<double>();
  const Rgb E_camera = lighting.daylight.irradiance_at(static_cast<float>(o.z()));
  double inside = 0.0, outside = 0.0, zenith = 0.0, half_angle = 0.0;
  int n_inside = 0, n_outside = 0;
  float brightest = 0.0f;
  for (const Rgbf& L : frame.radiance) brightest = std::max(brightest, L.maxCoeff());
  for (int v = 0; v < 201; ++v) {
    for (int u = 0; u < 201; ++u) {
      const Eigen::Vector3f d_f = (X_WC.linear().cast<float>() * lens.ray_C(u, v)).normalized();
      const Eigen::Vector3d d = d_f.cast<double>();
      const double angle = std::acos(std::clamp(d.z(), -1.0, 1.0));
      const Rgb expected = surface_from_below_radiance(lighting.water, lighting.daylight, o, d, 500.0) +
                           daylight_path_radiance(lighting.water, lighting.daylight, E_camera, o, d, 0.05, 500.0);
      const Rgb got = frame.radiance[static_cast<std::size_t>(v) * 201 + u].cast<double>();
      // At the window's edge the transmittance's slope is unbounded (sqrt(1 - n^2 sin^2)): there a single-precision
      // ray differs more.
      const bool near_edge = std::abs(angle - critical) < 0.5 * M_PI / 180.0;
      EXPECT_TRUE(near_edge || ((got - expected).abs() <= 1e-4 * expected.abs() + 1e-6 * brightest).all())
          << u << ", " << v << ": " << got.transpose() << " vs " << expected.transpose();
      if (u == 100 && v == 100) zenith = got[1];
      if (std::abs(angle - (critical - M_PI / 180.0)) < 0.25 * M_PI / 180.0) inside += got[1], ++n_inside;
      if (std::abs(angle - (critical + M_PI / 180.0)) < 0.25 * M_PI / 180.0) outside += got[1], ++n_outside;
    }
  }
  ASSERT_GT(n_inside, 10);
  ASSERT_GT(n_outside, 10);
  EXPECT_GT(inside / n_inside, 10.0 * outside / n_outside);
  // Where the sky's share falls to half the zenith's: along the image's row through the centre.
  for (int u = 100; u < 201; ++u) {
    const Eigen::Vector3d d = (X_WC.linear().cast<float>() * lens.ray_C(u, 100)).normalized().cast<double>();
    if (frame.radiance[100 * 201 + u][1] >= 0.5 * zenith) half_angle = std::acos(d.z());
  }
  EXPECT_LT(half_angle, critical);
  EXPECT_GT(half_angle, critical - M_PI / 180.0) << half_angle * 180 / M_PI;
  // A 10 deg slope: the window's centre follows the normal.
  FrameLighting tilted = lighting;
  tilted.daylight.surface_normal_W = Eigen::Vector3d(std::sin(0.1745), 0.0, std::cos(0.1745));
  const RadianceFrame leaning = render(tilted).first;
  double leaning_peak = 0.0, brightest_angle = 0.0;
  for (int u = 0; u < 201; ++u) {
    const Eigen::Vector3d d = (X_WC.linear().cast<float>() * lens.ray_C(u, 100)).normalized().cast<double>();
    if (leaning.radiance[100 * 201 + u][1] > leaning_peak) {
      leaning_peak = leaning.radiance[100 * 201 + u][1];
      brightest_angle = std::atan2(d.x(), d.z());
    }
  }
  EXPECT_NEAR(brightest_angle, 0.1745, 2.0 * 80.0 / 100.0 * M_PI / 180.0);  // two pixels
}

// A camera in the air, 3 m above a flat sea, looking 30 deg down: through clear air, the part of a plate standing in
// the water above the surface is lit by the sky unattenuated (albedo E0 / pi (1 + n_z) / 2, n_z = 0 here), the part
// below it is hidden by the surface, which shows the sky reflected (Fresnel, air to water) and the water's upwelling
// light transmitted out; above the horizon the sky, E0 / pi. Each pixel against render/optics.h in double precision
// (1e-4 relative plus 1e-6 of the brightest), the surface's depth along the optical axis, and the reflectance at
// normal incidence ((n - 1) / (n + 1))^2 = 2.1 % for n = 1.34.
TEST(FrameTest, FromTheAirACameraSeesTheSkyLitSurface) {
  EmbreeScene scene;
  scene.add_static_mesh(plate(10.0f, 0.0f, 0.5f, 1.0f), 0, "plate");  // x = 10, z from -0.5 to 1.5
  scene.build();
  FrameLighting lighting;
  lighting.water.absorption_per_m = Rgb(0.3, 0.06, 0.03);
  lighting.water.scattering_per_m = Rgb::Constant(0.05);
  lighting.daylight.surface_irradiance_W_per_m2 = Rgb(120.0, 150.0, 140.0);
  lighting.daylight.Kd_per_m = Rgb(0.3, 0.06, 0.04);
  lighting.daylight.surface_z_m = 0.0;
  const Lens lens = make_lens(lens_from_horizontal_fov(160, 120, 100.0 * M_PI / 180.0));
  Eigen::Isometry3d X_WC = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d z_C(std::cos(M_PI / 6.0), 0.0, -std::sin(M_PI / 6.0)), x_C(0.0, -1.0, 0.0);
  X_WC.linear().col(0) = x_C;
  X_WC.linear().col(1) = z_C.cross(x_C);
  X_WC.linear().col(2) = z_C;
  X_WC.translation() = Eigen::Vector3d(0.0, 0.0, 3.0);
  const Rgb albedo(0.6, 0.5, 0.4);
  const RadianceFrame frame = render_radiance(scene, lens, X_WC, 0.05f, 1000.0f, geometry::kNoHit, lighting,
                                              [&](const SurfacePoint&) { return albedo; });
  float brightest = 0.0f;
  for (const Rgbf& L : frame.radiance) brightest = std::max(brightest, L.maxCoeff());
  const Eigen::Vector3d o = X_WC.translation().cast<float>().cast<double>();
  int plate_above = 0, surface = 0, sky = 0;
  for (int v = 0; v < lens.height_px(); ++v) {
    for (int u = 0; u < lens.width_px(); ++u) {
      const Eigen::Vector3f d_f = (X_WC.linear().cast<float>() * lens.ray_C(u, v)).normalized();
      const Eigen::Vector3d d = d_f.cast<double>();
      geometry::RayBatch ray;
      ray.add_ray(o.cast<float>(), d_f, 0.05f, 1000.0f);
      geometry::RayHits hit;
      hit.resize(1);
      scene.intersect(ray, 0, 1, geometry::QueryPath::kSingle, hit);
      const double s_hit = hit.hit(0) ? hit.distance[0] : std::numeric_limits<double>::infinity();
      const double to_surface = d.z() < 0.0 ? -o.z() / d.z() : std::numeric_limits<double>::infinity();
      Rgb expected;
      if (s_hit < to_surface) {
        expected = albedo / M_PI * lighting.daylight.surface_irradiance_W_per_m2 * 0.5;  // n_z = 0, no water
        ++plate_above;
      } else {
        expected = surface_from_above_radiance(lighting.water, lighting.daylight, o, d, s_hit);
        (d.z() < 0.0 ? surface : sky) += 1;
      }
      const std::size_t i = static_cast<std::size_t>(v) * lens.width_px() + u;
      const Rgb got = frame.radiance[i].cast<double>();
      EXPECT_TRUE(((got - expected).abs() <= 1e-4 * expected.abs() + 1e-6 * brightest).all())
          << u << ", " << v << ": " << got.transpose() << " vs " << expected.transpose();
      if (to_surface < 1000.0 && to_surface < s_hit) {  // beyond the far clip the sea shows, without a depth
        EXPECT_NEAR(frame.depth_m[i], to_surface * lens.ray_C(u, v).normalized().z(), 1e-4 * to_surface);
      }
    }
  }
  EXPECT_GT(plate_above, 20);
  EXPECT_GT(surface, 1000);
  EXPECT_GT(sky, 1000);
  // Straight down: R = ((n - 1) / (n + 1))^2.
  const double n = 1.34, R = std::pow((n - 1.0) / (n + 1.0), 2.0);
  const Rgb& E0 = lighting.daylight.surface_irradiance_W_per_m2;
  const Rgb c = lighting.water.attenuation_per_m();
  const Rgb down = R * E0 / M_PI + (1.0 - R) / (n * n) * lighting.water.scattering_per_m *
                                       henyey_greenstein(lighting.water.phase_g, -1.0) * E0 / (c + lighting.daylight.Kd_per_m);
  EXPECT_LT((surface_from_above_radiance(lighting.water, lighting.daylight, o, -Eigen::Vector3d::UnitZ(), 1e9) - down)
                .abs().maxCoeff(), 1e-12 * down.maxCoeff());
  EXPECT_NEAR(R, 0.0211, 1e-4);
}

}  // namespace
}  // namespace hadal::render
