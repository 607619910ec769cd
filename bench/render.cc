// A deep-sea camera frame over a ~1M-triangle seabed: the wall time of render::render_radiance (640 x 480
// radiance and depth: primary rays, a shadow ray per hit and light inside its beam, backscatter from two
// lights through the frame's table, render/backscatter_table.h) and of sensors::expose_rgb8, on 1 and 2
// threads (the renderer's tasks on bench::run_on_threads), next to a bare rtcIntersect1 loop over the
// same primary rays on as many threads (bench/bare_embree.h). The backscatter table is kept from frame
// to frame, as the camera sensor keeps it when the lights ride on the camera's own vehicle
// (sensors/camera_sensor.h, the default AUV's case); building it, which every frame does when lights
// move relative to the camera, is timed on its own (backscatter_table_s; fps_building_the_table counts
// it in every frame). rgb8_fps counts the frame and its exposure. rays_per_s counts primary and shadow
// rays. A 2 m box (a lander, a body) stands on the seabed 20 m ahead and shadows it. Twice: with the
// seabed declared a height field (geometry::StaticShape::kHeightField), where shadow rays that provably
// reach their light are not cast (render/frame.h), and without, where every one is cast.
// Prints one JSON object per measurement (median of N repetitions, variants and thread counts interleaved).
//   build/bin/hadal_bench_render [--repetitions N]
// Scene: bench/seabed.h (708 x 708 quads, 1 002 528 triangles); camera 20 m above the seabed at the
// origin, pitched 45 deg down looking along +x, 60 deg horizontal field of view with barrel distortion
// (k1 = -0.2, k2 = 0.05); lights 0.5 m left and right of the camera along its axis, 40-50 deg beams,
// 300 W/sr; water a = pure water (Pope & Fry) + 0.02 /m, b = 0.05 /m, g = 0.924.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "hadal/core/allocator.h"
#include "hadal/core/units.h"
#include "hadal/render/camera_rays.h"
#include "hadal/render/frame.h"
#include "hadal/render/water_presets.h"
#include "hadal/sensors/image_sensor.h"
#include "bare_embree.h"
#include "seabed.h"
#include "timing.h"

using namespace hadal;
using bench::Clock;
using bench::median;
using bench::seconds_since;

