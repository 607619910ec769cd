#include "hadal/geometry/raycast_service.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace hadal::geometry {
namespace {

constexpr float kEps = std::numeric_limits<float>::epsilon();

// Flat seabed [-500, 500]^2 at z = -100 (normal +z) and, for body 0, a 2 x 1 x 1 m box hull in B.
EmbreeScene seabed_and_hull() {
  EmbreeScene scene;
  TriangleMesh seabed;
  seabed.positions = {-500, -500, -100, 500, -500, -100, 500, 500, -100, -500, 500, -100};
  seabed.indices = {0, 1, 2, 0, 2, 3};
  scene.add_static_mesh(seabed, 0, "seabed");
  TriangleMesh hull;
  for (int k = 0; k < 8; ++k) {
    hull.positions.insert(hull.positions.end(),
                          {(k & 1) ? 1.0f : -1.0f, (k & 2) ? 0.5f : -0.5f, (k & 4) ? 0.5f : -0.5f});
  }
  hull.indices = {0, 2, 1, 1, 2, 3,  4, 5, 6, 5, 7, 6,  0, 1, 4, 1, 5, 4,
                  2, 6, 3, 3, 6, 7,  0, 4, 2, 2, 4, 6,  1, 3, 5, 3, 7, 5};
  scene.add_body_mesh(0, hull, 1, "hull");
  return scene;
}

SimState state_with_hull_at(double time, std::uint64_t step, const Eigen::Vector3d& p_WB) {
  SimState state;
  state.time = time;
  state.step_count = step;
  state.vehicles.resize(1);
  state.vehicles[0].body.X_WB.translation() = p_WB;
  return state;
}

// `n` rays straight down from z = 0 at x = 0, y spread over [-0.4, 0.4] (inside the hull's footprint
// when the hull sits at x = y = 0).
RayBatch rays_down(const SimState& state, std::size_t n) {
  RayBatch batch;
  batch.set_snapshot(state);
  for (std::size_t i = 0; i < n; ++i) {
    const float y = -0.4f + 0.8f * static_cast<float>(i) / static_cast<float>(std::max<std::size_t>(1, n - 1));
    batch.add_ray({0.0f, y, 0.0f}, {0.0f, 0.0f, -1.0f});
  }
  return batch;
}

// Distance straight down from z = 0 to the top of the hull at depth z_B (hull top at z_B + 0.5).
float hull_distance(double z_B) { return static_cast<float>(-(z_B + 0.5)); }

TEST(RaycastService, RayDownOntoTheSeabedThroughTheFuture) {
  RaycastService service(seabed_and_hull(), {2});
  SimState state = state_with_hull_at(1.25, 625, {200.0, 0.0, -50.0});  // hull out of the way
  const RayHits hits = service.submit(rays_down(state, 3)).get();
  ASSERT_EQ(hits.size(), 3u);
  EXPECT_EQ(hits.sim_time, 1.25);
  EXPECT_EQ(hits.step_count, 625u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(hits.distance[i], 100.0f, 4 * kEps * 100.0f);
    EXPECT_EQ(hits.n_W_z[i], 1.0f);
    EXPECT_EQ(hits.body[i], kStaticBody);
  }
  EXPECT_EQ(service.path(), QueryPath::kStream);
  EXPECT_EQ(service.num_threads(), 2);
}

TEST(RaycastService, DefaultThreadCountIsTheHardwareConcurrency) {
  RaycastService service(seabed_and_hull());
  EXPECT_EQ(service.num_threads(), static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
}

TEST(RaycastService, CallbackGetsTheHits) {
  RaycastService service(seabed_and_hull(), {1});
  std::promise<RayHits> delivered;
  service.submit(rays_down(state_with_hull_at(2.0, 1000, {0.0, 0.0, -30.0}), 4),
                 [&](RayHits hits, std::exception_ptr error) {
                   ASSERT_EQ(error, nullptr);
                   delivered.set_value(std::move(hits));
                 });
  const RayHits hits = delivered.get_future().get();
  EXPECT_EQ(hits.step_count, 1000u);
  EXPECT_NEAR(hits.distance[0], hull_distance(-30.0), 4 * kEps * 30.0f);
  EXPECT_EQ(hits.body[0], 0);
  EXPECT_EQ(hits.material[0], 1u);
}

// A batch submitted with an old snapshot sees the hull where it was then, even though a batch with
// the new pose was submitted before the old one was traced.
TEST(RaycastService, EachBatchSeesItsOwnSnapshot) {
  RaycastService service(seabed_and_hull(), {2});
  std::vector<std::future<RayHits>> results;
  std::vector<double> depths;
  for (int k = 0; k < 40; ++k) {
    const double z_B = -20.0 - static_cast<double>(k % 7) * 10.0;
    depths.push_back(z_B);
    // Big and small batches alternate, so that later jobs queue behind earlier ones.
    results.push_back(service.submit(rays_down(state_with_hull_at(0.01 * k, k, {0.0, 0.0, z_B}), k % 2 ? 5 : 20000)));
  }
  for (int k = 0; k < 40; ++k) {
    const RayHits hits = results[k].get();
    EXPECT_EQ(hits.step_count, static_cast<std::uint64_t>(k));
    for (std::size_t i = 0; i < hits.size(); ++i) {
      ASSERT_EQ(hits.body[i], 0) << "batch " << k << " ray " << i;
      ASSERT_NEAR(hits.distance[i], hull_distance(depths[k]), 4 * kEps * 100.0f) << "batch " << k;
    }
  }
}

TEST(RaycastService, CallbacksArriveInSubmissionOrder) {
  RaycastService service(seabed_and_hull(), {2});
  std::mutex mutex;
  std::vector<std::uint64_t> order;
  for (std::uint64_t k = 0; k < 100; ++k) {
    service.submit(rays_down(state_with_hull_at(0.0, k, {0.0, 0.0, -50.0}), (k % 3) * 3000 + 1),
                   [&](RayHits hits, std::exception_ptr) {
                     std::lock_guard<std::mutex> lock(mutex);
                     order.push_back(hits.step_count);
                   });
  }
  service.shutdown();  // drains the queue
  ASSERT_EQ(order.size(), 100u);
  for (std::uint64_t k = 0; k < 100; ++k) EXPECT_EQ(order[k], k);
}

// Several physics-like threads submit at once; every result matches its own snapshot. Run under
// -fsanitize=thread to check the locking (see the report of issue 3).
TEST(RaycastService, ConcurrentSubmissions) {
  RaycastService service(seabed_and_hull(), {3});
  std::atomic<int> failures{0};
  std::vector<std::thread> submitters;
  for (int t = 0; t < 4; ++t) {
    submitters.emplace_back([&, t] {
      std::mt19937 rng(static_cast<unsigned>(t));
      std::uniform_real_distribution<double> depth(-90.0, -10.0);
      std::vector<std::pair<double, std::future<RayHits>>> pending;
      for (int k = 0; k < 30; ++k) {
        const double z_B = depth(rng);
        pending.emplace_back(z_B, service.submit(rays_down(state_with_hull_at(t, k, {0.0, 0.0, z_B}), 1 + 97 * k)));
      }
      for (auto& [z_B, future] : pending) {
        RayHits hits = future.get();
        for (std::size_t i = 0; i < hits.size(); ++i) {
          if (hits.body[i] != 0 || std::abs(hits.distance[i] - hull_distance(z_B)) > 4 * kEps * 100.0f) ++failures;
        }
        service.recycle(std::move(hits));
      }
    });
  }
  for (std::thread& s : submitters) s.join();
  EXPECT_EQ(failures.load(), 0);
}

// A seabed with bumps, a tilted plate as the body, camera-like rays. For one query path, every
// thread count and chunk size gives the same bits (packets and stream blocks start at multiples of
// 16 rays whatever the chunking). Across paths, distances and bodies are bit-identical; triangle and
// normal too, except for ties where a ray runs through an edge or vertex shared by two triangles
// (the middle column of this camera runs along the grid line y = 0).
TEST(RaycastService, SameHitsForAnyThreadCountAndPath) {
  TriangleMesh seabed;
  const int n = 50;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float x = -100.0f + 4.0f * static_cast<float>(i), y = -100.0f + 4.0f * static_cast<float>(j);
      seabed.positions.insert(seabed.positions.end(), {x, y, -100.0f + 2.0f * std::sin(0.2f * x + 0.1f * y)});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const auto a = static_cast<std::uint32_t>(j * (n + 1) + i), b = a + 1;
      const auto c = a + static_cast<std::uint32_t>(n + 1), d = c + 1;
      seabed.indices.insert(seabed.indices.end(), {a, b, d, a, d, c});
    }
  }
  TriangleMesh plate;
  plate.positions = {-3, -3, 0, 3, -3, 0, 3, 3, 0, -3, 3, 0};
  plate.indices = {0, 1, 2, 0, 2, 3};
  auto make_scene = [&] {
    EmbreeScene scene;
    scene.add_static_mesh(seabed);
    scene.add_body_mesh(0, plate);
    return scene;
  };
  SimState state;
  state.vehicles.resize(1);
  state.vehicles[0].body.X_WB.translate(Eigen::Vector3d(10.0, 0.0, -90.0));
  state.vehicles[0].body.X_WB.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d(1.0, 1.0, 0.0).normalized()));
  RayBatch batch;
  batch.set_snapshot(state);
  batch.coherence = RayCoherence::kCoherent;
  for (int v = 0; v < 60; ++v) {
    for (int u = 0; u < 80; ++u) {
      const Eigen::Vector3f d(1.0f, 0.01f * static_cast<float>(u - 40), -0.3f - 0.01f * static_cast<float>(v));
      batch.add_ray({0.0f, 0.0f, -85.0f}, d.normalized());
    }
  }
  std::vector<RayHits> by_path;
  for (QueryPath path : {QueryPath::kSingle, QueryPath::kPacket, QueryPath::kStream}) {
    std::vector<RayHits> results;
    for (auto [threads, chunk] : {std::pair<int, std::size_t>{1, 1024}, {2, 64}, {4, 16}, {3, 4096}}) {
      RaycastService service(make_scene(), {threads, path, chunk});
      results.push_back(service.submit(batch).get());
    }
    for (std::size_t r = 1; r < results.size(); ++r) {
      SCOPED_TRACE(std::string(to_string(path)) + " run " + std::to_string(r));
      EXPECT_EQ(results[r].distance, results[0].distance);
      EXPECT_EQ(results[r].n_W_x, results[0].n_W_x);
      EXPECT_EQ(results[r].n_W_y, results[0].n_W_y);
      EXPECT_EQ(results[r].n_W_z, results[0].n_W_z);
      EXPECT_EQ(results[r].body, results[0].body);
      EXPECT_EQ(results[r].mesh, results[0].mesh);
      EXPECT_EQ(results[r].triangle, results[0].triangle);
    }
    by_path.push_back(std::move(results[0]));
  }
  std::size_t body_hits = 0, ties = 0;
  for (std::size_t i = 0; i < batch.size(); ++i) body_hits += by_path[0].body[i] == 0;
  EXPECT_GT(body_hits, 50u);
  for (std::size_t p = 1; p < by_path.size(); ++p) {
    EXPECT_EQ(by_path[p].distance, by_path[0].distance);
    EXPECT_EQ(by_path[p].body, by_path[0].body);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      const std::uint32_t a = by_path[0].triangle[i], b = by_path[p].triangle[i];
      if (a == b) continue;
      ++ties;
      ASSERT_EQ(by_path[0].mesh[i], 0) << "ray " << i;  // seabed
      bool shared = false;
      for (int k = 0; k < 9; ++k) shared |= seabed.indices[3 * a + k / 3] == seabed.indices[3 * b + k % 3];
      ASSERT_TRUE(shared) << "ray " << i << ": triangles " << a << " and " << b;
    }
  }
  EXPECT_LT(ties, 2 * 60u);  // at most the middle column, per path
}

