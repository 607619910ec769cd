// Sonar pings over the benchmarks' ~1M-triangle seabed (bench/seabed.h) on the ray-cast service's workers,
// exactly as the sonar kinds ping (render/sonar.h through sensors/sonar.h's scene work): the ping rate a
// 2-core machine sustains, against the products' real ping rates (BENCHMARKS.md, "Sonars").
//   fls        256 beams x 512 bins over 130 deg x 20 deg, 10 rays per beam-bin cell (2 across each 1 deg
//              beam, 2560 across its vertical aperture: 1.31 M rays), 50 m window, 20 m above the seabed,
//              pitched 20 deg down; the image encoded as uint8
//   multibeam  256 beams over 130 deg, 1 deg x 1 deg, 32 x 4 rays per beam, 4000 bins over 100 m, 30 m above
//              the seabed looking down, bottom detection per beam
// Each on 1 and 2 worker threads; speckle and receiver noise on. Prints one JSON object per (sonar,
// threads): the median wall time of N pings and its rate.
//   build/bin/hadal_bench_sonar [--repetitions N]      (default 10)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/geometry/embree_scene.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/render/sonar.h"
#include "hadal/sensors/sonar.h"
#include "seabed.h"
#include "timing.h"

using namespace hadal;

namespace {

const render::BackscatterOfHits kSediment = [](const geometry::RayHits& hits, std::size_t count, float* mu) {
  for (std::size_t i = 0; i < count; ++i) mu[i] = hits.hit(i) ? 0.002f : 0.0f;  // -27 dB
};

}  // namespace

int main(int argc, char** argv) {
  int repetitions = 10;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repetitions" && i + 1 < argc) {
      repetitions = std::max(1, std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr, "usage: hadal_bench_sonar [--repetitions N]\n");
      return 2;
    }
  }
  const std::vector<bench::Bump> bumps = bench::make_bumps();
  geometry::EmbreeScene scene;
  scene.add_static_mesh(bench::make_seabed(bumps, 708), 0, "seabed", geometry::StaticShape::kHeightField);
  scene.build();
  const double floor_z = bench::seabed_height(bumps, 0.0f, 0.0f);

  render::SonarPingSpec fls;
  fls.beams = render::fan_beams(256, 130.0 * kDegToRad, 1.0 * kDegToRad, 20.0 * kDegToRad);
  fls.min_range_m = 0.5;
  fls.max_range_m = 50.0;
  fls.bins = 512;
  fls.rays_u = 2;
  fls.rays_v = 10 * 512 / 2;
  Eigen::Isometry3d X_WS_fls = Eigen::Isometry3d::Identity();
  X_WS_fls.linear() = Eigen::AngleAxisd(20.0 * kDegToRad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  X_WS_fls.translation() = Eigen::Vector3d(0.0, 0.0, floor_z + 20.0);

  render::SonarPingSpec multibeam;
  multibeam.beams = render::fan_beams(256, 130.0 * kDegToRad, 1.0 * kDegToRad, 1.0 * kDegToRad);
  multibeam.min_range_m = 0.5;
  multibeam.max_range_m = 100.5;
  multibeam.bins = 4000;
  multibeam.rays_u = 32;
  multibeam.rays_v = 4;
  multibeam.source_level_db = 215.0;
  Eigen::Isometry3d X_WS_mb = Eigen::Isometry3d::Identity();
  X_WS_mb.linear() = Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix();  // x_S down
  X_WS_mb.translation() = Eigen::Vector3d(0.0, 0.0, floor_z + 30.0);

  render::SonarWater water;
  water.sound_speed_m_per_s = 1500.0;
  water.absorption_db_per_m = 0.1;
  sensors::SonarImageEncoding encoding;

  std::printf("[\n");
  bool first = true;
  for (int threads : {1, 2}) {
    geometry::RaycastService service(scene.view(), {threads});
    struct Case {
      const char* name;
      const render::SonarPingSpec* spec;
      Eigen::Isometry3d X_WS;
      bool detect;
    };
    for (const Case& c : {Case{"fls", &fls, X_WS_fls, false}, Case{"multibeam", &multibeam, X_WS_mb, true}}) {
      const std::size_t beams = c.spec->beams.size(), bins = static_cast<std::size_t>(c.spec->bins);
      std::vector<std::uint8_t> image(beams * bins);
      std::vector<double> ranges(beams);
      std::vector<double> wall_s;
      std::size_t detections = 0;
      for (int r = 0; r < repetitions; ++r) {
        const auto start = bench::Clock::now();
        service
            .submit({}, [&](const geometry::EmbreeScene& posed, const ParallelFor& parallel) {
              render::ping(posed, *c.spec, c.X_WS, geometry::kNoHit, water, kSediment, 7, static_cast<std::uint64_t>(r),
                           parallel, [&](const render::BeamEcho& echo) {
                             if (c.detect) {
                               ranges[static_cast<std::size_t>(echo.beam)] =
                                   render::detect_bottom(*c.spec, water, echo).range_m;
                             } else {
                               for (int b = 0; b < echo.bins; ++b) {
                                 encoding.encode(echo.intensity[b], &image[static_cast<std::size_t>(b) * beams + static_cast<std::size_t>(echo.beam)]);
                               }
                             }
                           });
            })
            .get();
        wall_s.push_back(bench::seconds_since(start));
      }
      for (double range : ranges) detections += std::isfinite(range) ? 1 : 0;
      const double ping_s = bench::median(wall_s);
      const std::size_t rays = beams * static_cast<std::size_t>(c.spec->rays_u * c.spec->rays_v);
      std::printf("%s  {\"sonar\": \"%s\", \"threads\": %d, \"beams\": %zu, \"bins\": %zu, \"rays\": %zu, "
                  "\"ping_ms\": %.2f, \"pings_per_s\": %.2f, \"mrays_per_s\": %.2f, \"detections\": %zu}",
                  first ? "" : ",\n", c.name, threads, beams, bins, rays, 1e3 * ping_s, 1.0 / ping_s,
                  rays / ping_s / 1e6, c.detect ? detections : 0);
      first = false;
    }
  }
  std::printf("\n]\n");
  return 0;
}
