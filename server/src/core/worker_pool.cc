#include "worker_pool.h"

#include <chrono>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace hadal {

namespace {

// How long a helper keeps polling for the next run after finishing its items.
constexpr std::chrono::microseconds kSpin(200);

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

}  // namespace

WorkerPool::WorkerPool(unsigned helpers) {
  threads_.reserve(helpers);
  for (unsigned i = 0; i < helpers; ++i) threads_.emplace_back([this] { work_loop(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

// Takes items until none are left; `lock` holds mutex_ on entry and exit.
void WorkerPool::drain(std::unique_lock<std::mutex>& lock) {
  while (next_ < count_) {
    const std::size_t item = next_++;
    const std::function<void(std::size_t)>& task = *task_;
    lock.unlock();
    std::exception_ptr failure;
    try {
      task(item);
    } catch (...) {
      failure = std::current_exception();
    }
    lock.lock();
    std::size_t done = 1;
    if (failure && !failure_) {
      failure_ = failure;
      done += count_ - next_;  // skip what was not handed out
      next_ = count_;
    }
    finished_.fetch_add(done, std::memory_order_release);
  }
}

void WorkerPool::work_loop() {
  std::uint64_t seen = 0;
  for (;;) {
    const auto spin_until = std::chrono::steady_clock::now() + kSpin;
    while (generation_.load(std::memory_order_acquire) == seen && !stop_.load(std::memory_order_relaxed) &&
           std::chrono::steady_clock::now() < spin_until) {
      for (int k = 0; k < 64; ++k) cpu_relax();
    }
    std::unique_lock<std::mutex> lock(mutex_);
    start_.wait(lock, [&] { return stop_.load() || generation_.load() != seen; });
    if (stop_) return;
    seen = generation_.load();
    drain(lock);
  }
}

void WorkerPool::run(std::size_t count, const std::function<void(std::size_t)>& task) {
  if (count == 0) return;
  if (threads_.empty() || count == 1) {
    for (std::size_t i = 0; i < count; ++i) task(i);
    return;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  task_ = &task;
  count_ = count;
  next_ = 0;
  finished_.store(0, std::memory_order_relaxed);
  failure_ = nullptr;
  generation_.fetch_add(1, std::memory_order_release);
  lock.unlock();
  start_.notify_all();  // no system call when every helper is still spinning
  lock.lock();
  drain(lock);
  lock.unlock();
  // The other items are running on helpers: poll rather than sleep (a wake-up costs as much).
  while (finished_.load(std::memory_order_acquire) < count) cpu_relax();
  lock.lock();
  count_ = 0;
  task_ = nullptr;
  if (failure_) {
    std::exception_ptr failure = failure_;
    failure_ = nullptr;
    std::rethrow_exception(failure);
  }
}

}  // namespace hadal
