// Ray casting against a ~1M-triangle seabed: Embree BVH build time, and the throughput of
// RaycastService against a bare rtcIntersect1 loop over the same rays on the same Embree scene, in the
// same run. Prints one JSON object per measurement.
//   build/bin/hadal_bench_raycast [--repetitions N] [--quads Q]
//
// Seabed: Q x Q quads (default 708: 1 002 528 triangles) over 1 km x 1 km at z ~ -100 m, smooth
// seeded bumps (40 Gaussian hills and hollows of 1-8 m, sigma 20-120 m, std::mt19937 seed 1).
// Batches (307 200 rays each):
//   camera      640 x 480 pinhole, 60 deg horizontal field of view, 20 m above the seabed, pitched
//               45 deg down looking along +x, rays in row-major pixel order (coherent)
//   incoherent  origins uniform over 900 m x 900 m at 2-50 m above the seabed, directions uniform
//               over the lower hemisphere (DVL-like beams scattered over a survey; seed 7)
// Methods (median wall time of N repetitions, interleaved so that background load hits all alike):
//   bare_rtcIntersect1  RTCRayHit filled from the batch's arrays, rtcIntersect1, tfar/Ng/primID/
//                       geomID stored to preallocated arrays; on 2 threads the rays are split in
//                       chunks of 1024 taken from an atomic counter (the service's load balancing)
//   service_<path>      RaycastService::submit(...).get(), hits recycled (steady state of a camera);
//                       service_stream_no_recycle: the same without recycle() (fresh result buffers)
// ratio_vs_bare = service rays/s / bare rays/s at the same thread count. "scene": "seabed" traces the
// static seabed scene (the scene a bare loop would build); "seabed+hull" adds one vehicle hull
// instance, so rays go through Embree's two-level (instanced) traversal, bare loop included.
#include "hadal/geometry/raycast_service.h"
#include "hadal/core/units.h"
#include "seabed.h"
#include "timing.h"
#include "bare_embree.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

using hadal::geometry::EmbreeScene;
using hadal::geometry::QueryPath;
using hadal::geometry::RayBatch;
using hadal::geometry::RayCoherence;
using hadal::geometry::RayHits;
using hadal::geometry::RaycastService;
using hadal::geometry::RaycastServiceOptions;
using hadal::geometry::TriangleMesh;
using hadal::bench::Clock;
using hadal::bench::median;
using hadal::bench::seconds_since;

namespace {

using hadal::kPi;
using hadal::bench::Bump;
using hadal::bench::make_bumps;
using hadal::bench::make_seabed;
using hadal::bench::seabed_height;
using hadal::bench::kSeabedSize;
using hadal::bench::BareHits;
using hadal::bench::bare;
using hadal::bench::set_ftz_daz;

TriangleMesh make_hull() {  // 2 m x 1 m x 1 m box in B, outward winding
  TriangleMesh mesh;
  for (int k = 0; k < 8; ++k) {
    mesh.positions.insert(mesh.positions.end(),
                          {(k & 1) ? 1.0f : -1.0f, (k & 2) ? 0.5f : -0.5f, (k & 4) ? 0.5f : -0.5f});
  }
  mesh.indices = {0, 2, 1, 1, 2, 3,  4, 5, 6, 5, 7, 6,  0, 1, 4, 1, 5, 4,
                  2, 6, 3, 3, 6, 7,  0, 4, 2, 2, 4, 6,  1, 3, 5, 3, 7, 5};
  return mesh;
}

RayBatch camera_batch(const std::vector<Bump>& bumps) {
  RayBatch batch;
  batch.coherence = RayCoherence::kCoherent;
  const int width = 640, height = 480;
  const double f = (width / 2.0) / std::tan(30.0 * kPi / 180.0);  // 60 deg horizontal FOV [px]
  const double pitch = 45.0 * kPi / 180.0;
  // Camera frame C (z forward, x right, y down) in W, camera looking along +x pitched down.
  const Eigen::Vector3d z_C(std::cos(pitch), 0.0, -std::sin(pitch)), x_C(0.0, -1.0, 0.0);
  const Eigen::Vector3d y_C = z_C.cross(x_C);
  const Eigen::Vector3f p_WC(0.0f, 0.0f, seabed_height(bumps, 0.0f, 0.0f) + 20.0f);
  batch.reserve(static_cast<std::size_t>(width * height));
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector3d d =
          (z_C + (u + 0.5 - width / 2.0) / f * x_C + (v + 0.5 - height / 2.0) / f * y_C).normalized();
      batch.add_ray(p_WC, d.cast<float>());
    }
  }
  return batch;
}

