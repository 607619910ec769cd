#include "hadal/geometry/embree_scene.h"

#include "hadal/core/vector_kernel.h"
#include "hadal/geometry/hit_refinement.h"
#include "hadal/geometry/segment_slab.h"
#include "hadal/geometry/slope_grid.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace hadal::geometry {
namespace {

// Rays per inner block: the unit of validation, of scratch storage and of one rtcIntersectNp call.
constexpr std::size_t kBlock = 256;
constexpr unsigned kInvalidId = RTC_INVALID_GEOMETRY_ID;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// 3x4 column-major affine transform as Embree takes it (RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR).
using Transform12 = std::array<float, 12>;

Transform12 to_transform12(const Eigen::Isometry3d& X) {
  Transform12 t{};
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) t[3 * c + r] = static_cast<float>(X.linear()(r, c));
  }
  for (int r = 0; r < 3; ++r) t[9 + r] = static_cast<float>(X.translation()(r));
  return t;
}

std::string format_mesh(const std::string& kind, const std::string& name) {
  return "EmbreeScene: " + kind + " '" + name + "': ";
}

std::string vec3(float x, float y, float z) {
  std::ostringstream s;
  s << "(" << x << ", " << y << ", " << z << ")";
  return s.str();
}

// Throws InvalidRayError for the first ray of [begin, end) that breaks RayBatch's rules.
void throw_first_invalid_ray(const RayBatch& rays, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    const float ox = rays.p_WO_x[i], oy = rays.p_WO_y[i], oz = rays.p_WO_z[i];
    const float dx = rays.d_W_x[i], dy = rays.d_W_y[i], dz = rays.d_W_z[i];
    const float t0 = rays.t_near[i], t1 = rays.t_far[i];
    const float d2 = dx * dx + dy * dy + dz * dz;
    const std::string prefix = "ray " + std::to_string(i) + ": ";
    if (!std::isfinite(ox) || !std::isfinite(oy) || !std::isfinite(oz)) {
      throw InvalidRayError(i, prefix + "origin " + vec3(ox, oy, oz) + " is not finite");
    }
    if (!std::isfinite(d2) || std::abs(d2 - 1.0f) > 1e-5f) {
      throw InvalidRayError(i, prefix + "direction " + vec3(dx, dy, dz) + " is not unit length (|d| = " +
                                   std::to_string(std::sqrt(d2)) + ")");
    }
    if (!std::isfinite(t0) || t0 < 0.0f) {
      throw InvalidRayError(i, prefix + "t_near = " + std::to_string(t0) + " must be finite and >= 0");
    }
    if (!(t1 >= t0)) {
      throw InvalidRayError(i, prefix + "t_far = " + std::to_string(t1) + " must be >= t_near = " +
                                   std::to_string(t0));
    }
  }
}

// Branch-free check of [begin, end) (vectorized; it returns and validate_rays throws: an exception out
// of a HADAL_VECTOR_KERNEL function terminates the program, core/vector_kernel.h).
HADAL_VECTOR_KERNEL bool rays_valid(const RayBatch& rays, std::size_t begin, std::size_t end) {
  constexpr float kMax = std::numeric_limits<float>::max();
  const float* ox = rays.p_WO_x.data();
  const float* oy = rays.p_WO_y.data();
  const float* oz = rays.p_WO_z.data();
  const float* dx = rays.d_W_x.data();
  const float* dy = rays.d_W_y.data();
  const float* dz = rays.d_W_z.data();
  const float* t0 = rays.t_near.data();
  const float* t1 = rays.t_far.data();
  int ok = 1;
  for (std::size_t i = begin; i < end; ++i) {
    const float d2 = dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i];
    // Comparisons with NaN are false, so each term also rejects NaN (and |x| <= max rejects inf).
    ok &= (std::abs(ox[i]) <= kMax) & (std::abs(oy[i]) <= kMax) & (std::abs(oz[i]) <= kMax) &
          (std::abs(d2 - 1.0f) <= 1e-5f) & (t0[i] >= 0.0f) & (t0[i] <= kMax) & (t1[i] >= t0[i]);
  }
  return ok != 0;
}

// Throws InvalidRayError for the first invalid ray of [begin, end), if any (the slow scan above names
// the culprit only when something is wrong).
void validate_rays(const RayBatch& rays, std::size_t begin, std::size_t end) {
  if (!rays_valid(rays, begin, end)) throw_first_invalid_ray(rays, begin, end);
}

// n /= max(|n|, FLT_MIN) for n arrays of normals: unit normals, misses' (0, 0, 0) stay zero. Division
// rather than multiplication by 1/|n| keeps axis-aligned normals exact. Vectorized (sqrt without errno:
// server/CMakeLists.txt); every element gets the same correctly rounded operations in the same order,
// so results do not depend on the position or the clone.
HADAL_VECTOR_KERNEL void normalize(float* __restrict nx, float* __restrict ny, float* __restrict nz, std::size_t n) {
  constexpr float kMin = std::numeric_limits<float>::min();
  for (std::size_t k = 0; k < n; ++k) {
    const float x = nx[k], y = ny[k], z = nz[k];
    const float root = __builtin_sqrtf(x * x + y * y + z * z);
    const float length = root < kMin ? kMin : root;
    nx[k] = x / length;
    ny[k] = y / length;
    nz[k] = z / length;
  }
}

void occluded_packet(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRay4* r) { rtcOccluded4(valid, s, c, r); }
void occluded_packet(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRay8* r) { rtcOccluded8(valid, s, c, r); }
void occluded_packet(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRay16* r) { rtcOccluded16(valid, s, c, r); }

void intersect_packet(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRayHit4* r) {
  rtcIntersect4(valid, s, c, r);
}
void intersect_packet(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRayHit8* r) {
  rtcIntersect8(valid, s, c, r);
}
void intersect_packet(const int* valid, RTCScene s, RTCIntersectContext* c, RTCRayHit16* r) {
  rtcIntersect16(valid, s, c, r);
}

// Lane k of a packet (RTCRayN, or RTCRayHitN's .ray) from ray i of the batch; the id is i, for
// occluded()'s ignore filter.
template <typename RayN>
void set_lane(RayN& r, std::size_t k, const RayBatch& rays, std::size_t i) {
  r.org_x[k] = rays.p_WO_x[i];
  r.org_y[k] = rays.p_WO_y[i];
  r.org_z[k] = rays.p_WO_z[i];
  r.tnear[k] = rays.t_near[i];
  r.dir_x[k] = rays.d_W_x[i];
  r.dir_y[k] = rays.d_W_y[i];
  r.dir_z[k] = rays.d_W_z[i];
  r.time[k] = 0.0f;
  r.tfar[k] = rays.t_far[i];
  r.mask[k] = ~0u;
  r.id[k] = static_cast<unsigned>(i);
  r.flags[k] = 0;
}

bool aligned16(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % 16 == 0; }

}  // namespace

const char* to_string(QueryPath path) {
  switch (path) {
    case QueryPath::kAuto: return "auto";
    case QueryPath::kSingle: return "single";
    case QueryPath::kPacket: return "packet";
    case QueryPath::kStream: return "stream";
  }
  return "?";
}

// The world's geometry, shared by every view of it (EmbreeScene::view()): the device, the static scene,
// the body scenes and the mesh table. Filled before build(), never modified after it.
struct EmbreeWorld {
  struct BodyScene {
    RTCScene scene = nullptr;
    std::vector<int> mesh_of_geometry;
    Eigen::AlignedBox3d bounds_B;  // of its meshes' vertices, in B
  };
  struct Mesh {
    SceneMeshInfo info;
    std::vector<std::uint32_t> triangle_materials;
    // Texture coordinates (2 per vertex), kept when the mesh has them (RayHits::tex_u, tex_v); empty
    // otherwise.
    std::vector<float> uvs;
    // The mesh as Embree holds it (its geometry's buffers, alive as long as the world's scenes): the
    // vertices (x, y, z floats in the mesh's frame: W for the static scene, B for a body) and each
    // triangle's three vertex indices (for texture coordinates and refine_hits()), with each vertex's
    // triangles (for refine_hits(), RayKernels::kPortable only).
    const float* vertices = nullptr;
    const std::uint32_t* triangles = nullptr;
    VertexTriangles adjacency;
  };

