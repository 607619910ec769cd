// Sonar pings over the benchmarks' ~1M-triangle seabed (bench/seabed.h) on the ray-cast service's workers,
// with the ping specs the sonar kinds make from their presets (FlsSensor::make_ping, MultibeamSensor::make_ping)
// and the kinds' per-beam work (uint8 encoding, bottom detection): the ping rate a 2-core machine sustains,
// against the products' real ping rates (docs/benchmarks.md, "Sonars").
//   fls        preset oculus_m750d (750 kHz, 130 deg x 20 deg, 1 deg beams, 40 m window in 512 bins) with
//              256 beams and 10 rays per beam-bin cell (2 across each beam, 2560 over its vertical aperture:
//              1.31 M rays); 10 m above the seabed, pitched 20 deg down: the centre beam's lower edge meets the
//              seabed at 20 m and its rays more than 14.5 deg below the horizontal (78 %) within the window
//   multibeam  preset r2sonic_2024 (400 kHz, 256 beams over 130 deg, 0.5 deg x 1 deg, 50 m window in 4000
//              bins, 32 x 4 rays per beam), 20 m above the seabed looking down (outer beams at ~47 m)
// Water: 4 degC, S 35 at 100 m (sound speed UNESCO, Francois-Garrison absorption at each frequency).
// Each on 1 and 2 worker threads; speckle and receiver noise on. Prints one JSON object per (sonar,
// threads): the median wall time of N pings, its rate, and (multibeam) how many beams found the bottom.
//   build/bin/hadal_bench_sonar [--repetitions N]      (default 10)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/geometry/embree_scene.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/physics/seawater.h"
#include "hadal/render/sonar.h"
#include "hadal/sensors/fls_sensor.h"
#include "hadal/sensors/multibeam_sensor.h"
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

  // The kinds' specs from their presets, as `preset:` in a scenario sets them (sensors/fls_sensor.h,
  // sensors/multibeam_sensor.h).
  const auto preset = [](const auto& presets, std::string_view id) {
    if (const auto* p = config::find_preset(presets, id)) return p->figures;
    std::fprintf(stderr, "hadal_bench_sonar: no preset %.*s\n", static_cast<int>(id.size()), id.data());
    std::exit(1);
  };
  sensors::FlsSensor::Spec fls_spec;
  const sensors::FlsFigures oculus = preset(sensors::fls_presets(), "oculus_m750d");
  oculus.apply(fls_spec);
  fls_spec.beams = 256;
  fls_spec.rays_per_cell = 10;
  sensors::FlsSensor::make_ping(fls_spec);
  Eigen::Isometry3d X_WS_fls = Eigen::Isometry3d::Identity();
  X_WS_fls.linear() = Eigen::AngleAxisd(20.0 * kDegToRad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  X_WS_fls.translation() = Eigen::Vector3d(0.0, 0.0, floor_z + 10.0);

  sensors::MultibeamSensor::Spec mb_spec;
  const sensors::MultibeamFigures r2sonic = preset(sensors::multibeam_presets(), "r2sonic_2024");
  r2sonic.apply(mb_spec);
  sensors::MultibeamSensor::make_ping(mb_spec);
  Eigen::Isometry3d X_WS_mb = Eigen::Isometry3d::Identity();
  X_WS_mb.linear() = Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitY()).toRotationMatrix();  // x_S down
  X_WS_mb.translation() = Eigen::Vector3d(0.0, 0.0, floor_z + 20.0);

  const auto water_at = [](double frequency_hz) {
    render::SonarWater water;
    water.sound_speed_m_per_s = physics::sound_speed_unesco(35.0, physics::its90_to_ipts68(4.0), 100.0);
    water.absorption_db_per_m = 1e-3 * physics::absorption_francois_garrison_db_per_km(frequency_hz, 4.0, 35.0, 100.0);
    return water;
  };
  const sensors::SonarImageEncoding& encoding = fls_spec.encoding;

  std::printf("[\n");
  bool first = true;
  for (int threads : {1, 2}) {
    geometry::RaycastService service(scene.view(), {threads});
    struct Case {
      const char* name;
      const render::SonarPingSpec* spec;
      Eigen::Isometry3d X_WS;
      render::SonarWater water;
      double min_snr_db;  // < 0: an image (encoded), else bottom detection
    };
    for (const Case& c : {Case{"fls", fls_spec.ping.get(), X_WS_fls, water_at(fls_spec.acoustics.frequency_hz), -1.0},
                          Case{"multibeam", mb_spec.ping.get(), X_WS_mb, water_at(mb_spec.acoustics.frequency_hz),
                               mb_spec.min_snr_db}}) {
      const bool detect = c.min_snr_db >= 0.0;
      const std::size_t beams = c.spec->beams.size(), bins = static_cast<std::size_t>(c.spec->bins);
      std::vector<std::uint8_t> image(beams * bins);
      std::vector<double> ranges(beams, std::numeric_limits<double>::quiet_NaN());
      std::vector<double> wall_s;
      std::size_t detections = 0;
      for (int r = 0; r < repetitions; ++r) {
        const auto start = bench::Clock::now();
        service
            .submit({}, [&](const geometry::EmbreeScene& posed, const ParallelFor& parallel) {
              render::ping(posed, *c.spec, c.X_WS, geometry::kNoHit, c.water, kSediment, 7, static_cast<std::uint64_t>(r),
                           parallel, [&](const render::BeamEcho& echo) {
                             if (detect) {
                               ranges[static_cast<std::size_t>(echo.beam)] =
                                   render::detect_bottom(*c.spec, c.water, echo, c.min_snr_db).range_m;
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
                  "\"ping_ms\": %.2f, \"pings_per_s\": %.2f, \"mrays_per_s\": %.2f%s}",
                  first ? "" : ",\n", c.name, threads, beams, bins, rays, 1e3 * ping_s, 1.0 / ping_s,
                  rays / ping_s / 1e6, detect ? (", \"detections\": " + std::to_string(detections)).c_str() : "");
      first = false;
    }
  }
  std::printf("\n]\n");
  return 0;
}
