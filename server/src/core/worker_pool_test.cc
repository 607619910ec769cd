#include "worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <stdexcept>
#include <vector>

namespace hadal {
namespace {

TEST(WorkerPoolTest, RunsEveryItemOnceOverManyRuns) {
  for (unsigned helpers : {0u, 1u, 3u}) {
    WorkerPool pool(helpers);
    std::vector<int> hits(37, 0);
    for (int run = 0; run < 2000; ++run) {
      pool.run(hits.size(), [&](std::size_t i) { ++hits[i]; });  // each item owns its slot
    }
    for (int h : hits) EXPECT_EQ(h, 2000) << helpers;
  }
}

TEST(WorkerPoolTest, UsesTheHelpers) {
  WorkerPool pool(2);
  std::atomic<int> concurrent{0}, peak{0};
  pool.run(3, [&](std::size_t) {
    const int now = ++concurrent;
    int seen = peak.load();
    while (now > seen && !peak.compare_exchange_weak(seen, now)) {
    }
    // Hold the item until two run at once; the deadline only bounds a starved machine.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (peak.load() < 2 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    --concurrent;
  });
  EXPECT_GE(peak.load(), 2);
}

TEST(WorkerPoolTest, RethrowsATaskFailureAndStaysUsable) {
  WorkerPool pool(2);
  EXPECT_THROW(pool.run(10, [](std::size_t i) {
                 if (i == 4) throw std::runtime_error("item 4");
               }),
               std::runtime_error);
  std::atomic<int> done{0};
  pool.run(10, [&](std::size_t) { ++done; });
  EXPECT_EQ(done.load(), 10);
}

}  // namespace
}  // namespace hadal