  RTCDevice device = nullptr;
  RTCScene static_scene = nullptr;
  std::vector<int> static_mesh_of_geometry;
  std::map<int, BodyScene> body_scenes;  // by body index
  std::vector<Mesh> meshes;
  std::size_t static_triangles = 0;
  // The steepest slope |grad h| of the static meshes declared height fields, and how many static
  // meshes were not (static_height_field_max_slope()).
  SlopeGrid height_field_slopes;  // of the (one) height field, by region
  int static_height_fields = 0, other_static_meshes = 0;
  int num_bodies = 0;
  int packet_width = 4;
  bool built = false;
  bool refine = false;  // RayKernels::kPortable: refine_hits() recomputes every hit

  std::mutex error_mutex;
  std::string last_error;

  static void on_error(void* user, RTCError code, const char* message) {
    auto* self = static_cast<EmbreeWorld*>(user);
    std::lock_guard<std::mutex> lock(self->error_mutex);
    self->last_error = "code " + std::to_string(static_cast<int>(code)) + ": " +
                       (message != nullptr ? message : "");
  }

  // Throws std::runtime_error if Embree reported an error on this thread since the last check.
  void check(const char* what) {
    const RTCError code = rtcGetDeviceError(device);
    if (code == RTC_ERROR_NONE) return;
    std::lock_guard<std::mutex> lock(error_mutex);
    throw std::runtime_error(std::string("EmbreeScene: ") + what + ": Embree error code " +
                             std::to_string(static_cast<int>(code)) +
                             (last_error.empty() ? "" : " (" + last_error + ")"));
  }

  ~EmbreeWorld() {
    for (auto& [body, scene] : body_scenes) {
      if (scene.scene != nullptr) rtcReleaseScene(scene.scene);
    }
    if (static_scene != nullptr) rtcReleaseScene(static_scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }

  RTCGeometry make_geometry(const TriangleMesh& mesh, const float** vertices_out,
                            const std::uint32_t** triangles_out) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree allocates new buffers padded so that the last vertex can be read with a 16-byte load.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.num_vertices()));
    auto* indices = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), mesh.num_triangles()));
    if (vertices == nullptr || indices == nullptr) {
      rtcReleaseGeometry(geometry);
      check("allocating mesh buffers");
      throw std::runtime_error("EmbreeScene: could not allocate mesh buffers");
    }
    std::copy(mesh.positions.begin(), mesh.positions.end(), vertices);
    std::copy(mesh.indices.begin(), mesh.indices.end(), indices);
    rtcCommitGeometry(geometry);
    *vertices_out = vertices;
    *triangles_out = indices;
    return geometry;
  }

  int add_mesh(RTCScene scene, std::vector<int>& mesh_of_geometry, const TriangleMesh& mesh,
               SceneMeshInfo info) {
    const float* vertices = nullptr;
    const std::uint32_t* triangles = nullptr;
    RTCGeometry geometry = make_geometry(mesh, &vertices, &triangles);
    const unsigned geom_id = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    check("attaching a mesh");
    const int mesh_id = static_cast<int>(meshes.size());
    if (mesh_of_geometry.size() <= geom_id) mesh_of_geometry.resize(geom_id + 1, -1);
    mesh_of_geometry[geom_id] = mesh_id;
    info.num_triangles = mesh.num_triangles();
    Mesh kept{std::move(info), mesh.triangle_materials, mesh.uvs, vertices, triangles, {}};
    if (refine) kept.adjacency = vertex_triangles(vertices, mesh.num_vertices(), triangles, mesh.num_triangles());
    meshes.push_back(std::move(kept));
    return mesh_id;
  }
};

// One view of a world: the top-level scene with one instance of the static scene and of each body
// scene, posed independently of every other view.
struct EmbreeScene::Impl {
  // What a top-level instance maps back to.
  struct Instance {
    std::int32_t body = kStaticBody;
    std::vector<int> mesh_of_geometry;  // geomID in the instanced scene -> mesh id
    Eigen::Matrix3f R_WB = Eigen::Matrix3f::Identity();
    Transform12 transform{};
    RTCGeometry geometry = nullptr;  // the instance (owned by the top-level scene)
  };

  std::shared_ptr<EmbreeWorld> world;
  RTCScene top = nullptr;
  RTCScene trace = nullptr;  // what rays are traced against: top, or the static scene without bodies
  std::vector<Instance> instances;  // by top-level geomID (= instID of a hit)
  bool poses_set = false;
  // The body instances' boxes at the current poses (body_bounds_W), and the same in single precision
  // (rounded outwards), widened by the slab test's rounding (a few ulp of the coordinates, generously),
  // for the bodies' pass's test (bodies_within_reach).
  struct BodyBoxf {
    std::int32_t body;
    float lo[3], hi[3];
  };
  std::vector<BodyBounds> body_bounds;
  std::vector<BodyBoxf> body_boxes;
  // Two passes (make_view): the static scene traced directly, then the top level with the static
  // instance left out by ray mask, from the first pass's hit on (its tfar). Instance traversal costs a
  // quarter of a coherent stream's throughput; the bodies' pass, a few boxes, little.
  bool split = false;
  // Every body index below 31: each body instance has a mask bit of its own, and a ray leaves out the
  // body it ignores by mask (otherwise by filter, or by tracing on past its hits).
  bool unique_body_masks = false;

  static constexpr unsigned kStaticMask = 1u;
  static unsigned body_mask(std::int32_t body) { return 1u << (1u + static_cast<unsigned>(body) % 31u); }
  static std::int32_t ignored_by(const RayBatch& rays, std::size_t i) {
    return rays.ignore_body.empty() ? kNoHit : rays.ignore_body[i];
  }
  // Ray masks of the first pass (the static scene: none for a ray that ignores it) and of the second
  // (the bodies, but the ignored one when masks can tell it apart).
  unsigned static_pass_mask(std::int32_t ignored) const { return ignored == kStaticBody ? 0u : ~0u; }
  unsigned body_pass_mask(std::int32_t ignored) const {
    if (!split) return ~0u;
    return ignored >= 0 && unique_body_masks ? ~(kStaticMask | body_mask(ignored)) : ~kStaticMask;
  }
  // The scene of the first pass: the static scene when split, else everything.
  RTCScene first_pass() const { return split ? world->static_scene : trace; }

  ~Impl() {
    if (top != nullptr) rtcReleaseScene(top);
  }