int main(int argc, char** argv) {
  hadal::keep_frame_buffers_mapped();  // core/allocator.h
  int repetitions = 5;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repetitions" && i + 1 < argc) {
      repetitions = std::max(1, std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr, "usage: hadal_bench_render [--repetitions N]\n");
      return 2;
    }
  }
  const auto bumps = bench::make_bumps();
  const geometry::TriangleMesh seabed = bench::make_seabed(bumps, 708);
  // A 2 m cube, counter-clockwise seen from outside, standing on the seabed at (20, 3).
  geometry::TriangleMesh cube;
  for (int k = 0; k < 8; ++k) {
    cube.positions.insert(cube.positions.end(), {(k & 1) ? 1.0f : -1.0f, (k & 2) ? 1.0f : -1.0f, (k & 4) ? 1.0f : -1.0f});
  }
  cube.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  Eigen::Isometry3d X_W_lander = Eigen::Isometry3d::Identity();
  X_W_lander.translation() = Eigen::Vector3d(20.0, 3.0, bench::seabed_height(bumps, 20.0f, 3.0f) + 0.9);
  std::vector<geometry::EmbreeScene> scenes;
  for (geometry::StaticShape shape : {geometry::StaticShape::kHeightField, geometry::StaticShape::kAny}) {
    geometry::EmbreeScene& scene = scenes.emplace_back();
    scene.add_static_mesh(seabed, 0, "seabed", shape);
    scene.add_body_mesh(0, cube, 1, "lander");
    scene.build();
    scene.set_body_poses({X_W_lander});
  }

  render::LensSpec spec = render::lens_from_horizontal_fov(640, 480, 60.0 * kDegToRad);
  spec.model = render::LensModel::kRadialTangential;
  spec.distortion = {-0.2, 0.05, 0.0, 0.0, 0.0};
  const render::Lens lens = render::make_lens(spec);
  Eigen::Isometry3d X_WS = Eigen::Isometry3d::Identity();
  X_WS.translation() = Eigen::Vector3d(0.0, 0.0, bench::seabed_height(bumps, 0.0f, 0.0f) + 20.0);
  X_WS.rotate(Eigen::AngleAxisd(45.0 * kDegToRad, Eigen::Vector3d::UnitY()));  // pitched down
  const Eigen::Isometry3d X_WC = X_WS * render::X_SC();

  render::FrameLighting lighting;
  lighting.water.absorption_per_m = render::pure_water_absorption_per_m() + 0.02;
  lighting.water.scattering_per_m = render::Rgb::Constant(0.05);
  for (double side : {0.5, -0.5}) {
    render::SpotLight light;
    light.p_WL = X_WS * Eigen::Vector3d(0.0, side, 0.0);
    light.axis_W = X_WS.linear() * Eigen::Vector3d::UnitX();
    light.inner_half_angle_rad = 40.0 * kDegToRad;
    light.outer_half_angle_rad = 50.0 * kDegToRad;
    light.intensity_W_per_sr = render::Rgb::Constant(300.0);
    lighting.lights.push_back(light);
  }
  const auto albedo = [](const render::SurfacePoint&) { return render::Rgb(0.45, 0.42, 0.35); };
  std::vector<float> cos_theta;
  for (const auto& d : lens.rays_C()) cos_theta.push_back(d.z());
  geometry::RayBatch primary;
  render::add_camera_rays(lens, X_WC, 0.1f, 200.0f, geometry::kNoHit, primary);
  bench::BareHits bare_hits(primary.size());
  // The lights in the camera's frame C, for the table kept across frames (the one render_radiance would
  // make for each frame).
  const std::vector<render::SpotLight> lights_C = render::lights_in_camera_frame(lighting.lights, X_WC);

  // Per variant (height field or not) and thread count: frame, exposure and bare-loop times,
  // interleaved over the repetitions.
  const int thread_counts[] = {1, 2};
  std::vector<double> frame_s[2][2], expose_s[2], bare_s[2], table_s[2];
  std::size_t hit_pixels = 0, shadow_rays[2] = {0, 0};
  for (int r = 0; r < repetitions; ++r) {
    for (int t = 0; t < 2; ++t) {
      const int threads = thread_counts[t];
      const ParallelFor parallel = [threads](std::size_t count, const std::function<void(std::size_t)>& task) {
        bench::run_on_threads(threads, count, task);
      };
      auto table_start = Clock::now();
      render::FrameLighting kept = lighting;
      kept.backscatter = render::make_backscatter_table(lighting, lights_C, lens, 0.1f, 200.0f, parallel);
      table_s[t].push_back(seconds_since(table_start));
      render::RadianceFrame frame;
      for (int v = 0; v < 2; ++v) {
        const auto start = Clock::now();
        frame = render::render_radiance(scenes[static_cast<std::size_t>(v)], lens, X_WC, 0.1f, 200.0f, geometry::kNoHit,
                                        kept, albedo, parallel);
        frame_s[v][t].push_back(seconds_since(start));
        shadow_rays[v] = frame.shadow_rays;
      }
      hit_pixels = static_cast<std::size_t>(std::count_if(frame.depth_m.begin(), frame.depth_m.end(),
                                                           [](float z) { return z == z; }));
      sensors::ImageSensorSpec sensor;
      auto start = Clock::now();
      const auto rgb = sensors::expose_rgb8(sensor, frame.radiance, cos_theta, 1, static_cast<std::uint64_t>(r), parallel);
      expose_s[t].push_back(seconds_since(start));
      start = Clock::now();
      bench::bare(scenes[1].embree_scene(), primary, threads, bare_hits);
      bare_s[t].push_back(seconds_since(start));
      if (rgb.empty()) return 1;
    }
  }
  const double pixels = 640.0 * 480.0;
  for (int t = 0; t < 2; ++t) {
    const double expose = median(expose_s[t]), bare = median(bare_s[t]), table = median(table_s[t]);
    for (int v = 0; v < 2; ++v) {
      const double frame = median(frame_s[v][t]);
      std::printf("{\"benchmark\": \"render_frame\", \"threads\": %d, \"seabed_height_field\": %s, \"width\": 640, "
                  "\"height\": 480, \"lights\": 2, \"backscatter_samples\": %d, \"backscatter_grid_px\": %d, "
                  "\"seabed_triangles\": 1002528, \"hit_pixels\": %zu, \"shadow_rays_cast\": %zu, "
                  "\"shadow_rays_needed\": %zu, \"frame_s\": %.4f, \"fps\": %.2f, \"rays_cast_per_s\": %.4g, "
                  "\"expose_rgb8_s\": %.4f, \"rgb8_fps\": %.2f, \"backscatter_table_s\": %.4f, "
                  "\"fps_building_the_table\": %.2f}\n",
                  thread_counts[t], v == 0 ? "true" : "false", lighting.backscatter_samples,
                  lighting.backscatter_grid_px, hit_pixels, shadow_rays[v], shadow_rays[1], frame, 1.0 / frame,
                  (pixels + static_cast<double>(shadow_rays[v])) / frame, expose, 1.0 / (frame + expose), table,
                  1.0 / (frame + table));
    }
    std::printf("{\"benchmark\": \"bare_rtcIntersect1_primary_rays\", \"threads\": %d, \"rays\": %.0f, "
                "\"wall_s\": %.4f, \"rays_per_s\": %.4g}\n",
                thread_counts[t], pixels, bare, pixels / bare);
  }
  return 0;
}