TEST(RaycastService, BadBatchesAreClearErrors) {
  RaycastService service(seabed_and_hull(), {2});
  const SimState state = state_with_hull_at(3.5, 7, {0.0, 0.0, -50.0});

  RayBatch ragged = rays_down(state, 4);
  ragged.t_far.pop_back();
  EXPECT_THROW(service.submit(ragged), std::invalid_argument);

  RayBatch no_poses = rays_down(state, 4);
  no_poses.X_WB.clear();
  try {
    service.submit(no_poses);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sim time 3.500000 s: EmbreeScene: 0 body poses for 1 bodies"),
              std::string::npos)
        << e.what();
  }

  // Bad rays fail the job; the lowest bad index is named whichever chunk a worker reached first.
  RayBatch bad_rays = rays_down(state, 10000);
  bad_rays.d_W_z[9000] = 0.5f;
  bad_rays.p_WO_x[700] = std::nanf("");
  std::future<RayHits> failed = service.submit(bad_rays);
  try {
    failed.get();
    ADD_FAILURE() << "no exception";
  } catch (const InvalidRayError& e) {
    EXPECT_EQ(e.ray_index(), 700u);
  }
  // The service carries on.
  EXPECT_EQ(service.submit(rays_down(state, 2)).get().body[0], 0);

  // Callbacks get the error too.
  std::promise<std::exception_ptr> error;
  service.submit(bad_rays, [&](RayHits hits, std::exception_ptr e) {
    EXPECT_EQ(hits.size(), 0u);
    error.set_value(e);
  });
  EXPECT_THROW(std::rethrow_exception(error.get_future().get()), InvalidRayError);
  EXPECT_THROW(service.submit(rays_down(state, 1), RaycastService::Callback{}), std::invalid_argument);
}

