// RaycastService: traces batches of rays (camera frames, DVL beams, altimeters) on a pool of worker
// threads, without blocking the caller (the physics loop).
//
// A job is one RayBatch: rays in W plus the snapshot they belong to (sim time, step count, X_WB of
// every body). Jobs run one at a time, in submission order; a job's rays are split into chunks that
// all workers take from (dynamic load balancing, chunks of at most `chunk_rays`). Before a job's first
// ray is traced, the scene's body instances are moved to that job's poses (EmbreeScene::
// set_body_poses), so each batch sees the world as it was in its own snapshot even when a later
// snapshot has already been submitted. Results come back in submission order: through a
// std::future, or a callback run on a worker thread before the next job starts (keep it short: hand
// the hits to a publisher). RayHits carries the batch's sim time and step count.
//
// Errors: submit() throws at once (never blocks on tracing) for a batch whose arrays differ in
// length, whose poses are missing, non-finite or not rigid (std::invalid_argument), or after
// shutdown() (std::logic_error). A bad ray (non-finite, direction not unit, t_near < 0 or
// t_near > t_far) fails its job: the future throws / the callback gets InvalidRayError naming the
// lowest bad ray index found.
//
// Configuration (C++ only for now; a scenario key would map 1:1):
//   num_threads  worker threads, 0 = std::thread::hardware_concurrency()  (default 0)
//   path         Embree query path, QueryPath::kAuto = streams (default)
//   chunk_rays   most rays a worker takes at a time, >= 16 (default 1024)
//
// Scene work: besides ray batches, a job may be any work on the posed scene (a camera frame: rays,
// shadow rays and shading in bands). submit(X_WB, work) queues it like a batch (same order, same
// snapshot rule); one worker calls work(scene, parallel) with the scene posed at X_WB, and `parallel`
// spreads the tasks of a loop over every worker, the calling one included, returning when all are done
// (a task's exception is rethrown there, the lowest-indexed task's first). Every worker runs in
// FTZ/DAZ mode, so results do not depend on which worker ran a task. The future is ready when work()
// returns, and carries its exception.
//
// Buffers: results are written into RayHits whose vectors are reused when the caller hands finished
// results back with recycle() (a camera does this every frame; allocating and zeroing 10 MB per
// 640x480 frame would otherwise cost ~1 ms).
#pragma once

#include "hadal/core/parallel_for.h"
#include "hadal/geometry/embree_scene.h"
#include "hadal/geometry/ray_batch.h"

#include <Eigen/Geometry>

#include <cstddef>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <vector>

namespace hadal::geometry {

struct RaycastServiceOptions {
  int num_threads = 0;  // 0: std::thread::hardware_concurrency() (at least 1)
  QueryPath path = QueryPath::kAuto;
  std::size_t chunk_rays = 1024;
};

class RaycastService {
 public:
  // Called with the hits, or with empty hits and the error that failed the job. Runs on a worker
  // thread; must not throw (std::terminate) and must not call shutdown() or destroy the service.
  using Callback = std::function<void(RayHits hits, std::exception_ptr error)>;

  // Takes the scene (built here if it is not yet) and starts the workers. Throws std::invalid_argument
  // for negative num_threads or chunk_rays < 16.
  explicit RaycastService(EmbreeScene scene, RaycastServiceOptions options = {});
  ~RaycastService();  // shutdown()
  RaycastService(const RaycastService&) = delete;
  RaycastService& operator=(const RaycastService&) = delete;

  std::future<RayHits> submit(RayBatch batch);
  void submit(RayBatch batch, Callback on_done);

  // Scene work (above). Throws at once, like submit(RayBatch), for missing or bad poses, an empty
  // work function or after shutdown().
  using SceneWork = std::function<void(const EmbreeScene& scene, const ParallelFor& parallel)>;
  std::future<void> submit(std::vector<Eigen::Isometry3d> X_WB, SceneWork work);

  // Hands finished results back so that a later job can write into their buffers.
  void recycle(RayHits hits);

  // Completes every job already submitted, then joins the workers. Idempotent; later submit() calls
  // throw std::logic_error. Throws std::logic_error when called from a worker (from a callback).
  void shutdown();

  int num_threads() const;
  QueryPath path() const;  // the path used (never kAuto)
  // For inspection (mesh_info, num_bodies). Tracing through it while jobs run would race with the
  // workers' pose updates.
  const EmbreeScene& scene() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hadal::geometry
