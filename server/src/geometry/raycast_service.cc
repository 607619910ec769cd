#include "hadal/geometry/raycast_service.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#if defined(__SSE__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

namespace hadal::geometry {
namespace {

// Finished results kept for reuse (a camera needs one or two in flight).
constexpr std::size_t kMaxSpareBuffers = 4;

// How long an idle worker, or a parallel loop's owner waiting for the others' tasks, spins before it
// sleeps: a camera frame's dozen parallel loops (bands, forward scatter's levels, exposure) follow each
// other within microseconds, and a sleep costs the thread that wakes it a futex call and, on a virtual
// machine, an inter-processor interrupt (~4 % of a frame's CPU in perf before spinning).
constexpr std::chrono::microseconds kSpin{150};

// Spins, pausing, until done() or kSpin has passed; whether done().
template <typename Done>
bool spin_until(const Done& done) {
  const auto start = std::chrono::steady_clock::now();
  for (unsigned i = 1;; ++i) {
    if (done()) return true;
#if defined(__SSE__)
    _mm_pause();
#endif
    if (i % 64 == 0 && std::chrono::steady_clock::now() - start > kSpin) return done();
  }
}

}  // namespace

struct RaycastService::Impl {
  // One parallel loop of a running scene work: the workers take its tasks by index.
  struct TaskLoop {
    const std::function<void(std::size_t)>* task = nullptr;
    std::size_t count = 0;
    std::atomic<std::size_t> next{0};
    std::atomic<std::size_t> finished{0};
    std::mutex error_mutex;
    std::size_t error_index = std::numeric_limits<std::size_t>::max();
    std::exception_ptr error;
  };

  struct Job {
    SceneWork work;  // empty: a ray batch
    std::promise<void> work_done;
    std::shared_ptr<TaskLoop> loop;  // the work's open loop, if any (guarded by Impl::mutex)
    RayBatch batch;
    RayHits hits;
    std::promise<RayHits> promise;
    Callback callback;  // empty: deliver through `promise`
    std::size_t num_rays = 0;
    std::size_t chunk = 0;
    std::atomic<std::size_t> next_ray{0};  // first ray of the next chunk to hand out
    std::atomic<std::size_t> rays_done{0};
    std::mutex error_mutex;
    std::size_t error_ray = std::numeric_limits<std::size_t>::max();
    std::exception_ptr error;

    void record_error(std::size_t ray, std::exception_ptr e) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (error == nullptr || ray < error_ray) {
        error_ray = ray;
        error = std::move(e);
      }
    }
  };

  EmbreeScene scene;
  RaycastServiceOptions options;
  QueryPath path = QueryPath::kStream;
  int num_threads = 1;

  std::mutex mutex;  // guards everything below except `workers` and `generation`
  std::condition_variable wake;
  // Bumped (holding `mutex`) at every change that may give an idle worker something to do: a worker
  // spinning before it sleeps watches it.
  std::atomic<std::uint64_t> generation{0};

  // Marks a change of the state under `mutex` (held by the caller) that may give a worker work.
  void changed() { generation.fetch_add(1, std::memory_order_release); }
  std::deque<std::shared_ptr<Job>> queue;
  std::shared_ptr<Job> current;  // the job whose rays are being traced
  bool preparing = false;        // a worker is moving the bodies for (or delivering) the next job
  bool stopping = false;
  std::vector<RayHits> spare;

  std::mutex shutdown_mutex;  // guards `workers`
  std::vector<std::thread> workers;

  Impl(EmbreeScene s, RaycastServiceOptions o) : scene(std::move(s)), options(o) {}

  std::shared_ptr<Job> make_job(RayBatch batch) {
    if (!batch.consistent()) {
      throw std::invalid_argument("RaycastService::submit: the ray arrays of the batch at sim time " +
                                  std::to_string(batch.sim_time) + " s differ in length");
    }
    try {
      scene.check_body_poses(batch.X_WB);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("RaycastService::submit: batch at sim time " +
                                  std::to_string(batch.sim_time) + " s: " + e.what());
    }
    auto job = std::make_shared<Job>();
    job->num_rays = batch.size();
    job->batch = std::move(batch);
    return job;
  }

