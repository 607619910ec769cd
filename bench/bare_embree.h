// What the benchmarks compare Hadal's ray casting with: a bare rtcIntersect1 loop over a RayBatch's
// rays (RTCRayHit filled from the batch's arrays, tfar/Ng/primID/geomID stored to preallocated arrays),
// and the plain parallel loop both use on several threads (items taken from an atomic counter, the
// ray-cast service's load balancing; every thread in Embree's recommended FTZ/DAZ mode).
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <functional>
#include <thread>
#include <vector>

#if defined(__SSE__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

#include "hadal/geometry/ray_batch.h"

namespace hadal::bench {

inline void set_ftz_daz() {
#if defined(__SSE__)
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
}

// Runs task(i) for i in [0, count) on `threads` threads (the caller and threads - 1 helpers started
// here), each taking the next item from a shared counter.
inline void run_on_threads(int threads, std::size_t count, const std::function<void(std::size_t)>& task) {
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    set_ftz_daz();
    for (std::size_t i = next.fetch_add(1); i < count; i = next.fetch_add(1)) task(i);
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& h : helpers) h.join();
}

// What a bare loop keeps per ray.
struct BareHits {
  std::vector<float> t, ng_x, ng_y, ng_z;
  std::vector<unsigned> prim, geom;
  explicit BareHits(std::size_t n) : t(n), ng_x(n), ng_y(n), ng_z(n), prim(n), geom(n) {}
};

inline void bare_loop(RTCScene scene, const geometry::RayBatch& r, std::size_t begin, std::size_t end, BareHits& out) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (std::size_t i = begin; i < end; ++i) {
    RTCRayHit rh;
    rh.ray.org_x = r.p_WO_x[i];
    rh.ray.org_y = r.p_WO_y[i];
    rh.ray.org_z = r.p_WO_z[i];
    rh.ray.tnear = r.t_near[i];
    rh.ray.dir_x = r.d_W_x[i];
    rh.ray.dir_y = r.d_W_y[i];
    rh.ray.dir_z = r.d_W_z[i];
    rh.ray.time = 0.0f;
    rh.ray.tfar = r.t_far[i];
    rh.ray.mask = ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    out.t[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? INFINITY : rh.ray.tfar;
    out.ng_x[i] = rh.hit.Ng_x;
    out.ng_y[i] = rh.hit.Ng_y;
    out.ng_z[i] = rh.hit.Ng_z;
    out.prim[i] = rh.hit.primID;
    out.geom[i] = rh.hit.geomID;
  }
}

// The bare loop over all rays in chunks of 1024 on `threads` threads.
inline void bare(RTCScene scene, const geometry::RayBatch& rays, int threads, BareHits& out) {
  const std::size_t chunk = 1024, chunks = (rays.size() + chunk - 1) / chunk;
  run_on_threads(threads, chunks, [&](std::size_t k) {
    bare_loop(scene, rays, k * chunk, std::min(rays.size(), (k + 1) * chunk), out);
  });
}

}  // namespace hadal::bench
