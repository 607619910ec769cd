// Hadal's one threading primitive: a parallel loop as a value. Whoever runs a piece of work split into
// independent tasks (a camera frame's bands, a mesh's chunks, the vehicles' fluid forces) takes a
// ParallelFor (or, on the stepping thread, calls the same loop) and stays free of any thread pool. Three
// things run one, each where the others would not fit:
//   spawned_threads(n)        threads made for the one loop and joined at its end: load-time work (a mesh
//                             import, its properties), once per file, before any pool exists; spawning costs
//                             microseconds there.
//   WorkerPool::run           the same loop on a persistent pool that spins between steps
//                             (server/src/core/worker_pool.h): per-step work on the stepping thread (the
//                             fluid forces of large hulls), where waking a sleeping thread would cost as
//                             much as the work.
//   the ray-cast workers      RaycastService (geometry/raycast_service.h) runs captures on its workers with
//                             the scene posed at the capture's snapshot, and hands each capture their loop.
// serial_for runs on the caller. Results never depend on which provider or how many threads ran a loop.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hadal {

// Runs task(i) for every i in [0, count), in any order and on any threads, and returns when all are
// done. Tasks must not depend on the order they run in.
using ParallelFor = std::function<void(std::size_t count, const std::function<void(std::size_t)>& task)>;

inline void serial_for(std::size_t count, const std::function<void(std::size_t)>& task) {
  for (std::size_t i = 0; i < count; ++i) task(i);
}

// A loop on up to `workers` threads (the caller's included) made for each call and joined before it
// returns. An exception thrown by a task (std::bad_alloc) is rethrown after every thread has joined.
inline ParallelFor spawned_threads(unsigned workers) {
  return [workers](std::size_t count, const std::function<void(std::size_t)>& task) {
    const unsigned n = static_cast<unsigned>(std::min<std::size_t>(workers, count));
    if (n <= 1) {
      serial_for(count, task);
      return;
    }
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto run = [&] {
      try {
        for (std::size_t i = next++; i < count; i = next++) task(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = count;  // the other threads stop at their next task
      }
    };
    std::vector<std::thread> threads;
    threads.reserve(n - 1);
    for (unsigned w = 1; w < n; ++w) threads.emplace_back(run);
    run();
    for (auto& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
  };
}

}  // namespace hadal