// A sensor may chain its next batch from the callback (the service's lock is not held there).
TEST(RaycastService, CallbackMaySubmitTheNextBatch) {
  RaycastService service(seabed_and_hull(), {2});
  std::promise<RayHits> second;
  service.submit(rays_down(state_with_hull_at(1.0, 1, {0.0, 0.0, -50.0}), 100), [&](RayHits, std::exception_ptr) {
    service.submit(rays_down(state_with_hull_at(2.0, 2, {0.0, 0.0, -60.0}), 100),
                   [&](RayHits hits, std::exception_ptr) { second.set_value(std::move(hits)); });
  });
  const RayHits hits = second.get_future().get();
  EXPECT_EQ(hits.step_count, 2u);
  EXPECT_NEAR(hits.distance[50], hull_distance(-60.0), 4 * kEps * 100.0f);
}

TEST(RaycastService, EmptyBatchComesBackEmpty) {
  RaycastService service(seabed_and_hull(), {2});
  RayBatch batch = rays_down(state_with_hull_at(9.0, 9, {0.0, 0.0, -50.0}), 0);
  const RayHits hits = service.submit(batch).get();
  EXPECT_EQ(hits.size(), 0u);
  EXPECT_EQ(hits.sim_time, 9.0);
}

TEST(RaycastService, ShutdownCompletesQueuedJobsThenRefusesNewOnes) {
  RaycastService service(seabed_and_hull(), {2});
  const SimState state = state_with_hull_at(0.0, 0, {0.0, 0.0, -50.0});
  std::vector<std::future<RayHits>> results;
  for (int k = 0; k < 20; ++k) results.push_back(service.submit(rays_down(state, 5000)));
  service.shutdown();
  for (auto& result : results) {
    ASSERT_EQ(result.wait_for(std::chrono::seconds(0)), std::future_status::ready);
    EXPECT_EQ(result.get().size(), 5000u);
  }
  EXPECT_THROW(service.submit(rays_down(state, 1)), std::logic_error);
  EXPECT_NO_THROW(service.shutdown());
}

