// Internal to the core module: a small persistent thread pool for per-step parallel work (the fluid
// forces of several vehicles). Threads are created once; each run() wakes them, shares out the
// items through an atomic counter, and returns when every item is done, so the per-step cost is a
// wake-up (~10 us), not a thread start. Results must not depend on which thread ran an item (each
// item writes only its own output), so runs are deterministic whatever the thread count.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hadal {

class WorkerPool {
 public:
  // `helpers` threads besides the caller (0: run() is a plain loop).
  explicit WorkerPool(unsigned helpers);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  unsigned helpers() const { return static_cast<unsigned>(threads_.size()); }

  // Runs task(i) for i in [0, count) on the helpers and the caller; returns when all are done. An
  // exception from a task is rethrown here (the remaining items are skipped). Not reentrant.
  void run(std::size_t count, const std::function<void(std::size_t)>& task);

 private:
  void work_loop();
  void drain();

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable start_;
  std::condition_variable done_;
  const std::function<void(std::size_t)>* task_ = nullptr;
  std::size_t count_ = 0;
  std::size_t next_ = 0;          // next item to hand out (under mutex_)
  std::size_t finished_ = 0;      // items done in this run
  unsigned busy_ = 0;             // helpers inside drain()
  std::uint64_t generation_ = 0;  // bumped per run, wakes the helpers
  bool stop_ = false;
  std::exception_ptr failure_;
};

}  // namespace hadal