  void enqueue(std::shared_ptr<Job> job) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (stopping) throw std::logic_error("RaycastService::submit: the service is shut down");
      queue.push_back(std::move(job));
      changed();
    }
    wake.notify_one();
  }

  // Best-fitting spare buffer for n rays (smallest that holds n, else the largest), or a new one.
  RayHits take_spare(std::size_t n) {
    if (spare.empty()) return RayHits{};
    auto best = spare.end();
    for (auto it = spare.begin(); it != spare.end(); ++it) {
      const std::size_t capacity = it->distance.capacity();
      if (best == spare.end()) {
        best = it;
        continue;
      }
      const std::size_t best_capacity = best->distance.capacity();
      const bool fits = capacity >= n, best_fits = best_capacity >= n;
      if ((fits && (!best_fits || capacity < best_capacity)) || (!fits && !best_fits && capacity > best_capacity)) {
        best = it;
      }
    }
    RayHits hits = std::move(*best);
    spare.erase(best);
    return hits;
  }

  void give_back(RayHits hits) {
    std::lock_guard<std::mutex> lock(mutex);
    spare.push_back(std::move(hits));
    if (spare.size() > kMaxSpareBuffers) {
      auto smallest = std::min_element(spare.begin(), spare.end(), [](const RayHits& a, const RayHits& b) {
        return a.distance.capacity() < b.distance.capacity();
      });
      spare.erase(smallest);
    }
  }

  // Moves the bodies to the job's snapshot and sizes its hits. Runs while no ray is traced.
  bool prepare(Job& job, RayHits storage) {
    try {
      scene.set_body_poses(job.batch.X_WB);
      job.hits = std::move(storage);
      job.hits.resize(job.num_rays);
      const std::size_t threads = static_cast<std::size_t>(num_threads);
      const std::size_t target = (job.num_rays + 4 * threads - 1) / (4 * threads);
      const std::size_t chunk = std::min(options.chunk_rays, std::max<std::size_t>(64, target));
      job.chunk = std::max<std::size_t>(16, chunk / 16 * 16);  // keeps chunks 16-byte aligned
      return true;
    } catch (...) {
      job.record_error(0, std::current_exception());
      return false;
    }
  }

  void deliver(Job& job) noexcept {
    if (job.error != nullptr) {
      give_back(std::move(job.hits));
      if (job.callback) {
        job.callback(RayHits{}, job.error);
      } else {
        job.promise.set_exception(job.error);
      }
      return;
    }
    job.hits.sim_time = job.batch.sim_time;
    job.hits.step_count = job.batch.step_count;
    if (job.callback) {
      job.callback(std::move(job.hits), nullptr);
    } else {
      job.promise.set_value(std::move(job.hits));
    }
  }

  // Runs tasks of `loop` until none is left to take; the worker finishing the last one wakes the loop's
  // owner.
  void run_tasks(TaskLoop& loop) {
    for (std::size_t i = loop.next.fetch_add(1); i < loop.count; i = loop.next.fetch_add(1)) {
      try {
        (*loop.task)(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(loop.error_mutex);
        if (loop.error == nullptr || i < loop.error_index) {
          loop.error_index = i;
          loop.error = std::current_exception();
        }
      }
      if (loop.finished.fetch_add(1) + 1 == loop.count) {
        std::lock_guard<std::mutex> lock(mutex);
        wake.notify_all();
      }
    }
  }

  // The ParallelFor handed to a scene work: publishes the loop to the other workers, works on it, waits
  // for the tasks the others took, rethrows a task's exception.
  void parallel_for(Job& job, std::size_t count, const std::function<void(std::size_t)>& task) {
    if (count == 0) return;
    auto loop = std::make_shared<TaskLoop>();
    loop->task = &task;
    loop->count = count;
    {
      std::lock_guard<std::mutex> lock(mutex);
      job.loop = loop;
      changed();
    }
    wake.notify_all();
    run_tasks(*loop);
    const auto finished = [&] { return loop->finished.load() == count; };
    spin_until(finished);
    {
      std::unique_lock<std::mutex> lock(mutex);
      wake.wait(lock, finished);
      job.loop.reset();
    }
    if (loop->error != nullptr) std::rethrow_exception(loop->error);
  }

  // Runs a scene work on this worker (the scene posed at its snapshot), then releases the next job.
  void run_work(const std::shared_ptr<Job>& job) {
    try {
      const ParallelFor parallel = [this, &job](std::size_t count, const std::function<void(std::size_t)>& task) {
        parallel_for(*job, count, task);
      };
      job->work(scene, parallel);
      job->work_done.set_value();
    } catch (...) {
      job->work_done.set_exception(std::current_exception());
    }
    {
      std::lock_guard<std::mutex> lock(mutex);
      current.reset();
      changed();
    }
    wake.notify_all();
  }

  // Traces chunks of the current job until none is left; the worker completing the last chunk
  // delivers the job and releases the next one.
  void trace_chunks(const std::shared_ptr<Job>& job) {
    for (;;) {
      const std::size_t begin = job->next_ray.fetch_add(job->chunk);
      if (begin >= job->num_rays) return;
      const std::size_t end = std::min(job->num_rays, begin + job->chunk);
      try {
        scene.intersect(job->batch, begin, end, path, job->hits);
      } catch (const InvalidRayError& e) {
        job->record_error(e.ray_index(), std::current_exception());
      } catch (...) {
        job->record_error(begin, std::current_exception());
      }
      // acq_rel read-modify-write: every chunk's hits are visible to the worker that completes.
      const std::size_t done = job->rays_done.fetch_add(end - begin) + (end - begin);
      if (done == job->num_rays) {
        deliver(*job);  // before the next job may start: results arrive in submission order
        {
          std::lock_guard<std::mutex> lock(mutex);
          current.reset();
          changed();
        }
        wake.notify_all();
        return;
      }
    }
  }

  void work() {
#if defined(__SSE__)
    // Embree's recommendation for its traversal kernels: no denormal slow paths.
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      if (current != nullptr && current->loop != nullptr && current->loop->next.load() < current->loop->count) {
        const std::shared_ptr<TaskLoop> loop = current->loop;
        lock.unlock();
        run_tasks(*loop);
        lock.lock();
        continue;
      }
      if (current != nullptr && current->next_ray.load() < current->num_rays) {
        const std::shared_ptr<Job> job = current;
        lock.unlock();
        trace_chunks(job);
        lock.lock();
        continue;
      }
      if (current == nullptr && !preparing && !queue.empty()) {
        std::shared_ptr<Job> job = std::move(queue.front());
        queue.pop_front();
        preparing = true;
        RayHits storage = job->work ? RayHits{} : take_spare(job->num_rays);
        lock.unlock();
        if (job->work) {
          const bool posed = prepare(*job, std::move(storage));
          lock.lock();
          preparing = false;
          changed();
          if (!posed) {
            job->work_done.set_exception(job->error);
            wake.notify_all();
            continue;
          }
          current = job;
          lock.unlock();
          run_work(job);
          lock.lock();
          continue;
        }
        const bool ready = prepare(*job, std::move(storage)) && job->num_rays > 0;
        if (!ready) deliver(*job);  // failed or empty: still in order, before the next job starts
        lock.lock();
        preparing = false;
        changed();
        if (ready) current = std::move(job);
        wake.notify_all();
        continue;
      }
      if (stopping && queue.empty() && current == nullptr && !preparing) return;
      // Nothing to do: spin a while for a change before sleeping (kSpin).
      const std::uint64_t seen = generation.load(std::memory_order_relaxed);
      lock.unlock();
      spin_until([&] { return generation.load(std::memory_order_acquire) != seen; });
      lock.lock();
      if (generation.load(std::memory_order_relaxed) != seen) continue;
      wake.wait(lock);
    }
  }
};

