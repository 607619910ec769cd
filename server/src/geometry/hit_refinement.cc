#include "hadal/geometry/hit_refinement.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstring>

namespace hadal::geometry {
namespace {

// Rounding units of the coordinates within which Embree's kernels may disagree on which triangle a ray
// meets (an edge, a vertex), and the cosine under which a hit counts as grazing (its distance then 1 / cos
// as uncertain; kMinCosine bounds that).
constexpr double kZoneUlps = 32.0;
constexpr double kGrazingCosine = 0.05;
constexpr double kMinCosine = 1e-3;

// The ray's meeting with one triangle's plane: parameter, barycentrics, the point's signed distance to
// each edge (edge j is the one opposite vertex j; positive inside) and the unit normal.
struct PlaneHit {
  bool ok = false;
  double t = 0.0;
  double b[3] = {0.0, 0.0, 0.0};
  double edge_distance[3] = {0.0, 0.0, 0.0};
  double p[3] = {0.0, 0.0, 0.0};
  double n[3] = {0.0, 0.0, 0.0};
  double depth() const { return std::min({edge_distance[0], edge_distance[1], edge_distance[2]}); }
};

void vertex(const RefinementMesh& mesh, std::uint32_t index, double out[3]) {
  for (int a = 0; a < 3; ++a) out[a] = mesh.vertices[3 * static_cast<std::size_t>(index) + a];
}

double norm(const double x[3]) { return std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]); }

PlaneHit intersect(const RefinementMesh& mesh, std::uint32_t triangle, const double o[3], const double d[3]) {
  const std::uint32_t* tri = &mesh.triangles[3 * static_cast<std::size_t>(triangle)];
  double v[3][3];
  for (int j = 0; j < 3; ++j) vertex(mesh, tri[j], v[j]);
  double e1[3], e2[3], T[3];
  for (int a = 0; a < 3; ++a) {
    e1[a] = v[1][a] - v[0][a];
    e2[a] = v[2][a] - v[0][a];
    T[a] = o[a] - v[0][a];
  }
  // Moeller-Trumbore: P = d x e2, det = e1 . P, u = T . P / det, Q = T x e1, v = d . Q / det,
  // t = e2 . Q / det.
  const double P[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
  const double det = e1[0] * P[0] + e1[1] * P[1] + e1[2] * P[2];
  const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  const double area2 = norm(n);  // twice the area
  PlaneHit hit;
  // A degenerate triangle, or a ray within ~1e-9 rad of its plane: nothing to trust.
  if (!(area2 > 0.0) || !(std::abs(det) > 1e-9 * area2)) return hit;
  const double Q[3] = {T[1] * e1[2] - T[2] * e1[1], T[2] * e1[0] - T[0] * e1[2], T[0] * e1[1] - T[1] * e1[0]};
  hit.t = (e2[0] * Q[0] + e2[1] * Q[1] + e2[2] * Q[2]) / det;
  hit.b[1] = (T[0] * P[0] + T[1] * P[1] + T[2] * P[2]) / det;
  hit.b[2] = (d[0] * Q[0] + d[1] * Q[1] + d[2] * Q[2]) / det;
  hit.b[0] = 1.0 - hit.b[1] - hit.b[2];
  for (int a = 0; a < 3; ++a) {
    hit.p[a] = o[a] + hit.t * d[a];
    hit.n[a] = n[a] / area2;
  }
  // Distance to edge j = b_j times the height over it, 2 A / |edge j|.
  for (int j = 0; j < 3; ++j) {
    const double* a = v[(j + 1) % 3];
    const double* c = v[(j + 2) % 3];
    const double edge[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    hit.edge_distance[j] = hit.b[j] * area2 / norm(edge);
  }
  hit.ok = std::isfinite(hit.t) && std::isfinite(hit.depth());
  return hit;
}

// The answer from the plane hit of the triangle chosen.
RefinedHit refined(const PlaneHit& hit, std::uint32_t triangle) {
  RefinedHit out;
  out.ok = true;
  out.triangle = triangle;
  out.t = hit.t;
  out.u = hit.b[1];
  out.v = hit.b[2];
  std::copy(hit.n, hit.n + 3, out.n);
  return out;
}

}  // namespace

VertexTriangles vertex_triangles(const float* vertices, std::size_t num_vertices, const std::uint32_t* indices,
                                 std::size_t num_triangles) {
  VertexTriangles out;
  // Position ids: the vertices sorted by their coordinates' bits, each run of equal ones named by its
  // lowest index.
  std::vector<std::uint32_t> order(num_vertices);
  for (std::size_t v = 0; v < num_vertices; ++v) order[v] = static_cast<std::uint32_t>(v);
  const auto key = [vertices](std::uint32_t v) {
    std::array<std::uint32_t, 3> bits;
    std::memcpy(bits.data(), &vertices[3 * static_cast<std::size_t>(v)], sizeof bits);
    return bits;
  };
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    const auto ka = key(a), kb = key(b);
    return ka != kb ? ka < kb : a < b;
  });
  out.position.resize(num_vertices);
  for (std::size_t k = 0; k < num_vertices; ++k) {
    const bool same = k > 0 && key(order[k]) == key(order[k - 1]);
    out.position[order[k]] = same ? out.position[order[k - 1]] : order[k];
  }
  out.offsets.assign(num_vertices + 1, 0);
  for (std::size_t k = 0; k < 3 * num_triangles; ++k) ++out.offsets[out.position[indices[k]] + 1];
  for (std::size_t v = 0; v < num_vertices; ++v) out.offsets[v + 1] += out.offsets[v];
  out.triangles.resize(3 * num_triangles);
  std::vector<std::uint32_t> next(out.offsets.begin(), out.offsets.end() - 1);
  for (std::size_t k = 0; k < 3 * num_triangles; ++k) {
    out.triangles[next[out.position[indices[k]]]++] = static_cast<std::uint32_t>(k / 3);
  }
  return out;
}

