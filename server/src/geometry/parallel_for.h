// Internal to the geometry module: a minimal parallel loop over work items (no thread pool: the
// callers run it once per mesh load, where spawning two threads costs microseconds).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hadal::geometry {

// Runs task(i) for i in [0, count) on up to `workers` threads (the caller's included). An exception
// thrown by a task (std::bad_alloc) is rethrown here after every thread has joined.
inline void parallel_for(std::size_t count, unsigned workers,
                  const std::function<void(std::size_t)>& task) {
  workers = static_cast<unsigned>(std::min<std::size_t>(workers, count));
  if (workers <= 1) {
    for (std::size_t i = 0; i < count; ++i) task(i);
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
  threads.reserve(workers - 1);
  for (unsigned w = 1; w < workers; ++w) threads.emplace_back(run);
  run();
  for (auto& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace hadal::geometry