RaycastService::RaycastService(EmbreeScene scene, RaycastServiceOptions options) {
  if (options.num_threads < 0) {
    throw std::invalid_argument("RaycastService: num_threads must be >= 0 (got " +
                                std::to_string(options.num_threads) + ")");
  }
  if (options.chunk_rays < 16) {
    throw std::invalid_argument("RaycastService: chunk_rays must be >= 16 (got " +
                                std::to_string(options.chunk_rays) + ")");
  }
  if (!scene.built()) scene.build();
  impl_ = std::make_unique<Impl>(std::move(scene), options);
  impl_->path = options.path == QueryPath::kAuto ? QueryPath::kStream : options.path;
  impl_->num_threads = options.num_threads > 0
                           ? options.num_threads
                           : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  std::lock_guard<std::mutex> lock(impl_->shutdown_mutex);
  for (int i = 0; i < impl_->num_threads; ++i) impl_->workers.emplace_back([this] { impl_->work(); });
}

RaycastService::~RaycastService() { shutdown(); }

std::future<RayHits> RaycastService::submit(RayBatch batch) {
  std::shared_ptr<Impl::Job> job = impl_->make_job(std::move(batch));
  std::future<RayHits> result = job->promise.get_future();
  impl_->enqueue(std::move(job));
  return result;
}

void RaycastService::submit(RayBatch batch, Callback on_done) {
  if (!on_done) throw std::invalid_argument("RaycastService::submit: empty callback");
  std::shared_ptr<Impl::Job> job = impl_->make_job(std::move(batch));
  job->callback = std::move(on_done);
  impl_->enqueue(std::move(job));
}

std::future<void> RaycastService::submit(std::vector<Eigen::Isometry3d> X_WB, SceneWork work) {
  if (!work) throw std::invalid_argument("RaycastService::submit: empty scene work");
  RayBatch snapshot;  // no rays: the poses only
  snapshot.X_WB = std::move(X_WB);
  std::shared_ptr<Impl::Job> job = impl_->make_job(std::move(snapshot));
  job->work = std::move(work);
  std::future<void> result = job->work_done.get_future();
  impl_->enqueue(std::move(job));
  return result;
}

void RaycastService::recycle(RayHits hits) { impl_->give_back(std::move(hits)); }

void RaycastService::shutdown() {
  std::lock_guard<std::mutex> guard(impl_->shutdown_mutex);
  for (const std::thread& worker : impl_->workers) {
    if (worker.get_id() == std::this_thread::get_id()) {
      throw std::logic_error("RaycastService::shutdown: called from a worker thread (a callback)");
    }
  }
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stopping = true;
    impl_->changed();
  }
  impl_->wake.notify_all();
  for (std::thread& worker : impl_->workers) worker.join();
  impl_->workers.clear();
}

int RaycastService::num_threads() const { return impl_->num_threads; }
QueryPath RaycastService::path() const { return impl_->path; }
const EmbreeScene& RaycastService::scene() const { return impl_->scene; }

}  // namespace hadal::geometry
