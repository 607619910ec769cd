// RayBatch and RayHits: the rays a sensor casts against the world for one state snapshot, and what they
// hit, as structure-of-arrays (one entry per ray in every array, float like Embree).
//
// A ray is  p_W(t) = p_WO + t d_W,  t in [t_near, t_far],  expressed in the world frame W, with
//   p_WO  origin O of the ray in W [m]
//   d_W   direction in W, unit length (|d|^2 within 1e-5 of 1), so that t is a distance in metres
//   t_near, t_far  0 <= t_near <= t_far [m]; t_far may be +inf
// A ray may name a body it passes through (ignore_body): a sensor's own vehicle, whose hull its rays
// start inside of or graze. Hits on that body are skipped (the ray is continued 0.1 mm past each such
// hit, at most kMaxIgnoredHits times, then reported as a miss), so distance, body, ... describe the
// first hit on anything else. kNoHit (the default) ignores nothing.
// The batch also carries the snapshot it belongs to (sim time, step count, the pose X_WB of every
// body, indexed like SimState::vehicles), so that rays cast for step k see the bodies where they were
// at step k however long the job waits in the ray-cast service's queue.
//
// A hit reports, per ray i:
//   distance[i]   t of the nearest hit in [t_near, t_far] [m]; +inf for a miss. The hit point is
//                 p_WO + distance d_W.
//   n_W_*[i]      unit geometric normal of the hit triangle in W, oriented by the triangle's winding
//                 (right-hand rule v0 -> v1 -> v2: outward for TriangleMesh's counter-clockwise
//                 convention). It is NOT flipped towards the ray: dot(n_W, d_W) > 0 means the ray hit a
//                 back face (e.g. it started inside a hull). (0, 0, 0) for a miss.
//   body[i]       index of the body whose instance was hit (index into SimState::vehicles),
//                 kStaticBody (-1) for the static world, kNoHit (-2) for a miss.
//   mesh[i]       id returned by EmbreeScene::add_static_mesh / add_body_mesh, kNoHit for a miss.
//   material[i]   material id given for that mesh, plus TriangleMesh::triangle_materials[triangle] when
//                 the mesh has per-triangle materials; kInvalidIndex for a miss.
//   triangle[i]   index of the triangle in that mesh (TriangleMesh::indices[3 triangle ...]);
//                 kInvalidIndex for a miss.
//   tex_u[i], tex_v[i]  texture coordinates of the hit point, interpolated linearly over the triangle
//                 from the mesh's uvs (TriangleMesh's convention); NaN for a miss or a mesh without uvs.
#pragma once

#include "hadal/core/state.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace hadal::geometry {

inline constexpr std::int32_t kStaticBody = -1;  // RayHits::body of a hit on the static world
inline constexpr std::int32_t kNoHit = -2;       // RayHits::body and RayHits::mesh of a miss
inline constexpr std::uint32_t kInvalidIndex = std::numeric_limits<std::uint32_t>::max();
inline constexpr int kMaxIgnoredHits = 16;  // crossings of an ignored body's surface per ray
inline constexpr float kIgnoredHitStep = 1e-4f;  // a ray continues this far past an ignored hit [m]

// How the rays of a batch relate to each other; chooses Embree's traversal mode. Coherent: neighbours
// in the arrays start near each other and point in similar directions (a camera's pixels in row-major
// or tile order). Incoherent: anything else (DVL beams of many vehicles, scattered rays). Occlusion
// queries are always traced incoherent (EmbreeScene::occluded says why).
enum class RayCoherence { kCoherent, kIncoherent };

struct RayBatch {
  // The snapshot the rays belong to (copied into RayHits).
  double sim_time = 0.0;  // [s]
  std::uint64_t step_count = 0;
  std::vector<Eigen::Isometry3d> X_WB;  // pose of body B in W, one per body index (SimState::vehicles)

  RayCoherence coherence = RayCoherence::kIncoherent;