TEST(RaycastService, ShutdownFromACallbackIsAnError) {
  RaycastService service(seabed_and_hull(), {1});
  std::promise<std::string> message;
  service.submit(rays_down(state_with_hull_at(0.0, 0, {0.0, 0.0, -50.0}), 1), [&](RayHits, std::exception_ptr) {
    try {
      service.shutdown();
      message.set_value("(no exception)");
    } catch (const std::logic_error& e) {
      message.set_value(e.what());
    }
  });
  EXPECT_NE(message.get_future().get().find("called from a worker thread"), std::string::npos);
}

TEST(RaycastService, RecycledBuffersAreReused) {
  RaycastService service(seabed_and_hull(), {2});
  const SimState state = state_with_hull_at(0.0, 0, {0.0, 0.0, -50.0});
  RayHits first = service.submit(rays_down(state, 4096)).get();
  const float* buffer = first.distance.data();
  service.recycle(std::move(first));
  const RayHits second = service.submit(rays_down(state, 4000)).get();
  EXPECT_EQ(second.distance.data(), buffer);
  EXPECT_EQ(second.size(), 4000u);
  EXPECT_NEAR(second.distance[3999], hull_distance(-50.0), 4 * kEps * 50.0f);
}

// Scene work between ray batches: each job, work or batch, sees the bodies where its own snapshot put
// them, in submission order; the work's parallel loop runs every task once (on 1 and 2 workers), and
// tasks trace against the posed scene.
TEST(RaycastService, SceneWorkSeesItsSnapshotBetweenBatches) {
  for (int threads : {1, 2}) {
    RaycastService service(seabed_and_hull(), {threads});
    std::vector<std::future<RayHits>> batches;
    std::vector<std::future<void>> works;
    std::vector<std::vector<float>> distances(20);
    for (int k = 0; k < 20; ++k) {
      const SimState state = state_with_hull_at(0.01 * k, k, {0.0, 0.0, -20.0 - 10.0 * (k % 5)});
      batches.push_back(service.submit(rays_down(state, k % 2 ? 3000 : 7)));
      const RayBatch rays = rays_down(state, 160);
      works.push_back(service.submit(rays.X_WB, [rays, &out = distances[k]](const EmbreeScene& scene, const ParallelFor& parallel) {
        RayHits hits;
        hits.resize(rays.size());
        // Ten tasks of 16 rays each, every task writing its own range.
        parallel(10, [&](std::size_t task) { scene.intersect(rays, 16 * task, 16 * task + 16, QueryPath::kSingle, hits); });
        out = hits.distance;
      }));
    }
    for (int k = 0; k < 20; ++k) {
      const float expected = hull_distance(-20.0 - 10.0 * (k % 5));
      const RayHits hits = batches[k].get();
      for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_NEAR(hits.distance[i], expected, 4 * kEps * 100.0f) << k;
      works[k].get();
      ASSERT_EQ(distances[k].size(), 160u);
      for (float d : distances[k]) ASSERT_NEAR(d, expected, 4 * kEps * 100.0f) << "work " << k << ", " << threads << " threads";
    }
  }
}