RayBatch incoherent_batch(const std::vector<Bump>& bumps, std::size_t n) {
  RayBatch batch;
  batch.coherence = RayCoherence::kIncoherent;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  batch.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float x = -450.0f + 900.0f * unit(rng), y = -450.0f + 900.0f * unit(rng);
    const float z = seabed_height(bumps, x, y) + 2.0f + 48.0f * unit(rng);
    const float cos_theta = -unit(rng), phi = 2.0f * static_cast<float>(kPi) * unit(rng);
    const float sin_theta = std::sqrt(1.0f - cos_theta * cos_theta);
    const Eigen::Vector3f d(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
    batch.add_ray({x, y, z}, d.normalized());
  }
  return batch;
}


double load_average() {
  std::ifstream in("/proc/loadavg");
  double one_minute = -1.0;
  in >> one_minute;
  return one_minute;
}

EmbreeScene seabed_scene(const TriangleMesh& seabed, bool with_hull) {
  EmbreeScene scene;
  scene.add_static_mesh(seabed, 0, "seabed");
  if (with_hull) scene.add_body_mesh(0, make_hull(), 1, "hull");
  scene.build();
  return scene;
}

// One timed configuration: `prepare` (untimed) then `run`, which traces the whole batch once.
struct Measurement {
  std::string batch, scene, method;
  int threads;
  std::function<void()> prepare;
  std::function<void()> run;
  std::vector<double> seconds;
  const std::vector<float>* distances = nullptr;  // result of the last run, to check against bare
};

}  // namespace

