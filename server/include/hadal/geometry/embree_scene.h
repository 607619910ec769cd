// EmbreeScene: the world as Embree ray-traces it — a static part whose BVH is built once, plus one
// instance per dynamic body, moved to the body's pose before each batch of rays is traced.
//
// Two levels (one Embree device, all scenes in it):
//   static scene S     every static mesh (seabed, wrecks, landers), vertices given in W
//   body scene B_i     every mesh of body i, vertices given in its body frame B
//   top-level scene T  { instance of S with X_WS = identity } + { instance of B_i with X_WB_i }
// Rays are traced against T. Moving a body changes one 3x4 instance transform and re-commits T,
// whose BVH has one leaf per instance (microseconds); the static BVH is never rebuilt.
// Normals: Embree reports an instanced hit's geometric normal in the instance's object frame; it is
// rotated into W as n_W = R_WB n_B and normalised (poses are rigid, so no inverse transpose is needed).
//
// Precision: Embree works in float32. Coordinates are quantised to ~6e-8 of their magnitude (61 um at
// 1 km from W's origin, 1 mm at 10 km), and distances carry errors of a few float ulp of that size.
// The default (non-robust) triangle test is used: rays through shared inner edges and vertices of a
// mesh do not slip through (tested), and RTC_SCENE_FLAG_ROBUST cost 12-25 % of throughput on the
// benchmark seabed. A ray through a shared edge meets both triangles at the same distance; which
// of the two is reported (triangle, normal) may differ between query paths, never the distance.
// Cost of instancing: with bodies present every ray goes through Embree's two-level traversal (the
// static scene is an identity instance), measured at 8-20 % of single-ray and ~25 % of stream
// throughput on the benchmark seabed; without bodies the static scene is traced directly.
//
// Mesh ids: add_static_mesh and add_body_mesh return consecutive ids starting at 0, reported in
// RayHits::mesh. Material of a hit: the mesh's material_id, plus triangle_materials[t] when the mesh
// has per-triangle materials (so a caller can place a mesh's materials at a base offset in its own
// material table).
//
// Lifecycle: add meshes, build() once, then set_body_poses() / intersect(). intersect() is const and
// may run on many threads at once; set_body_poses() must not run concurrently with intersect() on the
// same view (RaycastService serialises them: it owns its view). Views (view()) share the world's
// geometry and pose their bodies independently: the stepping thread's sensors and the ray-cast workers
// each trace their own view of the one world (docs/ARCHITECTURE.md, "One ray-cast world").
#pragma once

#include "hadal/geometry/ray_batch.h"
#include "hadal/geometry/ray_kernels.h"
#include "hadal/geometry/triangle_mesh.h"

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

// Embree's opaque scene handle (rtcore_scene.h declares the same typedef), so that this header does
// not pull in Embree.
struct RTCSceneTy;

namespace hadal::geometry {

// How intersect() asks Embree for hits. kSingle: one rtcIntersect1 per ray. kPacket: rtcIntersect16
// (or 8 / 4, the widest the CPU runs natively) on consecutive rays. kStream: rtcIntersectNp on blocks
// of consecutive rays, reading the batch's arrays in place. kAuto picks kStream, the fastest for
// coherent and incoherent batches alike on bench/raycast.cc (1M-triangle seabed, one thread: camera
// rays ~6x, scattered rays ~1.5x a bare rtcIntersect1 loop; packets ~4x and ~1.4x).
// All paths return bit-identical distances, bodies, meshes and materials for the same rays (tested);
// see above for ties at shared edges. For one path, results do not depend on how rays are split
// into ranges as long as ranges start at multiples of 16 rays (RaycastService's chunks do).
enum class QueryPath { kAuto, kSingle, kPacket, kStream };

const char* to_string(QueryPath path);

// A ray that breaks RayBatch's rules (non-finite values, direction not unit, t_near < 0 or
// t_near > t_far); what() names the ray index and the problem.
class InvalidRayError : public std::invalid_argument {
 public:
  InvalidRayError(std::size_t ray_index, const std::string& message)
      : std::invalid_argument(message), ray_index_(ray_index) {}
  std::size_t ray_index() const { return ray_index_; }