RefinedHit refine_hit(const RefinementMesh& mesh, std::uint32_t triangle, const double o[3], const double d[3]) {
  RefinedHit out;
  out.triangle = triangle;
  const PlaneHit first = intersect(mesh, triangle, o, d);
  if (!first.ok) return out;
  // The zone where single-precision arithmetic can pick another triangle: kZoneUlps rounding units of the
  // largest coordinate involved (at least 1 m's worth), the same from whichever triangle it is seen.
  double scale = 1.0;
  for (int a = 0; a < 3; ++a) scale = std::max({scale, std::abs(o[a]), std::abs(first.p[a])});
  const double zone = kZoneUlps * FLT_EPSILON * scale;
  // Along a grazing ray, a rounding unit across the surface is 1 / cos of it along the ray.
  const double cosine = std::abs(first.n[0] * d[0] + first.n[1] * d[1] + first.n[2] * d[2]);
  const double along = zone / std::max(cosine, kMinCosine);
  const std::uint32_t* tri = &mesh.triangles[3 * static_cast<std::size_t>(triangle)];
  bool uncertain = cosine < kGrazingCosine;
  for (int j = 0; j < 3 && !uncertain; ++j) uncertain = first.edge_distance[j] < zone;
  if (!uncertain || mesh.adjacency == nullptr) return refined(first, triangle);
  // The triangles around Embree's triangle's vertices (its 1-ring), nearest hit first among those the ray
  // meets inside (within the zone) near Embree's distance; ties by the deeper inside, then the lower index.
  const VertexTriangles& around = *mesh.adjacency;
  thread_local std::vector<std::uint32_t> candidates;  // reused: no allocation per hit
  candidates.clear();
  for (int j = 0; j < 3; ++j) {
    const std::uint32_t at = around.position[tri[j]];
    candidates.insert(candidates.end(), around.triangles.begin() + around.offsets[at],
                      around.triangles.begin() + around.offsets[at + 1]);
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  PlaneHit best = first;
  std::uint32_t chosen = triangle;
  bool any = false;
  for (std::uint32_t c : candidates) {  // ascending: an exact tie keeps the lower index
    const PlaneHit hit = c == triangle ? first : intersect(mesh, c, o, d);
    if (!hit.ok || hit.depth() < -zone || std::abs(hit.t - first.t) > 4.0 * along) continue;
    if (!any || hit.t < best.t || (hit.t == best.t && hit.depth() > best.depth())) {
      best = hit;
      chosen = c;
      any = true;
    }
  }
  return refined(best, chosen);
}

}  // namespace hadal::geometry