// A task's exception reaches the work (the lowest failing task's), a work's exception its future; the
// service goes on with the next job. Bad poses and empty work are refused at submit().
TEST(RaycastService, SceneWorkErrorsReachTheFuture) {
  RaycastService service(seabed_and_hull(), {2});
  const std::vector<Eigen::Isometry3d> X_WB{Eigen::Isometry3d::Identity()};
  std::atomic<int> ran{0};
  auto failing = service.submit(X_WB, [&](const EmbreeScene&, const ParallelFor& parallel) {
    parallel(50, [&](std::size_t i) {
      ++ran;
      if (i == 7 || i == 31) throw std::runtime_error("task " + std::to_string(i));
    });
  });
  try {
    failing.get();
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "task 7");
  }
  EXPECT_EQ(ran.load(), 50);  // the other tasks still ran
  auto thrown = service.submit(X_WB, [](const EmbreeScene&, const ParallelFor&) { throw std::logic_error("work"); });
  EXPECT_THROW(thrown.get(), std::logic_error);
  EXPECT_NEAR(service.submit(rays_down(state_with_hull_at(0.0, 0, {0.0, 0.0, -30.0}), 4)).get().distance[0],
              hull_distance(-30.0), 4 * kEps * 100.0f);
  EXPECT_THROW(service.submit(X_WB, RaycastService::SceneWork{}), std::invalid_argument);
  EXPECT_THROW(service.submit(std::vector<Eigen::Isometry3d>{}, [](const EmbreeScene&, const ParallelFor&) {}),
               std::invalid_argument);
}

TEST(RaycastService, BadOptionsAreClearErrors) {
  EXPECT_THROW(RaycastService(seabed_and_hull(), {-1}), std::invalid_argument);
  EXPECT_THROW(RaycastService(seabed_and_hull(), {1, QueryPath::kAuto, 8}), std::invalid_argument);
}

}  // namespace
}  // namespace hadal::geometry