  std::vector<float> p_WO_x, p_WO_y, p_WO_z;  // ray origins in W [m]
  std::vector<float> d_W_x, d_W_y, d_W_z;     // unit ray directions in W
  std::vector<float> t_near, t_far;           // [m]
  // Empty (no ray ignores a body) or one per ray: the body index whose hits the ray passes through,
  // kNoHit for none (header text).
  std::vector<std::int32_t> ignore_body;

  std::size_t size() const { return p_WO_x.size(); }

  // True when all eight ray arrays have the same length and ignore_body is empty or as long.
  bool consistent() const {
    const std::size_t n = p_WO_x.size();
    return p_WO_y.size() == n && p_WO_z.size() == n && d_W_x.size() == n && d_W_y.size() == n &&
           d_W_z.size() == n && t_near.size() == n && t_far.size() == n &&
           (ignore_body.empty() || ignore_body.size() == n);
  }

  // Removes every ray (keeps the snapshot and the arrays' capacity).
  void clear_rays() {
    for (auto* v : {&p_WO_x, &p_WO_y, &p_WO_z, &d_W_x, &d_W_y, &d_W_z, &t_near, &t_far}) v->clear();
    ignore_body.clear();
  }

  void reserve(std::size_t n) {
    for (auto* v : {&p_WO_x, &p_WO_y, &p_WO_z, &d_W_x, &d_W_y, &d_W_z, &t_near, &t_far}) v->reserve(n);
    ignore_body.reserve(n);
  }

  void add_ray(const Eigen::Vector3f& p_WO, const Eigen::Vector3f& d_W, float t_min = 0.0f,
               float t_max = std::numeric_limits<float>::infinity(), std::int32_t ignored_body = kNoHit) {
    if (ignored_body != kNoHit && ignore_body.size() < p_WO_x.size()) ignore_body.resize(p_WO_x.size(), kNoHit);
    if (!ignore_body.empty() || ignored_body != kNoHit) ignore_body.push_back(ignored_body);
    p_WO_x.push_back(p_WO.x());
    p_WO_y.push_back(p_WO.y());
    p_WO_z.push_back(p_WO.z());
    d_W_x.push_back(d_W.x());
    d_W_y.push_back(d_W.y());
    d_W_z.push_back(d_W.z());
    t_near.push_back(t_min);
    t_far.push_back(t_max);
  }

  // Takes sim time and step count from a state snapshot, and the ray bodies' poses at it (world_scene.h;
  // Simulation::ray_body_poses); without them every vehicle's X_WB (a world without moving bodies).
  void set_snapshot(const SimState& state, std::vector<Eigen::Isometry3d> poses = {}) {
    sim_time = state.time;
    step_count = state.step_count;
    X_WB = std::move(poses);
    if (!X_WB.empty()) return;
    X_WB.reserve(state.vehicles.size());
    for (const VehicleState& vehicle : state.vehicles) X_WB.push_back(vehicle.body.X_WB);
  }
};

struct RayHits {
  double sim_time = 0.0;  // of the snapshot the rays were cast in [s]
  std::uint64_t step_count = 0;

  std::vector<float> distance;              // [m], +inf for a miss
  std::vector<float> n_W_x, n_W_y, n_W_z;   // unit geometric normal in W (winding-oriented)
  std::vector<std::int32_t> body;           // body index, kStaticBody, or kNoHit
  std::vector<std::int32_t> mesh;           // scene mesh id or kNoHit
  std::vector<std::uint32_t> material;      // material id or kInvalidIndex
  std::vector<std::uint32_t> triangle;      // triangle index in the mesh or kInvalidIndex
  std::vector<float> tex_u, tex_v;          // texture coordinates, NaN without

  std::size_t size() const { return distance.size(); }
  bool hit(std::size_t i) const { return std::isfinite(distance[i]); }

  void resize(std::size_t n) {
    for (auto* v : {&distance, &n_W_x, &n_W_y, &n_W_z, &tex_u, &tex_v}) v->resize(n);
    body.resize(n);
    mesh.resize(n);
    material.resize(n);
    triangle.resize(n);
  }
};

}  // namespace hadal::geometry
