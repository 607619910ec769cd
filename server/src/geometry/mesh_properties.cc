#include "hadal/geometry/mesh_properties.h"
#include "hadal/core/parallel_for.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace hadal::geometry {
namespace {

constexpr std::size_t kChunk = 1 << 16;  // triangles per work item


// Stable LSD radix sort of `keys` on bits [low_bit, 64) in 11-bit digits; digits that are equal
// in every key are skipped. `scratch` is resized to keys.size().
void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch,
                int low_bit) {
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t(1) << kBits;
  const int passes = (64 - low_bit + kBits - 1) / kBits;
  std::vector<std::array<std::size_t, kBuckets>> histograms(passes);
  for (auto& h : histograms) h.fill(0);
  for (std::uint64_t k : keys)
    for (int p = 0; p < passes; ++p) ++histograms[p][(k >> (low_bit + p * kBits)) & (kBuckets - 1)];
  scratch.resize(keys.size());
  for (int p = 0; p < passes; ++p) {
    auto& h = histograms[p];
    if (std::any_of(h.begin(), h.end(), [&](std::size_t c) { return c == keys.size(); })) continue;
    std::size_t sum = 0;
    for (auto& c : h) {
      const std::size_t count = c;
      c = sum;
      sum += count;
    }
    const int shift = low_bit + p * kBits;
    for (std::uint64_t k : keys) scratch[h[(k >> shift) & (kBuckets - 1)]++] = k;
    keys.swap(scratch);
  }
}

std::uint32_t float_key(float f) {
  if (f == 0.0f) f = 0.0f;  // -0 and +0 are the same position
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof(bits));
  return bits;
}

// canonical[v] = the lowest-numbered vertex with exactly v's position.
std::vector<std::uint32_t> weld_by_position(const std::vector<float>& positions) {
  const std::size_t n = positions.size() / 3;
  std::vector<std::uint64_t> keys(n), scratch;
  for (std::size_t v = 0; v < n; ++v) {
    // 32-bit mix of the three coordinates' bits (collisions are resolved exactly below).
    std::uint64_t h = float_key(positions[3 * v]);
    h = h * 0x9E3779B97F4A7C15ull ^ float_key(positions[3 * v + 1]);
    h = h * 0x9E3779B97F4A7C15ull ^ float_key(positions[3 * v + 2]);
    h *= 0xD6E8FEB86659FD93ull;
    keys[v] = (h & 0xFFFFFFFF00000000ull) | v;
  }
  radix_sort(keys, scratch, 32);  // stable: equal hashes stay in vertex order
  std::vector<std::uint32_t> canonical(n);
  auto same = [&](std::uint32_t a, std::uint32_t b) {
    return float_key(positions[3 * a]) == float_key(positions[3 * b]) &&
           float_key(positions[3 * a + 1]) == float_key(positions[3 * b + 1]) &&
           float_key(positions[3 * a + 2]) == float_key(positions[3 * b + 2]);
  };
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin + 1;
    while (end < n && (keys[end] >> 32) == (keys[begin] >> 32)) ++end;
    for (std::size_t i = begin; i < end; ++i) {
      const auto v = static_cast<std::uint32_t>(keys[i]);
      canonical[v] = v;
      for (std::size_t j = begin; j < i; ++j) {
        const auto w = static_cast<std::uint32_t>(keys[j]);
        if (canonical[w] == w && same(v, w)) {
          canonical[v] = w;
          break;
        }
      }
    }
    begin = end;
  }
  return canonical;
}

struct Sums {
  double area = 0.0, volume = 0.0;
  std::array<double, 3> first{};   // int (x - r) dV
  std::array<double, 6> second{};  // int (x - r)(x - r)^T dV: xx yy zz xy yz zx
};

}  // namespace