  // The bodies' pass over rays [begin, end) of one block (at most kBlock rays), whose segments run from
  // t_near to tfar[k - begin]: which rays may reach a body's box (the box of the body every ray of the
  // block ignores left out, when they all ignore the same one). Writes each ray's t_near for that pass
  // into t_near_out: its own where it may, +inf where it cannot (Embree passes over a ray whose tnear
  // is above its tfar), and returns whether any ray may. For a camera, most rays of most frames reach
  // no body (the bodies' pass was a quarter of a frame's tracing). Conservative: a ray is dropped only
  // when its segment misses every box by more than the rounding here. Vectorized loops over the rays
  // (geometry/segment_slab.h: the directions' reciprocals once, then box by box).
  HADAL_VECTOR_KERNEL bool bodies_within_reach(const RayBatch& rays, std::size_t begin, std::size_t end,
                                               const float* tfar, float* t_near_out) const {
    const std::size_t n = end - begin;  // <= kBlock (trace_stream's block)
    const float* t_near = &rays.t_near[begin];
    std::copy(t_near, t_near + n, t_near_out);
    if (body_boxes.empty() || n == 0) return false;
    const std::int32_t ignored = ignored_by(rays, begin);
    bool same_ignored = true;
    if (!rays.ignore_body.empty()) {
      const std::int32_t* ignore = &rays.ignore_body[begin];
      int differs = 0;
      for (std::size_t k = 0; k < n; ++k) differs |= ignore[k] != ignored ? 1 : 0;  // no early exit: vectorized
      same_ignored = differs == 0;
    }
    // The body the block's rays all ignore (if they do) is left out.
    const std::int32_t skipped = same_ignored ? ignored : kNoHit;
    if (std::all_of(body_boxes.begin(), body_boxes.end(), [&](const BodyBoxf& box) { return box.body == skipped; })) {
      std::fill(t_near_out, t_near_out + n, kInf);
      return false;
    }
    const float* __restrict ox = &rays.p_WO_x[begin];
    const float* __restrict oy = &rays.p_WO_y[begin];
    const float* __restrict oz = &rays.p_WO_z[begin];
    // Each ray's 1 / d per axis, once for all boxes (geometry/segment_slab.h).
    alignas(64) float inv_x[kBlock], inv_y[kBlock], inv_z[kBlock], reach[kBlock];
    {
      const float* __restrict dx = &rays.d_W_x[begin];
      const float* __restrict dy = &rays.d_W_y[begin];
      const float* __restrict dz = &rays.d_W_z[begin];
      for (std::size_t k = 0; k < n; ++k) {
        inv_x[k] = slab_reciprocal(dx[k]);
        inv_y[k] = slab_reciprocal(dy[k]);
        inv_z[k] = slab_reciprocal(dz[k]);
        reach[k] = 0.0f;
      }
    }
    for (const BodyBoxf& box : body_boxes) {
      if (box.body == skipped) continue;
      const float lo_x = box.lo[0], lo_y = box.lo[1], lo_z = box.lo[2];
      const float hi_x = box.hi[0], hi_y = box.hi[1], hi_z = box.hi[2];
      for (std::size_t k = 0; k < n; ++k) {
        float t0 = t_near[k], t1 = tfar[k];
        clip_to_slab_reciprocal(lo_x, hi_x, ox[k], inv_x[k], t0, t1);
        clip_to_slab_reciprocal(lo_y, hi_y, oy[k], inv_y[k], t0, t1);
        clip_to_slab_reciprocal(lo_z, hi_z, oz[k], inv_z[k], t0, t1);
        const float was = reach[k];
        reach[k] = t0 <= t1 ? 1.0f : was;
      }
    }
    int any = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const bool may = reach[k] != 0.0f;
      any |= may ? 1 : 0;
      t_near_out[k] = may ? t_near[k] : kInf;
    }
    return any != 0;
  }

  // The body instances' boxes in W at their current transforms, padded by 1 cm (Embree moves the
  // vertices in single precision), into body_bounds and body_boxes.
  void update_body_bounds() {
    body_bounds.clear();
    body_boxes.clear();
    for (const Instance& instance : instances) {
      if (instance.body == kStaticBody) continue;
      const Eigen::AlignedBox3d& box_B = world->body_scenes.at(instance.body).bounds_B;
      // The pose as Embree has it (column-major 3x4, single precision).
      const Transform12& m = instance.transform;
      BodyBounds bounds{instance.body, Eigen::AlignedBox3d()};
      for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3d c = box_B.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner));
        bounds.box_W.extend(Eigen::Vector3d(m[0] * c.x() + m[3] * c.y() + m[6] * c.z() + m[9],
                                            m[1] * c.x() + m[4] * c.y() + m[7] * c.z() + m[10],
                                            m[2] * c.x() + m[5] * c.y() + m[8] * c.z() + m[11]));
      }
      bounds.box_W.min().array() -= 0.01;
      bounds.box_W.max().array() += 0.01;
      body_bounds.push_back(bounds);
      BodyBoxf box{instance.body, {}, {}};
      for (int a = 0; a < 3; ++a) {
        const float lo = std::nextafter(static_cast<float>(bounds.box_W.min()[a]), -kInf);
        const float hi = std::nextafter(static_cast<float>(bounds.box_W.max()[a]), kInf);
        const float margin = 1e-3f + 1e-5f * std::max(std::abs(lo), std::abs(hi));
        box.lo[a] = lo - margin;
        box.hi[a] = hi + margin;
      }
      body_boxes.push_back(box);
    }
  }

  // This view's top level over the built world: the static scene traced directly when nothing moves
  // (saving the instance traversal: 8-20 % of single-ray and ~25 % of stream throughput on the
  // benchmark seabed), else one instance per scene at identity until the first set_body_poses().
  void make_view() {
    EmbreeWorld& w = *world;
    if (w.body_scenes.empty()) {
      trace = w.static_scene;
      poses_set = true;
      return;
    }
    top = rtcNewScene(w.device);
    // Rebuilt at every pose change, over a handful of instances: fast build beats best quality.
    rtcSetSceneBuildQuality(top, RTC_BUILD_QUALITY_LOW);
    const Transform12 identity = to_transform12(Eigen::Isometry3d::Identity());
    const bool masks = rtcGetDeviceProperty(w.device, RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED) != 0;
    auto add_instance = [&](RTCScene scene, std::int32_t body, const std::vector<int>& mesh_of_geometry) {
      RTCGeometry geometry = rtcNewGeometry(w.device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(geometry, scene);
      rtcSetGeometryTransform(geometry, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity.data());
      if (masks) rtcSetGeometryMask(geometry, body == kStaticBody ? kStaticMask : body_mask(body));
      rtcCommitGeometry(geometry);
      const unsigned id = rtcAttachGeometry(top, geometry);
      rtcReleaseGeometry(geometry);  // the top-level scene keeps it alive
      if (instances.size() <= id) instances.resize(id + 1);
      Instance& instance = instances[id];
      instance.body = body;
      instance.mesh_of_geometry = mesh_of_geometry;
      instance.transform = identity;
      instance.geometry = geometry;
    };
    if (!w.static_mesh_of_geometry.empty()) add_instance(w.static_scene, kStaticBody, w.static_mesh_of_geometry);
    for (const auto& [body, scene] : w.body_scenes) add_instance(scene.scene, body, scene.mesh_of_geometry);
    // Robust: see the constructor.
    rtcSetSceneFlags(top, RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
    rtcCommitScene(top);
    w.check("building the top-level scene");
    trace = top;
    split = masks && !w.static_mesh_of_geometry.empty();
    unique_body_masks = split && w.body_scenes.rbegin()->first < 31;
    poses_set = false;
  }

  // With RayKernels::kPortable (else nothing), Embree's hit fields of rays [begin, end) recomputed by
  // refine_hit() (geometry/hit_refinement.h), so that they do not depend on Embree's arithmetic: the
  // distance (hits.distance), the triangle (hits.triangle), the unit geometric normal in the mesh's frame
  // (hits.n_W_*, which finish() turns into W) and the barycentric u, v (hits.tex_u, tex_v); geom and inst
  // are indexed from begin. A body's ray is taken into B through the exact inverse of the single-precision
  // transform Embree traced it with, so the distance is the exact one of the geometry Embree traced,
  // rounded once (to ~1e-15 relative). A hit the refinement cannot trust (a ray in the triangle's plane,
  // or a distance far from Embree's) keeps Embree's values; a refined distance is kept within the ray's
  // [t_near, t_far].
  void refine_hits(const RayBatch& rays, std::size_t begin, std::size_t end, const unsigned* geom,
                   const unsigned* inst, RayHits& hits) const {
    if (!world->refine) return;
    unsigned cached_geom = kInvalidId, cached_inst = kInvalidId;
    const EmbreeWorld::Mesh* mesh = nullptr;
    RefinementMesh view;
    // A body's ray into B through the exact inverse of the single-precision transform Embree was given
    // (x_B = A^-1 (x_W - p)); none for the static scene.
    bool body = false;
    Eigen::Matrix3d A_inverse;
    Eigen::Vector3d p_W;
    for (std::size_t i = begin; i < end; ++i) {
      const unsigned g = geom[i - begin], in = inst[i - begin];
      if (g == kInvalidId) continue;
      if (mesh == nullptr || g != cached_geom || in != cached_inst) {
        cached_geom = g;
        cached_inst = in;
        body = false;
        int mesh_id;
        if (in == kInvalidId) {  // the static scene traced directly
          mesh_id = world->static_mesh_of_geometry[g];
        } else {
          const Instance& instance = instances[in];
          mesh_id = instance.mesh_of_geometry[g];
          if (instance.body != kStaticBody) {
            const Transform12& m = instance.transform;  // column-major 3x4
            Eigen::Matrix3d A;
            for (int c = 0; c < 3; ++c) {
              for (int r = 0; r < 3; ++r) A(r, c) = m[3 * c + r];
            }
            A_inverse = A.inverse();
            p_W = Eigen::Vector3d(m[9], m[10], m[11]);
            body = true;
          }
        }
        mesh = &world->meshes[static_cast<std::size_t>(mesh_id)];
        view = RefinementMesh{mesh->vertices, mesh->triangles, &mesh->adjacency};
      }
      Eigen::Vector3d o(rays.p_WO_x[i], rays.p_WO_y[i], rays.p_WO_z[i]);
      Eigen::Vector3d d(rays.d_W_x[i], rays.d_W_y[i], rays.d_W_z[i]);
      if (body) {
        o = A_inverse * (o - p_W);
        d = A_inverse * d;
      }
      const RefinedHit hit = refine_hit(view, hits.triangle[i], o.data(), d.data());
      const double embree_t = hits.distance[i];
      if (!hit.ok || std::abs(hit.t - embree_t) > 1e-3 * (1.0 + std::abs(embree_t))) continue;
      hits.distance[i] = std::clamp(static_cast<float>(hit.t), rays.t_near[i], rays.t_far[i]);
      hits.triangle[i] = hit.triangle;
      hits.n_W_x[i] = static_cast<float>(hit.n[0]);
      hits.n_W_y[i] = static_cast<float>(hit.n[1]);
      hits.n_W_z[i] = static_cast<float>(hit.n[2]);
      hits.tex_u[i] = static_cast<float>(hit.u);
      hits.tex_v[i] = static_cast<float>(hit.v);
    }
  }

  // Fills hit fields of rays [begin, end) from Embree's raw output: hits.distance holds tfar,
  // hits.n_W_* the unnormalised object-space Ng, hits.triangle the primID; geom/inst the IDs
  // (index i - begin).
  HADAL_VECTOR_KERNEL void finish(std::size_t begin, std::size_t end, const unsigned* geom, const unsigned* inst,
                                  RayHits& hits) const {
    // The output arrays as restrict pointers from the block's first ray (else the compiler reloads the
    // vectors' data pointers after every store).
    float* __restrict nx = &hits.n_W_x[begin];
    float* __restrict ny = &hits.n_W_y[begin];
    float* __restrict nz = &hits.n_W_z[begin];
    float* __restrict distance = &hits.distance[begin];
    std::int32_t* __restrict body_of = &hits.body[begin];
    std::int32_t* __restrict mesh_of = &hits.mesh[begin];
    std::uint32_t* __restrict material = &hits.material[begin];
    std::uint32_t* __restrict triangle = &hits.triangle[begin];
    float* __restrict tex_u = &hits.tex_u[begin];
    float* __restrict tex_v = &hits.tex_v[begin];
    const std::size_t n = end - begin;
    // What a hit's (geomID, instID) maps to: its mesh, body and, for a moving body's instance, the
    // rotation of its normals into W.
    struct Target {
      int mesh_id = kNoHit;
      std::int32_t body = kStaticBody;
      const Eigen::Matrix3f* R_WB = nullptr;
      const EmbreeWorld::Mesh* mesh = nullptr;
    };
    const auto target_of = [this](unsigned g, unsigned i) {
      Target t;
      if (i == kInvalidId) {  // the static scene traced directly
        t.mesh_id = world->static_mesh_of_geometry[g];
      } else {
        const Instance& instance = instances[i];
        t.mesh_id = instance.mesh_of_geometry[g];
        t.body = instance.body;
        if (t.body != kStaticBody) t.R_WB = &instance.R_WB;
      }
      t.mesh = &world->meshes[static_cast<std::size_t>(t.mesh_id)];
      return t;
    };
    // The common block, a camera's over the seabed: every hit on one static mesh without per-triangle
    // materials or texture coordinates. Its fields are the same for every hit, written without lookups
    // or branches (vectorized); the loop below gives the same values.
    std::size_t first_hit = 0;
    while (first_hit < n && geom[first_hit] == kInvalidId) ++first_hit;
    bool one_target = true;
    Target target;
    if (first_hit < n) {
      const unsigned g0 = geom[first_hit], i0 = inst[first_hit];
      unsigned others = 0;  // an integer reduction: GCC vectorizes it (not the bool's)
      for (std::size_t k = first_hit; k < n; ++k) {
        const unsigned g = geom[k], i = inst[k];
        others |= (g != kInvalidId) & ((g != g0) | (i != i0)) ? 1u : 0u;
      }
      one_target = others == 0;
      if (one_target) {
        target = target_of(g0, i0);
        one_target = target.R_WB == nullptr && target.mesh->uvs.empty() && target.mesh->triangle_materials.empty();
      }
    }
    if (one_target) {
      const std::int32_t body = target.body, mesh_id = target.mesh_id;
      const std::uint32_t material_id = first_hit < n ? target.mesh->info.material_id : kInvalidIndex;
      // The float fields sixteen rays at a time (GCC's vector extension: GCC leaves this loop scalar),
      // then the rest; the integer fields in a loop GCC vectorizes.
      typedef float Lanes __attribute__((vector_size(64)));
      typedef std::uint32_t Ids __attribute__((vector_size(64)));
      constexpr std::size_t kLanes = 16;
      std::size_t k = 0;
      for (; k + kLanes <= n; k += kLanes) {
        Ids ids;
        Lanes t, x, y, z;
        std::memcpy(&ids, geom + k, sizeof ids);
        std::memcpy(&t, distance + k, sizeof t);
        std::memcpy(&x, nx + k, sizeof x);
        std::memcpy(&y, ny + k, sizeof y);
        std::memcpy(&z, nz + k, sizeof z);
        const auto hit = ids != kInvalidId;
        const Lanes zero = {}, inf = zero + kInf, nan = zero + kNaN;
        t = hit ? t : inf;
        x = hit ? x : zero;
        y = hit ? y : zero;
        z = hit ? z : zero;
        std::memcpy(distance + k, &t, sizeof t);
        std::memcpy(nx + k, &x, sizeof x);
        std::memcpy(ny + k, &y, sizeof y);
        std::memcpy(nz + k, &z, sizeof z);
        std::memcpy(tex_u + k, &nan, sizeof nan);
        std::memcpy(tex_v + k, &nan, sizeof nan);
      }
      for (; k < n; ++k) {
        const bool hit = geom[k] != kInvalidId;
        distance[k] = hit ? distance[k] : kInf;
        nx[k] = hit ? nx[k] : 0.0f;
        ny[k] = hit ? ny[k] : 0.0f;
        nz[k] = hit ? nz[k] : 0.0f;
        tex_u[k] = kNaN;
        tex_v[k] = kNaN;
      }
      for (std::size_t k = 0; k < n; ++k) {
        const bool hit = geom[k] != kInvalidId;
        const std::uint32_t primitive = triangle[k];
        body_of[k] = hit ? body : kNoHit;
        mesh_of[k] = hit ? mesh_id : kNoHit;
        material[k] = hit ? material_id : kInvalidIndex;
        triangle[k] = hit ? primitive : kInvalidIndex;
      }
      normalize(nx, ny, nz, n);
      return;
    }
    // Otherwise each hit looked up, once per run of equal ids (a block's rays mostly hit the same mesh).
    unsigned cached_geom = kInvalidId, cached_inst = kInvalidId;
    bool cached = false;
    for (std::size_t k = 0; k < n; ++k) {
      const unsigned g = geom[k];
      if (g == kInvalidId) {
        distance[k] = kInf;
        nx[k] = ny[k] = nz[k] = 0.0f;
        body_of[k] = kNoHit;
        mesh_of[k] = kNoHit;
        material[k] = kInvalidIndex;
        triangle[k] = kInvalidIndex;
        tex_u[k] = tex_v[k] = kNaN;
        continue;
      }
      if (!cached || g != cached_geom || inst[k] != cached_inst) {
        cached = true;
        cached_geom = g;
        cached_inst = inst[k];
        target = target_of(g, inst[k]);
      }
      const Eigen::Matrix3f* R_WB = target.R_WB;
      const EmbreeWorld::Mesh* mesh = target.mesh;
      if (R_WB != nullptr) {
        const Eigen::Vector3f n_W = *R_WB * Eigen::Vector3f(nx[k], ny[k], nz[k]);
        nx[k] = n_W.x();
        ny[k] = n_W.y();
        nz[k] = n_W.z();
      }
      body_of[k] = target.body;
      mesh_of[k] = target.mesh_id;
      material[k] = mesh->info.material_id +
                    (mesh->triangle_materials.empty() ? 0u : mesh->triangle_materials[triangle[k]]);
      // tex_u, tex_v hold Embree's barycentric u, v of the hit: texture coordinates from them.
      if (mesh->uvs.empty()) {
        tex_u[k] = tex_v[k] = kNaN;
      } else {
        const std::uint32_t* tri = &mesh->triangles[3 * static_cast<std::size_t>(triangle[k])];
        const float b1 = tex_u[k], b2 = tex_v[k], b0 = 1.0f - b1 - b2;
        const float* t0 = &mesh->uvs[2 * static_cast<std::size_t>(tri[0])];
        const float* t1 = &mesh->uvs[2 * static_cast<std::size_t>(tri[1])];
        const float* t2 = &mesh->uvs[2 * static_cast<std::size_t>(tri[2])];
        tex_u[k] = b0 * t0[0] + b1 * t1[0] + b2 * t2[0];
        tex_v[k] = b0 * t0[1] + b1 * t1[1] + b2 * t2[1];
      }
    }
    normalize(nx, ny, nz, n);
  }

  void trace_single(const RayBatch& rays, std::size_t begin, std::size_t end, RTCIntersectContext* context,
                    RayHits& hits) const {
    unsigned geom[kBlock], inst[kBlock];
    for (std::size_t i = begin; i < end; ++i) {
      trace_ray(rays, i, rays.t_near[i], context, hits, &geom[i - begin], &inst[i - begin]);
    }
    refine_hits(rays, begin, end, geom, inst, hits);
    finish(begin, end, geom, inst, hits);
  }

  // Ray i of the batch from t_near on (its own or a later start); geometry and instance ids out.
  void trace_ray(const RayBatch& rays, std::size_t i, float t_near, RTCIntersectContext* context, RayHits& hits,
                 unsigned* geom, unsigned* inst) const {
    const std::int32_t ignored = ignored_by(rays, i);
    RTCRayHit rh;
    rh.ray.org_x = rays.p_WO_x[i];
    rh.ray.org_y = rays.p_WO_y[i];
    rh.ray.org_z = rays.p_WO_z[i];
    rh.ray.tnear = t_near;
    rh.ray.dir_x = rays.d_W_x[i];
    rh.ray.dir_y = rays.d_W_y[i];
    rh.ray.dir_z = rays.d_W_z[i];
    rh.ray.time = 0.0f;
    rh.ray.tfar = rays.t_far[i];
    rh.ray.mask = split ? static_pass_mask(ignored) : ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = kInvalidId;
    rh.hit.instID[0] = kInvalidId;
    rtcIntersect1(first_pass(), context, &rh);
    *geom = rh.hit.geomID;
    *inst = rh.hit.instID[0];
    if (split) {  // the bodies, up to the static hit
      rh.ray.mask = body_pass_mask(ignored);
      rh.hit.geomID = kInvalidId;
      rtcIntersect1(top, context, &rh);
      if (rh.hit.geomID != kInvalidId) {
        *geom = rh.hit.geomID;
        *inst = rh.hit.instID[0];
      }
    }
    hits.distance[i] = rh.ray.tfar;
    hits.n_W_x[i] = rh.hit.Ng_x;
    hits.n_W_y[i] = rh.hit.Ng_y;
    hits.n_W_z[i] = rh.hit.Ng_z;
    hits.triangle[i] = rh.hit.primID;
    hits.tex_u[i] = rh.hit.u;
    hits.tex_v[i] = rh.hit.v;
  }

  // Rays that ignore a body and hit it are continued past the hit (ray_batch.h).
  void pass_ignored_bodies(const RayBatch& rays, std::size_t begin, std::size_t end, RTCIntersectContext* context,
                           RayHits& hits) const {
    for (std::size_t i = begin; i < end; ++i) {
      const std::int32_t ignored = rays.ignore_body[i];
      if (ignored == kNoHit) continue;
      for (int pass = 0; hits.body[i] == ignored; ++pass) {
        const float t_next = hits.distance[i] + kIgnoredHitStep;
        unsigned geom = kInvalidId, inst = kInvalidId;
        if (pass < kMaxIgnoredHits && t_next <= rays.t_far[i]) trace_ray(rays, i, t_next, context, hits, &geom, &inst);
        refine_hits(rays, i, i + 1, &geom, &inst, hits);
        finish(i, i + 1, &geom, &inst, hits);
      }
    }
  }

  template <int N, typename RayHitN>
  void trace_packets(const RayBatch& rays, std::size_t begin, std::size_t end,
                     RTCIntersectContext* context, RayHits& hits) const {
    unsigned geom[kBlock], inst[kBlock];
    RayHitN rh;  // RTC_ALIGN'ed by Embree
    alignas(64) int valid[N];
    for (std::size_t p = begin; p < end; p += N) {
      const std::size_t m = std::min<std::size_t>(N, end - p);
      for (std::size_t k = 0; k < static_cast<std::size_t>(N); ++k) {
        const std::size_t i = k < m ? p + k : p;  // inactive lanes repeat the first ray
        valid[k] = k < m ? -1 : 0;
        set_lane(rh.ray, k, rays, i);
        if (split) rh.ray.mask[k] = static_pass_mask(ignored_by(rays, i));
        rh.hit.geomID[k] = kInvalidId;
        rh.hit.instID[0][k] = kInvalidId;
      }
      intersect_packet(valid, first_pass(), context, &rh);
      if (split) {  // the bodies, up to the static hits: a lane they hit gets their ids
        unsigned static_geom[N];
        for (std::size_t k = 0; k < static_cast<std::size_t>(N); ++k) {
          static_geom[k] = rh.hit.geomID[k];
          rh.hit.geomID[k] = kInvalidId;
          rh.ray.mask[k] = body_pass_mask(ignored_by(rays, k < m ? p + k : p));
        }
        intersect_packet(valid, top, context, &rh);
        for (std::size_t k = 0; k < static_cast<std::size_t>(N); ++k) {
          if (rh.hit.geomID[k] == kInvalidId) rh.hit.geomID[k] = static_geom[k];  // instID stays invalid
        }
      }
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t i = p + k;
        hits.distance[i] = rh.ray.tfar[k];
        hits.n_W_x[i] = rh.hit.Ng_x[k];
        hits.n_W_y[i] = rh.hit.Ng_y[k];
        hits.n_W_z[i] = rh.hit.Ng_z[k];
        hits.triangle[i] = rh.hit.primID[k];
        hits.tex_u[i] = rh.hit.u[k];
        hits.tex_v[i] = rh.hit.v[k];
        geom[i - begin] = rh.hit.geomID[k];
        inst[i - begin] = rh.hit.instID[0][k];
      }
    }
    refine_hits(rays, begin, end, geom, inst, hits);
    finish(begin, end, geom, inst, hits);
  }

  void trace_packets(const RayBatch& rays, std::size_t begin, std::size_t end,
                     RTCIntersectContext* context, RayHits& hits) const {
    if (world->packet_width == 16) {
      trace_packets<16, RTCRayHit16>(rays, begin, end, context, hits);
    } else if (world->packet_width == 8) {
      trace_packets<8, RTCRayHit8>(rays, begin, end, context, hits);
    } else {
      trace_packets<4, RTCRayHit4>(rays, begin, end, context, hits);
    }
  }

  // rtcIntersectNp straight on the batch's and the hits' arrays (Embree reads origins, directions and
  // t_near from the batch, and writes tfar, Ng and primID into the hits). Needs every array
  // 16-byte aligned at `begin`.
  void trace_stream(const RayBatch& rays, std::size_t begin, std::size_t end, RTCIntersectContext* context,
                    RayHits& hits) const {
    alignas(64) unsigned geom[kBlock], inst[kBlock], mask[kBlock], id[kBlock], flags[kBlock];
    alignas(64) float time[kBlock];
    const std::size_t n = end - begin;
    if (split) {
      for (std::size_t k = 0; k < n; ++k) mask[k] = static_pass_mask(ignored_by(rays, begin + k));
    } else {
      std::fill_n(mask, n, ~0u);
    }
    std::fill_n(id, n, 0u);
    std::fill_n(flags, n, 0u);
    std::fill_n(time, n, 0.0f);
    std::fill_n(geom, n, kInvalidId);
    std::fill_n(inst, n, kInvalidId);
    std::copy(rays.t_far.begin() + begin, rays.t_far.begin() + end, hits.distance.begin() + begin);
    // Embree only reads the ray inputs; its struct just is not const-qualified.
    RTCRayHitNp rh;
    rh.ray.org_x = const_cast<float*>(&rays.p_WO_x[begin]);
    rh.ray.org_y = const_cast<float*>(&rays.p_WO_y[begin]);
    rh.ray.org_z = const_cast<float*>(&rays.p_WO_z[begin]);
    rh.ray.tnear = const_cast<float*>(&rays.t_near[begin]);
    rh.ray.dir_x = const_cast<float*>(&rays.d_W_x[begin]);
    rh.ray.dir_y = const_cast<float*>(&rays.d_W_y[begin]);
    rh.ray.dir_z = const_cast<float*>(&rays.d_W_z[begin]);
    rh.ray.time = time;
    rh.ray.tfar = &hits.distance[begin];
    rh.ray.mask = mask;
    rh.ray.id = id;
    rh.ray.flags = flags;
    rh.hit.Ng_x = &hits.n_W_x[begin];
    rh.hit.Ng_y = &hits.n_W_y[begin];
    rh.hit.Ng_z = &hits.n_W_z[begin];
    rh.hit.u = &hits.tex_u[begin];
    rh.hit.v = &hits.tex_v[begin];
    rh.hit.primID = &hits.triangle[begin];
    rh.hit.geomID = geom;
    rh.hit.instID[0] = inst;
    rtcIntersectNp(first_pass(), context, &rh, static_cast<unsigned>(n));
    // The bodies, if any ray may reach one, from the same arrays: tfar is the static hit's distance
    // (or the ray's end), and Embree overwrites a ray's hit fields only where a body is nearer.
    alignas(64) float body_tnear[kBlock];
    if (split && bodies_within_reach(rays, begin, end, &hits.distance[begin], body_tnear)) {
      alignas(64) unsigned body_geom[kBlock], body_inst[kBlock];
      std::fill_n(body_geom, n, kInvalidId);
      std::fill_n(body_inst, n, kInvalidId);
      for (std::size_t k = 0; k < n; ++k) mask[k] = body_pass_mask(ignored_by(rays, begin + k));
      rh.hit.geomID = body_geom;
      rh.hit.instID[0] = body_inst;
      rh.ray.tnear = body_tnear;
      rtcIntersectNp(top, context, &rh, static_cast<unsigned>(n));
      for (std::size_t k = 0; k < n; ++k) {
        if (body_geom[k] == kInvalidId) continue;
        geom[k] = body_geom[k];
        inst[k] = body_inst[k];
      }
    }
    refine_hits(rays, begin, end, geom, inst, hits);
    finish(begin, end, geom, inst, hits);
  }

  // Occlusion of rays [begin, end) (one block): rtcOccludedNp on the batch's arrays when they are
  // 16-byte aligned, else packets; Embree sets tfar to -inf on a blocked ray.
  void occlude_block(const RayBatch& rays, std::size_t begin, std::size_t end, RTCIntersectContext* context,
                     std::uint8_t* blocked) const {
    alignas(64) float tfar[kBlock], time[kBlock];
    alignas(64) unsigned mask[kBlock], id[kBlock], flags[kBlock];
    const std::size_t n = end - begin;
    std::copy(rays.t_far.begin() + begin, rays.t_far.begin() + end, tfar);
    const bool aligned = aligned16(&rays.p_WO_x[begin]) && aligned16(&rays.p_WO_y[begin]) &&
                         aligned16(&rays.p_WO_z[begin]) && aligned16(&rays.d_W_x[begin]) &&
                         aligned16(&rays.d_W_y[begin]) && aligned16(&rays.d_W_z[begin]) && aligned16(&rays.t_near[begin]);
    if (aligned) {
      for (std::size_t k = 0; k < n; ++k) mask[k] = split ? static_pass_mask(ignored_by(rays, begin + k)) : ~0u;
      for (std::size_t k = 0; k < n; ++k) id[k] = static_cast<unsigned>(begin + k);  // for the ignore filter
      std::fill_n(flags, n, 0u);
      std::fill_n(time, n, 0.0f);
      RTCRayNp r;  // Embree only reads the inputs
      r.org_x = const_cast<float*>(&rays.p_WO_x[begin]);
      r.org_y = const_cast<float*>(&rays.p_WO_y[begin]);
      r.org_z = const_cast<float*>(&rays.p_WO_z[begin]);
      r.tnear = const_cast<float*>(&rays.t_near[begin]);
      r.dir_x = const_cast<float*>(&rays.d_W_x[begin]);
      r.dir_y = const_cast<float*>(&rays.d_W_y[begin]);
      r.dir_z = const_cast<float*>(&rays.d_W_z[begin]);
      r.time = time;
      r.tfar = tfar;
      r.mask = mask;
      r.id = id;
      r.flags = flags;
      RTCIntersectContext unfiltered = *context;  // the static scene has no context filter (make_view)
      unfiltered.filter = nullptr;
      rtcOccludedNp(first_pass(), split ? &unfiltered : context, &r, static_cast<unsigned>(n));
      // The bodies, for the rays the static scene left clear (Embree skips tfar -inf), if any may
      // reach one (over the rays' whole length).
      alignas(64) float body_tnear[kBlock];
      if (split && bodies_within_reach(rays, begin, end, &rays.t_far[begin], body_tnear)) {
        for (std::size_t k = 0; k < n; ++k) mask[k] = body_pass_mask(ignored_by(rays, begin + k));
        r.tnear = body_tnear;
        rtcOccludedNp(top, context, &r, static_cast<unsigned>(n));
      }
    } else if (world->packet_width == 16) {
      occlude_packets<16, RTCRay16>(rays, begin, end, context, tfar);
    } else if (world->packet_width == 8) {
      occlude_packets<8, RTCRay8>(rays, begin, end, context, tfar);
    } else {
      occlude_packets<4, RTCRay4>(rays, begin, end, context, tfar);
    }
    for (std::size_t k = 0; k < n; ++k) blocked[begin + k] = tfar[k] < 0.0f ? 1 : 0;
  }

  template <int N, typename RayN>
  void occlude_packets(const RayBatch& rays, std::size_t begin, std::size_t end, RTCIntersectContext* context,
                       float* tfar) const {
    RayN r;
    alignas(64) int valid[N];
    for (std::size_t p = begin; p < end; p += N) {
      const std::size_t m = std::min<std::size_t>(N, end - p);
      for (std::size_t k = 0; k < static_cast<std::size_t>(N); ++k) {
        const std::size_t i = k < m ? p + k : p;  // inactive lanes repeat the first ray
        valid[k] = k < m ? -1 : 0;
        set_lane(r, k, rays, i);
        if (split) r.mask[k] = static_pass_mask(ignored_by(rays, i));
      }
      RTCIntersectContext unfiltered = *context;  // the static scene has no context filter (make_view)
      unfiltered.filter = nullptr;
      occluded_packet(valid, first_pass(), split ? &unfiltered : context, &r);
      if (split) {  // the bodies, for the lanes the static scene left clear
        for (std::size_t k = 0; k < static_cast<std::size_t>(N); ++k) {
          r.mask[k] = body_pass_mask(ignored_by(rays, k < m ? p + k : p));
          if (r.tfar[k] < 0.0f) valid[k] = 0;
        }
        occluded_packet(valid, top, context, &r);
      }
      for (std::size_t k = 0; k < m; ++k) tfar[p + k - begin] = r.tfar[k];
    }
  }

  // An occlusion query's context when rays ignore bodies: Embree hands &context back to the filter,
  // which reads the rest (this view, for the body of a hit's instance, and each ray's ignored body, by
  // ray id = index in the batch). Standard layout, `context` first, so the cast back is valid.
  struct IgnoringContext {
    RTCIntersectContext context;
    const Impl* view;
    const std::int32_t* ignore_body;
  };

  // Rejects every candidate hit on the ray's ignored body (Embree then looks further along the ray).
  static void reject_ignored_body(const RTCFilterFunctionNArguments* args) {
    const auto* self = reinterpret_cast<const IgnoringContext*>(args->context);
    const std::vector<Instance>& instances = self->view->instances;
    for (unsigned k = 0; k < args->N; ++k) {
      if (args->valid[k] != -1) continue;
      const unsigned inst = RTCHitN_instID(args->hit, args->N, k, 0);
      const std::int32_t body = inst == kInvalidId || instances.empty() ? kStaticBody : instances[inst].body;
      if (body == self->ignore_body[RTCRayN_id(args->ray, args->N, k)]) args->valid[k] = 0;
    }
  }

  bool stream_aligned(const RayBatch& rays, std::size_t i, const RayHits& hits) const {
    return aligned16(&rays.p_WO_x[i]) && aligned16(&rays.p_WO_y[i]) && aligned16(&rays.p_WO_z[i]) &&
           aligned16(&rays.d_W_x[i]) && aligned16(&rays.d_W_y[i]) && aligned16(&rays.d_W_z[i]) &&
           aligned16(&rays.t_near[i]) && aligned16(&hits.distance[i]) && aligned16(&hits.n_W_x[i]) &&
           aligned16(&hits.n_W_y[i]) && aligned16(&hits.n_W_z[i]) && aligned16(&hits.triangle[i]) &&
           aligned16(&hits.tex_u[i]) && aligned16(&hits.tex_v[i]);
  }
};