 private:
  std::size_t ray_index_;
};

struct SceneMeshInfo {
  std::string name;                  // as given to add_*_mesh, for messages
  std::int32_t body = kStaticBody;   // owning body index, or kStaticBody
  std::uint32_t material_id = 0;
  std::size_t num_triangles = 0;
};

// What add_static_mesh may assume of a static mesh.
enum class StaticShape { kAny, kHeightField };

// A body instance's bounds (EmbreeScene::body_bounds_W).
struct BodyBounds {
  std::int32_t body = 0;
  Eigen::AlignedBox3d box_W;
};

class EmbreeScene {
 public:
  // device_config: Embree's rtcNewDevice configuration string ("" for defaults, e.g. "threads=1"
  // to build BVHs on one thread). kernels (geometry/ray_kernels.h): kPortable adds "isa=sse4.2" unless
  // device_config names an ISA itself, and recomputes every hit (refine_hit, geometry/hit_refinement.h).
  // Throws std::runtime_error when Embree cannot create the device.
  explicit EmbreeScene(const std::string& device_config = "", RayKernels kernels = RayKernels::kNative);
  ~EmbreeScene();
  // A moved-from scene may only be destroyed or assigned to.
  EmbreeScene(EmbreeScene&&) noexcept;
  EmbreeScene& operator=(EmbreeScene&&) noexcept;
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Adds a static mesh (vertices in W) / a mesh of body `body_index` (vertices in B; a body may have
  // several meshes, all moved together). The mesh is copied into Embree-owned, padded buffers.
  // Throws std::invalid_argument naming the mesh for: no triangles or no vertices, array sizes that
  // are not multiples of 3, a vertex index >= the number of vertices, non-finite positions,
  // triangle_materials of the wrong length or (when `materials` is non-empty) out of its range, and
  // a negative body index. Throws std::logic_error after build().
  // shape kHeightField declares the static mesh a height field z = h(x, y) (every vertical line meets
  // it at most once; the caller vouches for it, e.g. a terrain grid): then its triangles must face up
  // (otherwise std::invalid_argument) and static_height_field_max_slope() reports its steepest slope.
  int add_static_mesh(const TriangleMesh& mesh_W, std::uint32_t material_id = 0,
                      const std::string& name = "static mesh", StaticShape shape = StaticShape::kAny);
  int add_body_mesh(int body_index, const TriangleMesh& mesh_B, std::uint32_t material_id = 0,
                    const std::string& name = "body mesh");

  // When the static world is one mesh declared a height field: its steepest slope L = max |grad h| over
  // its triangles (|h(q) - h(p)| <= L |q - p|_xy everywhere on it, so a segment that starts above it
  // and climbs faster than L never meets it). nullopt otherwise.
  std::optional<double> static_height_field_max_slope() const;
  // The same over the triangles whose xy extent meets `region_xy` (an upper bound of it:
  // geometry/slope_grid.h), for segments whose xy projection lies inside the region.
  std::optional<double> static_height_field_max_slope(const Eigen::AlignedBox2d& region_xy) const;
  // Every body instance's axis-aligned bounding box in W at the poses last set (the box of its meshes'
  // vertices in B, moved as Embree moves them, padded by 1 cm). Requires build() and, with bodies,
  // set_body_poses() (std::logic_error otherwise).
  std::vector<BodyBounds> body_bounds_W() const;

  // Builds the BVHs (static scene, body scenes, top level). Once; throws std::logic_error if called
  // again, std::runtime_error on an Embree error (e.g. out of memory).
  void build();
  bool built() const;

  // Another view of the same built world: it shares the device, the static scene and the body scenes
  // (their BVHs and vertex buffers exist once, whatever the number of views) and has its own top-level
  // scene, so its bodies are posed independently of this one's. A view may live longer than the scene
  // it was made from. Throws std::logic_error before build().
  EmbreeScene view() const;

  // Moves every body instance to X_WB[body] and commits the top-level scene; a no-op when the poses
  // equal the last ones set. X_WB needs at least num_bodies() entries, finite and rigid (rotation
  // orthonormal within 1e-6): otherwise std::invalid_argument. Requires build().
  void set_body_poses(const std::vector<Eigen::Isometry3d>& X_WB);

  // Throws std::invalid_argument describing the first problem of these poses, as set_body_poses would.
  void check_body_poses(const std::vector<Eigen::Isometry3d>& X_WB) const;

  // Traces rays [begin, end) of `rays` against the scene at the last poses set and writes entries
  // [begin, end) of `hits` (which must already have rays.size() entries). Thread-safe with itself.
  // Throws InvalidRayError for a bad ray (hits of the range are unspecified then), std::logic_error
  // before build() or, with bodies, before the first set_body_poses(), std::out_of_range for a range
  // outside the batch or the hits.
  void intersect(const RayBatch& rays, std::size_t begin, std::size_t end, QueryPath path,
                 RayHits& hits) const;

  // Whether anything lies on each ray of [begin, end) between its t_near and t_far: blocked[i] = 1 if
  // so, else 0 (`blocked` must already have rays.size() entries; entries outside the range are left
  // alone). A shadow-ray query: Embree stops at the first surface found (rtcOccludedNp, or packets
  // when the arrays are not 16-byte aligned), cheaper than intersect(), which finds the nearest. A ray's
  // ignore_body is left out by a filter on the candidate hits, so the answer is intersect()'s "hit or
  // not" (intersect() steps 0.1 mm past each ignored surface, at most kMaxIgnoredHits times: the two
  // differ only for another surface within 0.1 mm behind an ignored one; a ray ignoring the static
  // world, which the filter does not see, is answered by intersect()). Thread-safe with itself and
  // intersect(); throws as intersect() does.
  void occluded(const RayBatch& rays, std::size_t begin, std::size_t end, std::vector<std::uint8_t>& blocked) const;

  // 1 + the largest body index that has a mesh (the number of poses set_body_poses needs); 0 without
  // bodies.
  int num_bodies() const;
  int num_meshes() const;
  const SceneMeshInfo& mesh_info(int mesh_id) const;
  std::size_t num_static_triangles() const;
  // Packet width kPacket uses on this CPU (16, 8 or 4).
  int packet_width() const;

  // The top-level Embree scene, for benchmarks comparing against bare Embree calls on the same
  // scene. Valid after build(); poses as last set.
  RTCSceneTy* embree_scene() const;

 private:
  struct Impl;
  explicit EmbreeScene(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hadal::geometry