int main(int argc, char** argv) {
  int repetitions = 7;
  int quads = 708;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repetitions" && i + 1 < argc) {
      repetitions = std::atoi(argv[++i]);
    } else if (arg == "--quads" && i + 1 < argc) {
      quads = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: hadal_bench_raycast [--repetitions N] [--quads Q]\n");
      return 2;
    }
  }
  if (repetitions < 1 || quads < 1) {
    std::fprintf(stderr, "hadal_bench_raycast: --repetitions and --quads must be >= 1\n");
    return 2;
  }
  set_ftz_daz();
  const double load_start = load_average();
  const std::vector<Bump> bumps = make_bumps();
  const TriangleMesh seabed = make_seabed(bumps, quads);

  // BVH build: EmbreeScene::build() of the static seabed (rtcCommitScene, Embree's default build
  // quality, all cores via Embree's TBB tasking), after the copy into Embree's buffers.
  {
    std::vector<double> copy_s, build_s;
    for (int r = 0; r < 5; ++r) {
      EmbreeScene scene;
      auto start = Clock::now();
      scene.add_static_mesh(seabed, 0, "seabed");
      copy_s.push_back(seconds_since(start));
      start = Clock::now();
      scene.build();
      build_s.push_back(seconds_since(start));
    }
    std::printf("{\"benchmark\": \"embree_bvh_build\", \"triangles\": %zu, \"vertices\": %zu, \"repetitions\": 5, "
                "\"median_s\": %.4f, \"min_s\": %.4f, \"max_s\": %.4f, \"copy_and_validate_median_s\": %.4f, "
                "\"hardware_threads\": %u, \"loadavg_1min_at_start\": %.2f}\n",
                seabed.num_triangles(), seabed.num_vertices(), median(build_s),
                *std::min_element(build_s.begin(), build_s.end()), *std::max_element(build_s.begin(), build_s.end()),
                median(copy_s), std::thread::hardware_concurrency(), load_start);
    std::fflush(stdout);
  }

  const RayBatch camera = camera_batch(bumps);
  const RayBatch scattered = incoherent_batch(bumps, camera.size());

  // Services own their scenes: one scene per (threads, path).
  struct ServiceSetup {
    std::string scene_name;
    int threads;
    QueryPath path;
    std::unique_ptr<RaycastService> service;
    bool recycle = true;
  };
  std::vector<ServiceSetup> setups;
  for (int threads : {1, 2}) {
    for (QueryPath path : {QueryPath::kSingle, QueryPath::kPacket, QueryPath::kStream}) {
      setups.push_back({"seabed", threads, path,
                        std::make_unique<RaycastService>(seabed_scene(seabed, false),
                                                         RaycastServiceOptions{threads, path, 1024})});
    }
    for (QueryPath path : {QueryPath::kSingle, QueryPath::kStream}) {
      setups.push_back({"seabed+hull", threads, path,
                        std::make_unique<RaycastService>(seabed_scene(seabed, true),
                                                         RaycastServiceOptions{threads, path, 1024})});
    }
  }
  // What recycle() saves: the same service without handing results back (fresh 10 MB per frame).
  setups.push_back({"seabed", 2, QueryPath::kStream,
                    std::make_unique<RaycastService>(seabed_scene(seabed, false),
                                                     RaycastServiceOptions{2, QueryPath::kStream, 1024}),
                    false});
  // The hull sits 1 m behind the camera (the vehicle carrying it): every ray starts beside its
  // instance's bounds but none hits it.
  hadal::SimState state;
  state.vehicles.resize(1);
  state.vehicles[0].body.X_WB.translation() =
      Eigen::Vector3d(-1.5, 0.0, static_cast<double>(camera.p_WO_z[0]));
  RTCScene seabed_only = setups[0].service->scene().embree_scene();
  RTCScene two_level = nullptr;
  for (const ServiceSetup& s : setups) {
    if (s.scene_name == "seabed+hull") two_level = s.service->scene().embree_scene();
  }

  std::vector<Measurement> measurements;
  std::vector<BareHits> bare_hits;
  bare_hits.reserve(8);
  std::vector<RayHits> last_hits(2 * setups.size());
  std::vector<RayBatch> next_batches(2 * setups.size());
  for (const RayBatch* rays : {&camera, &scattered}) {
    const std::string batch_name = rays == &camera ? "camera_640x480" : "incoherent";
    for (const char* scene_name : {"seabed", "seabed+hull"}) {
      RTCScene scene = std::string(scene_name) == "seabed" ? seabed_only : two_level;
      for (int threads : {1, 2}) {
        bare_hits.emplace_back(rays->size());
        BareHits* out = &bare_hits.back();
        measurements.push_back({batch_name, scene_name, "bare_rtcIntersect1", threads, [] {},
                                [=] { bare(scene, *rays, threads, *out); }, {}, &out->t});
      }
    }
    for (std::size_t k = 0; k < setups.size(); ++k) {
      ServiceSetup& s = setups[k];
      RaycastService* service = s.service.get();
      RayHits* last = &last_hits[(rays == &camera ? 0 : setups.size()) + k];
      RayBatch* next = &next_batches[(rays == &camera ? 0 : setups.size()) + k];
      // A camera builds a new batch per frame and moves it into submit(); building it is the
      // camera's cost, so the copy standing in for it is made before the clock starts.
      const bool recycle = s.recycle;
      measurements.push_back({batch_name, s.scene_name,
                              std::string("service_") + to_string(s.path) + (recycle ? "" : "_no_recycle"),
                              s.threads,
                              [=] {
                                *next = *rays;
                                next->set_snapshot(state);
                                if (!recycle) *last = RayHits{};  // the old frame is dropped untimed
                              },
                              [=] {
                                if (recycle) service->recycle(std::move(*last));
                                *last = service->submit(std::move(*next)).get();
                              },
                              {}, &last->distance});
    }
  }
  for (Measurement& m : measurements) {  // warm-up: first touch of buffers, poses committed
    m.prepare();
    m.run();
  }
  for (int r = 0; r < repetitions; ++r) {
    for (Measurement& m : measurements) {
      m.prepare();
      const auto start = Clock::now();
      m.run();
      m.seconds.push_back(seconds_since(start));
    }
  }
  const double load_end = load_average();

  auto find_bare = [&](const Measurement& m) -> const Measurement* {
    for (const Measurement& b : measurements) {
      if (b.method == "bare_rtcIntersect1" && b.batch == m.batch && b.scene == m.scene && b.threads == m.threads) {
        return &b;
      }
    }
    return nullptr;
  };
  for (const Measurement& m : measurements) {
    const double n = static_cast<double>(camera.size());
    const double rays_per_s = n / median(m.seconds);
    const Measurement* b = find_bare(m);
    const double ratio = rays_per_s / (n / median(b->seconds));
    // Same rays, same Embree scene: the service's distances must be the bare loop's, bit for bit.
    std::size_t mismatches = 0, hits = 0;
    for (std::size_t i = 0; i < m.distances->size(); ++i) {
      mismatches += (*m.distances)[i] != (*b->distances)[i];
      hits += std::isfinite((*m.distances)[i]);
    }
    std::printf("{\"benchmark\": \"raycast_throughput\", \"batch\": \"%s\", \"rays\": %zu, \"scene\": \"%s\", "
                "\"triangles\": %zu, \"method\": \"%s\", \"threads\": %d, \"repetitions\": %d, "
                "\"median_s\": %.5f, \"mrays_per_s\": %.2f, \"ratio_vs_bare\": %.3f, \"hit_fraction\": %.4f, "
                "\"distance_mismatches_vs_bare\": %zu, \"loadavg_1min_at_end\": %.2f}\n",
                m.batch.c_str(), camera.size(), m.scene.c_str(), seabed.num_triangles(), m.method.c_str(), m.threads,
                repetitions, median(m.seconds), rays_per_s / 1e6, ratio, static_cast<double>(hits) / n, mismatches,
                load_end);
  }
  return 0;
}
