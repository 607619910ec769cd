// Internal to the core module: a small persistent thread pool for per-step parallel work (the fluid
// forces of several vehicles). Threads are created once; each run() publishes a new generation,
// shares out the items under a mutex and returns when every item is done. A waking thread can take
// tens of microseconds to run on a VM -- as long as a whole item -- so helpers spin on the generation
// for up to kSpin after their last item before they block (in fast mode the next step's run comes
// within microseconds; in real-time mode they are asleep between steps), and the caller spins for
// the last item instead of sleeping. Results must not depend on which thread ran an item (each
// item writes only its own output), so runs are deterministic whatever the thread count.
#pragma once

#include <atomic>
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
  void drain(std::unique_lock<std::mutex>& lock);

  std::vector<std::thread> threads_;
  std::mutex mutex_;                 // guards task_, count_, next_, failure_ and the waits
  std::condition_variable start_;
  const std::function<void(std::size_t)>* task_ = nullptr;
  std::size_t count_ = 0;
  std::size_t next_ = 0;                      // next item to hand out
  std::atomic<std::size_t> finished_{0};      // items done in this run (written under mutex_)
  std::atomic<std::uint64_t> generation_{0};  // bumped per run (under mutex_); helpers spin on it
  std::atomic<bool> stop_{false};
  std::exception_ptr failure_;
};

}  // namespace hadal