MeshProperties compute_mesh_properties(const TriangleMesh& mesh) {
  if (mesh.positions.size() % 3 != 0 || mesh.indices.size() % 3 != 0)
    throw std::invalid_argument(
        "compute_mesh_properties: positions and indices must be whole triples");
  const std::size_t nv = mesh.num_vertices(), nt = mesh.num_triangles();
  for (std::uint32_t i : mesh.indices)
    if (i >= nv)
      throw std::invalid_argument("compute_mesh_properties: index " + std::to_string(i) +
                                  " out of range (" + std::to_string(nv) + " vertices)");
  MeshProperties props;
  if (nv == 0) return props;
  static const unsigned hw = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  const unsigned workers = nt > 2 * kChunk ? hw : 1;
  const float* p = mesh.positions.data();

  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (std::size_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double(p[3 * v + k]));
      hi[k] = std::max(hi[k], double(p[3 * v + k]));
    }
  props.bounds_min = lo;
  props.bounds_max = hi;
  const Eigen::Vector3d r = 0.5 * (lo + hi);

  props.face_area.resize(nt);
  props.normal_x.resize(nt);
  props.normal_y.resize(nt);
  props.normal_z.resize(nt);
  props.centroid_x.resize(nt);
  props.centroid_y.resize(nt);
  props.centroid_z.resize(nt);
  const std::size_t chunks = (nt + kChunk - 1) / kChunk;
  std::vector<Sums> partial(chunks);
  spawned_threads(workers)(chunks, [&](std::size_t c) {
    Sums s;
    const std::size_t end = std::min(nt, (c + 1) * kChunk);
    for (std::size_t t = c * kChunk; t < end; ++t) {
      const std::uint32_t* tri = mesh.indices.data() + 3 * t;
      const double ax = p[3 * tri[0]] - r[0], ay = p[3 * tri[0] + 1] - r[1],
                   az = p[3 * tri[0] + 2] - r[2];
      const double bx = p[3 * tri[1]] - r[0], by = p[3 * tri[1] + 1] - r[1],
                   bz = p[3 * tri[1] + 2] - r[2];
      const double cx = p[3 * tri[2]] - r[0], cy = p[3 * tri[2] + 1] - r[1],
                   cz = p[3 * tri[2] + 2] - r[2];
      const double ux = bx - ax, uy = by - ay, uz = bz - az, vx = cx - ax, vy = cy - ay,
                   vz = cz - az;
      const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
      const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
      const double inv = len > 0.0 ? 1.0 / len : 0.0;
      props.face_area[t] = 0.5 * len;
      props.normal_x[t] = nx * inv;
      props.normal_y[t] = ny * inv;
      props.normal_z[t] = nz * inv;
      const double sx = ax + bx + cx, sy = ay + by + cy, sz = az + bz + cz;
      props.centroid_x[t] = sx / 3.0 + r[0];
      props.centroid_y[t] = sy / 3.0 + r[1];
      props.centroid_z[t] = sz / 3.0 + r[2];
      s.area += 0.5 * len;
      // Signed tetrahedron (r, a, b, c): v = a . (b x c) / 6.
      const double v =
          (ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)) / 6.0;
      s.volume += v;
      s.first[0] += v * sx / 4.0;
      s.first[1] += v * sy / 4.0;
      s.first[2] += v * sz / 4.0;
      const double w = v / 20.0;
      s.second[0] += w * (ax * ax + bx * bx + cx * cx + sx * sx);
      s.second[1] += w * (ay * ay + by * by + cy * cy + sy * sy);
      s.second[2] += w * (az * az + bz * bz + cz * cz + sz * sz);
      s.second[3] += w * (ax * ay + bx * by + cx * cy + sx * sy);
      s.second[4] += w * (ay * az + by * bz + cy * cz + sy * sz);
      s.second[5] += w * (az * ax + bz * bx + cz * cx + sz * sx);
    }
    partial[c] = s;
  });
  Sums total;  // summed in chunk order, so the result does not depend on the thread count
  for (const Sums& s : partial) {
    total.area += s.area;
    total.volume += s.volume;
    for (int k = 0; k < 3; ++k) total.first[k] += s.first[k];
    for (int k = 0; k < 6; ++k) total.second[k] += s.second[k];
  }
  props.surface_area = total.area;
  props.volume = total.volume;
  if (total.volume != 0.0) {
    const Eigen::Vector3d c_r(total.first[0] / total.volume, total.first[1] / total.volume,
                              total.first[2] / total.volume);  // centroid relative to r
    props.centroid = r + c_r;
    Eigen::Matrix3d C;
    C << total.second[0], total.second[3], total.second[5], total.second[3], total.second[1],
        total.second[4], total.second[5], total.second[4], total.second[2];
    C -= total.volume * c_r * c_r.transpose();  // parallel-axis shift from r to the centroid
    props.inertia_unit_density = C.trace() * Eigen::Matrix3d::Identity() - C;
  }

  // Closedness: directed edges (a, b) on welded vertices, counting-sorted by min(a, b) into one
  // flat array of (max(a, b) << 1 | direction); each vertex's short run is then sorted in place.
  if (nt == 0 || nv >= (std::size_t(1) << 31)) return props;
  const std::vector<std::uint32_t> canonical = weld_by_position(mesh.positions);
  std::vector<std::uint32_t> start(nv + 1, 0);
  for (std::size_t t = 0; t < nt; ++t)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = canonical[mesh.indices[3 * t + e]],
                          b = canonical[mesh.indices[3 * t + (e + 1) % 3]];
      if (a != b) ++start[std::min(a, b) + 1];  // a == b: a collapsed edge of a degenerate triangle
    }
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> cursor(start.begin(), start.end() - 1), other(start[nv]);
  for (std::size_t t = 0; t < nt; ++t)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = canonical[mesh.indices[3 * t + e]],
                          b = canonical[mesh.indices[3 * t + (e + 1) % 3]];
      if (a < b)
        other[cursor[a]++] = b << 1;
      else if (b < a)
        other[cursor[b]++] = (a << 1) | 1u;
    }
  for (std::size_t v = 0; v < nv; ++v) {
    std::uint32_t* begin = other.data() + start[v];
    std::uint32_t* const end = other.data() + start[v + 1];
    std::sort(begin, end);
    while (begin < end) {
      std::uint32_t* run = begin;
      std::size_t backward = 0;
      while (run < end && (*run >> 1) == (*begin >> 1)) backward += *run++ & 1u;
      const std::size_t uses = static_cast<std::size_t>(run - begin);
      if (uses == 1)
        ++props.boundary_edges;
      else if (uses != 2 || backward != 1)
        ++props.non_manifold_edges;
      begin = run;
    }
  }
  props.closed = props.boundary_edges == 0 && props.non_manifold_edges == 0;
  return props;
}

}  // namespace hadal::geometry