EmbreeScene::EmbreeScene(const std::string& device_config, RayKernels kernels) : impl_(std::make_unique<Impl>()) {
  impl_->world = std::make_shared<EmbreeWorld>();
  EmbreeWorld& w = *impl_->world;
  w.refine = kernels == RayKernels::kPortable;
  std::string config = device_config;
  if (w.refine && config.find("isa=") == std::string::npos) {
    config += (config.empty() ? "" : ",") + std::string("isa=sse4.2");
  }
  w.device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (w.device == nullptr) {
    throw std::runtime_error("EmbreeScene: rtcNewDevice(\"" + config + "\") failed (Embree error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  }
  rtcSetDeviceErrorFunction(w.device, &EmbreeWorld::on_error, &w);
  if (rtcGetDeviceProperty(w.device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0) {
    w.packet_width = 16;
  } else if (rtcGetDeviceProperty(w.device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0) {
    w.packet_width = 8;
  }
  // No context filter on the static scene: the flag costs ~7 % of a camera frame's traversal of the
  // seabed (bench/render.cc), and occluded()'s filter only ever rejects body hits (see occluded()).
  // Robust mode everywhere: Embree's watertight triangle test, so no ray slips between two triangles
  // sharing an edge (seen without it: a camera ray through the seabed mesh, a hit with one kernel and a
  // miss with another); it cost nothing measurable on a camera frame (docs/benchmarks.md).
  w.static_scene = rtcNewScene(w.device);
  rtcSetSceneFlags(w.static_scene, RTC_SCENE_FLAG_ROBUST);
  w.check("creating the static scene");
}

EmbreeScene::EmbreeScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;

int EmbreeScene::add_static_mesh(const TriangleMesh& mesh_W, std::uint32_t material_id,
                                 const std::string& name, StaticShape shape) {
  EmbreeWorld& w = *impl_->world;
  const std::string prefix = format_mesh("static mesh", name);
  if (w.built) throw std::logic_error(prefix + "added after build()");
  validate(mesh_W, prefix);
  if (shape == StaticShape::kHeightField) {
    // Every triangle's plane must face up (|grad h| = |n_xy| / n_z, the slope SlopeGrid keeps by region).
    for (std::size_t t = 0; t < mesh_W.num_triangles(); ++t) {
      const auto vertex = [&](int k) {
        const std::size_t v = mesh_W.indices[3 * t + static_cast<std::size_t>(k)];
        return Eigen::Vector3d(mesh_W.positions[3 * v], mesh_W.positions[3 * v + 1], mesh_W.positions[3 * v + 2]);
      };
      const Eigen::Vector3d n = (vertex(1) - vertex(0)).cross(vertex(2) - vertex(0));
      if (n.squaredNorm() == 0.0) continue;  // degenerate: no plane, no slope
      if (!(n.z() > 0.0)) {
        throw std::invalid_argument(prefix + "declared a height field, but triangle " + std::to_string(t) +
                                    " does not face up (counter-clockwise seen from above)");
      }
    }
  }
  SceneMeshInfo info{name, kStaticBody, material_id, 0};
  const int id = w.add_mesh(w.static_scene, w.static_mesh_of_geometry, mesh_W, info);
  w.static_triangles += mesh_W.num_triangles();
  if (shape == StaticShape::kHeightField) {
    ++w.static_height_fields;
    w.height_field_slopes = SlopeGrid(mesh_W);
  } else {
    ++w.other_static_meshes;
  }
  return id;
}

std::optional<double> EmbreeScene::static_height_field_max_slope() const {
  const EmbreeWorld& w = *impl_->world;
  if (w.static_height_fields != 1 || w.other_static_meshes != 0) return std::nullopt;
  return w.height_field_slopes.max_slope();
}

std::optional<double> EmbreeScene::static_height_field_max_slope(const Eigen::AlignedBox2d& region_xy) const {
  const EmbreeWorld& w = *impl_->world;
  if (w.static_height_fields != 1 || w.other_static_meshes != 0) return std::nullopt;
  return w.height_field_slopes.max_slope_in(region_xy);
}

std::vector<BodyBounds> EmbreeScene::body_bounds_W() const {
  const Impl& s = *impl_;
  if (!s.world->built) throw std::logic_error("EmbreeScene::body_bounds_W: called before build()");
  if (!s.poses_set) throw std::logic_error("EmbreeScene::body_bounds_W: body poses were never set");
  return s.body_bounds;
}

int EmbreeScene::add_body_mesh(int body_index, const TriangleMesh& mesh_B, std::uint32_t material_id,
                               const std::string& name) {
  EmbreeWorld& w = *impl_->world;
  const std::string prefix = format_mesh("mesh of body " + std::to_string(body_index), name);
  if (w.built) throw std::logic_error(prefix + "added after build()");
  if (body_index < 0) throw std::invalid_argument(prefix + "body index must be >= 0");
  validate(mesh_B, prefix);
  EmbreeWorld::BodyScene& body = w.body_scenes[body_index];
  if (body.scene == nullptr) {
    body.scene = rtcNewScene(w.device);
    // occluded()'s ignore filter; robust: see the constructor.
    rtcSetSceneFlags(body.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
    w.check("creating a body scene");
  }
  for (std::size_t v = 0; v < mesh_B.num_vertices(); ++v) {
    body.bounds_B.extend(Eigen::Vector3d(mesh_B.positions[3 * v], mesh_B.positions[3 * v + 1], mesh_B.positions[3 * v + 2]));
  }
  SceneMeshInfo info{name, body_index, material_id, 0};
  return w.add_mesh(body.scene, body.mesh_of_geometry, mesh_B, info);
}

void EmbreeScene::build() {
  EmbreeWorld& w = *impl_->world;
  if (w.built) throw std::logic_error("EmbreeScene::build: called twice");
  if (w.meshes.empty()) throw std::logic_error("EmbreeScene::build: the scene has no meshes");
  rtcCommitScene(w.static_scene);
  w.check("building the static BVH");
  for (auto& [body, scene] : w.body_scenes) {
    rtcCommitScene(scene.scene);
    w.check("building a body BVH");
  }
  w.num_bodies = w.body_scenes.empty() ? 0 : w.body_scenes.rbegin()->first + 1;
  w.built = true;
  impl_->make_view();
}

EmbreeScene EmbreeScene::view() const {
  if (!built()) throw std::logic_error("EmbreeScene::view: called before build()");
  auto impl = std::make_unique<Impl>();
  impl->world = impl_->world;
  impl->make_view();
  return EmbreeScene(std::move(impl));
}

bool EmbreeScene::built() const { return impl_->world->built; }

void EmbreeScene::check_body_poses(const std::vector<Eigen::Isometry3d>& X_WB) const {
  if (X_WB.size() < static_cast<std::size_t>(impl_->world->num_bodies)) {
    throw std::invalid_argument("EmbreeScene: " + std::to_string(X_WB.size()) + " body poses for " +
                                std::to_string(impl_->world->num_bodies) + " bodies (X_WB needs one per body index)");
  }
  for (const Impl::Instance& instance : impl_->instances) {
    if (instance.body == kStaticBody) continue;
    const Eigen::Isometry3d& X = X_WB[static_cast<std::size_t>(instance.body)];
    const std::string prefix = "EmbreeScene: X_WB of body " + std::to_string(instance.body) + " ";
    if (!X.matrix().allFinite()) throw std::invalid_argument(prefix + "is not finite");
    const double error =
        (X.linear().transpose() * X.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (error > 1e-6 || X.linear().determinant() < 0.0) {
      throw std::invalid_argument(prefix + "is not a rigid transform (|R^T R - I| = " +
                                  std::to_string(error) + ", det R = " +
                                  std::to_string(X.linear().determinant()) + ")");
    }
  }
}

void EmbreeScene::set_body_poses(const std::vector<Eigen::Isometry3d>& X_WB) {
  Impl& s = *impl_;
  if (!s.world->built) throw std::logic_error("EmbreeScene::set_body_poses: called before build()");
  if (s.world->num_bodies == 0) return;
  check_body_poses(X_WB);
  bool changed = !s.poses_set;
  for (Impl::Instance& instance : s.instances) {
    if (instance.body == kStaticBody) continue;
    const Eigen::Isometry3d& X = X_WB[static_cast<std::size_t>(instance.body)];
    const Transform12 transform = to_transform12(X);
    if (transform == instance.transform && s.poses_set) continue;
    instance.transform = transform;
    instance.R_WB = X.linear().cast<float>();
    rtcSetGeometryTransform(instance.geometry, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, transform.data());
    rtcCommitGeometry(instance.geometry);
    changed = true;
  }
  if (changed) {
    rtcCommitScene(s.top);
    s.world->check("committing body poses");
    s.update_body_bounds();
  }
  s.poses_set = true;
}

void EmbreeScene::intersect(const RayBatch& rays, std::size_t begin, std::size_t end, QueryPath path,
                            RayHits& hits) const {
  const Impl& s = *impl_;
  if (!s.world->built) throw std::logic_error("EmbreeScene::intersect: called before build()");
  if (!s.poses_set) throw std::logic_error("EmbreeScene::intersect: body poses were never set");
  if (!rays.consistent()) throw std::invalid_argument("EmbreeScene::intersect: ray arrays differ in length");
  if (begin > end || end > rays.size() || hits.size() < end || hits.n_W_x.size() != hits.size() ||
      hits.n_W_y.size() != hits.size() || hits.n_W_z.size() != hits.size() ||
      hits.body.size() != hits.size() || hits.mesh.size() != hits.size() ||
      hits.material.size() != hits.size() || hits.triangle.size() != hits.size()) {
    throw std::out_of_range("EmbreeScene::intersect: range [" + std::to_string(begin) + ", " +
                            std::to_string(end) + ") outside the batch (" + std::to_string(rays.size()) +
                            " rays) or the hits (" + std::to_string(hits.size()) + ")");
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = rays.coherence == RayCoherence::kCoherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                                             : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  if (path == QueryPath::kAuto) path = QueryPath::kStream;
  std::size_t i = begin;
  while (i < end) {
    std::size_t block_end = std::min(end, i + kBlock);
    if (path == QueryPath::kStream && i % 4 != 0) block_end = std::min(block_end, (i + 3) / 4 * 4);
    validate_rays(rays, i, block_end);
    switch (path) {
      case QueryPath::kSingle: s.trace_single(rays, i, block_end, &context, hits); break;
      case QueryPath::kPacket: s.trace_packets(rays, i, block_end, &context, hits); break;
      case QueryPath::kAuto:
      case QueryPath::kStream:
        // Embree's streams need 16-byte aligned arrays: a misaligned head (begin not a multiple of 4)
        // or foreign allocators fall back to packets, which copy.
        if (s.stream_aligned(rays, i, hits)) {
          s.trace_stream(rays, i, block_end, &context, hits);
        } else {
          s.trace_packets(rays, i, block_end, &context, hits);
        }
        break;
    }
    i = block_end;
  }
  if (!rays.ignore_body.empty()) s.pass_ignored_bodies(rays, begin, end, &context, hits);
}

void EmbreeScene::occluded(const RayBatch& rays, std::size_t begin, std::size_t end,
                           std::vector<std::uint8_t>& blocked) const {
  const Impl& s = *impl_;
  if (!s.world->built) throw std::logic_error("EmbreeScene::occluded: called before build()");
  if (!s.poses_set) throw std::logic_error("EmbreeScene::occluded: body poses were never set");
  if (!rays.consistent()) throw std::invalid_argument("EmbreeScene::occluded: ray arrays differ in length");
  if (begin > end || end > rays.size() || blocked.size() < end) {
    throw std::out_of_range("EmbreeScene::occluded: range [" + std::to_string(begin) + ", " + std::to_string(end) +
                            ") outside the batch (" + std::to_string(rays.size()) + " rays) or the output (" +
                            std::to_string(blocked.size()) + ")");
  }
  Impl::IgnoringContext ignoring{};
  rtcInitIntersectContext(&ignoring.context);
  // Always incoherent: Debian 12's Embree 3.13.5 traces a coherent occlusion stream with its AVX-512
  // kernels in a loop that, for some valid rays (finite, unit directions, t_near <= t_far), never ends: seen
  // on an AMD EPYC (Zen 4) with render/frame_test.cc's FrameTest.ProvablyClearShadowRays... followed by
  // FrameTest.NegligibleDaylight..., and in hadald's first camera frame. Its AVX2 and SSE4.2 kernels and
  // the incoherent mode return. Shadow rays (the only coherent occlusion batches) start at scattered hit
  // points anyway.
  ignoring.context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  if (!rays.ignore_body.empty()) {
    ignoring.context.filter = &Impl::reject_ignored_body;
    ignoring.view = &s;
    ignoring.ignore_body = rays.ignore_body.data();
  }
  for (std::size_t i = begin; i < end;) {
    std::size_t block_end = std::min(end, i + kBlock);
    if (i % 4 != 0) block_end = std::min(block_end, (i + 3) / 4 * 4);  // later blocks start aligned
    validate_rays(rays, i, block_end);
    s.occlude_block(rays, i, block_end, &ignoring.context, blocked.data());
    i = block_end;
  }
  // The filter runs on body hits only (the static scene has no context filter, for speed): a ray that
  // ignores the static world itself takes intersect()'s answer instead (unless split: then its first
  // pass has mask 0, and the static instance is left out of the second by mask).
  if (rays.ignore_body.empty() || s.split) return;
  for (std::size_t k = begin; k < end; ++k) {
    if (rays.ignore_body[k] != kStaticBody || blocked[k] == 0) continue;
    RayBatch one;
    one.add_ray(Eigen::Vector3f(rays.p_WO_x[k], rays.p_WO_y[k], rays.p_WO_z[k]),
                Eigen::Vector3f(rays.d_W_x[k], rays.d_W_y[k], rays.d_W_z[k]), rays.t_near[k], rays.t_far[k], kStaticBody);
    RayHits hit;
    hit.resize(1);
    intersect(one, 0, 1, QueryPath::kSingle, hit);
    blocked[k] = hit.hit(0) ? 1 : 0;
  }
}

int EmbreeScene::num_bodies() const { return impl_->world->num_bodies; }
int EmbreeScene::num_meshes() const { return static_cast<int>(impl_->world->meshes.size()); }

const SceneMeshInfo& EmbreeScene::mesh_info(int mesh_id) const {
  if (mesh_id < 0 || mesh_id >= num_meshes()) {
    throw std::out_of_range("EmbreeScene::mesh_info: no mesh " + std::to_string(mesh_id) + " (the scene has " +
                            std::to_string(num_meshes()) + ")");
  }
  return impl_->world->meshes[static_cast<std::size_t>(mesh_id)].info;
}

std::size_t EmbreeScene::num_static_triangles() const { return impl_->world->static_triangles; }
int EmbreeScene::packet_width() const { return impl_->world->packet_width; }
RTCSceneTy* EmbreeScene::embree_scene() const { return impl_->trace; }

}  // namespace hadal::geometry
