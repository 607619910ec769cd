#include "hadal/assets/mesh_generators.h"
#include "hadal/core/units.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace hadal::assets {
namespace {


void push3(std::vector<float>& v, double x, double y, double z) {
  v.push_back(static_cast<float>(x));
  v.push_back(static_cast<float>(y));
  v.push_back(static_cast<float>(z));
}

void push_triangle(MeshData& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  m.indices.push_back(a);
  m.indices.push_back(b);
  m.indices.push_back(c);
}

// Portable uniform double in [0, 1) from a 64-bit Mersenne twister (std::uniform_real_distribution
// is not specified bit-for-bit, so seeded assets would differ between standard libraries).
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace

void compute_vertex_normals(MeshData& mesh) {
  const std::size_t nv = mesh.num_vertices();
  std::vector<double> acc(3 * nv, 0.0);
  const auto& p = mesh.positions;
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    const std::uint32_t ia = mesh.indices[3 * t], ib = mesh.indices[3 * t + 1],
                        ic = mesh.indices[3 * t + 2];
    const double e1[3] = {p[3 * ib] - double(p[3 * ia]), p[3 * ib + 1] - double(p[3 * ia + 1]),
                          p[3 * ib + 2] - double(p[3 * ia + 2])};
    const double e2[3] = {p[3 * ic] - double(p[3 * ia]), p[3 * ic + 1] - double(p[3 * ia + 1]),
                          p[3 * ic + 2] - double(p[3 * ia + 2])};
    // |e1 x e2| = 2 * area, so summing the raw cross products weights by area.
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                         e1[0] * e2[1] - e1[1] * e2[0]};
    for (std::uint32_t v : {ia, ib, ic})
      for (int k = 0; k < 3; ++k) acc[3 * v + k] += n[k];
  }
  mesh.normals.resize(3 * nv);
  for (std::size_t v = 0; v < nv; ++v) {
    const double len = std::sqrt(acc[3 * v] * acc[3 * v] + acc[3 * v + 1] * acc[3 * v + 1] +
                                 acc[3 * v + 2] * acc[3 * v + 2]);
    for (int k = 0; k < 3; ++k)
      mesh.normals[3 * v + k] = len > 0.0 ? static_cast<float>(acc[3 * v + k] / len) : 0.0f;
  }
}

void append_mesh(MeshData& mesh, const MeshData& other) {
  if (mesh.normals.empty() != other.normals.empty() || mesh.uvs.empty() != other.uvs.empty()) {
    if (mesh.positions.empty()) {
      // An empty target takes the attributes of the first mesh appended.
    } else {
      throw std::invalid_argument("append_mesh: meshes carry different vertex attributes");
    }
  }
  const auto offset = static_cast<std::uint32_t>(mesh.num_vertices());
  mesh.positions.insert(mesh.positions.end(), other.positions.begin(), other.positions.end());
  mesh.normals.insert(mesh.normals.end(), other.normals.begin(), other.normals.end());
  mesh.uvs.insert(mesh.uvs.end(), other.uvs.begin(), other.uvs.end());
  for (std::uint32_t i : other.indices) mesh.indices.push_back(i + offset);
}

void transform_mesh(MeshData& mesh, const double R[9], const double t[3]) {
  auto apply = [&](std::vector<float>& v, bool translate) {
    for (std::size_t i = 0; i + 2 < v.size(); i += 3) {
      const double x = v[i], y = v[i + 1], z = v[i + 2];
      for (int r = 0; r < 3; ++r)
        v[i + r] = static_cast<float>(R[3 * r] * x + R[3 * r + 1] * y + R[3 * r + 2] * z +
                                      (translate ? t[r] : 0.0));
    }
  };
  apply(mesh.positions, true);
  apply(mesh.normals, false);
}

MeshData make_box(double sx, double sy, double sz, double cx, double cy, double cz) {
  if (!(sx > 0.0 && sy > 0.0 && sz > 0.0))
    throw std::invalid_argument("make_box: size must be > 0");
  MeshData m;
  m.name = "box";
  const double lo[3] = {cx - sx / 2, cy - sy / 2, cz - sz / 2};
  const double hi[3] = {cx + sx / 2, cy + sy / 2, cz + sz / 2};
  // Each face: outward axis a with sign s; (u, v) axes chosen so u x v = s * e_a (CCW from
  // outside).
  for (int a = 0; a < 3; ++a) {
    for (int s = -1; s <= 1; s += 2) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;  // e_u x e_v = e_a
      const auto base = static_cast<std::uint32_t>(m.num_vertices());
      const double corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (const auto& c : corners) {
        double p[3];
        p[a] = s > 0 ? hi[a] : lo[a];
        // For the negative face swap the roles of u and v to reverse the winding.
        const double cu = s > 0 ? c[0] : c[1], cv = s > 0 ? c[1] : c[0];
        p[u] = cu > 0 ? hi[u] : lo[u];
        p[v] = cv > 0 ? hi[v] : lo[v];
        push3(m.positions, p[0], p[1], p[2]);
        double n[3] = {0, 0, 0};
        n[a] = s;
        push3(m.normals, n[0], n[1], n[2]);
        m.uvs.push_back(static_cast<float>(c[0]));
        m.uvs.push_back(static_cast<float>(c[1]));
      }
      push_triangle(m, base, base + 1, base + 2);
      push_triangle(m, base, base + 2, base + 3);
    }
  }
  return m;
}

MeshData make_revolved(const std::vector<double>& zs, const std::vector<double>& rs, int segments) {
  const std::size_t K = zs.size();
  if (segments < 3 || K < 3 || rs.size() != K || rs.front() != 0.0 || rs.back() != 0.0)
    throw std::invalid_argument("make_revolved: need >= 3 segments and a profile with zero ends");
  for (std::size_t k = 1; k + 1 < K; ++k)
    if (!(rs[k] > 0.0)) throw std::invalid_argument("make_revolved: inner radii must be > 0");
  for (std::size_t k = 1; k < K; ++k)
    if (!(zs[k] > zs[k - 1])) throw std::invalid_argument("make_revolved: z must increase");
  MeshData m;
  m.name = "revolved";
  std::vector<double> c(segments), s(segments);
  for (int j = 0; j < segments; ++j) {
    const double phi = 2.0 * kPi * j / segments;
    c[j] = std::cos(phi);
    s[j] = std::sin(phi);
  }
  // Vertex 0: bottom pole; rings k = 1..K-2 of `segments` vertices; last: top pole.
  push3(m.positions, 0.0, 0.0, zs.front());
  for (std::size_t k = 1; k + 1 < K; ++k)
    for (int j = 0; j < segments; ++j) push3(m.positions, rs[k] * c[j], rs[k] * s[j], zs[k]);
  push3(m.positions, 0.0, 0.0, zs.back());
  const auto n = static_cast<std::uint32_t>(segments);
  auto ring = [&](std::size_t k, int j) {
    return static_cast<std::uint32_t>(1 + (k - 1) * n + static_cast<std::uint32_t>(j % segments));
  };
  const auto top = static_cast<std::uint32_t>(m.num_vertices() - 1);
  for (int j = 0; j < segments; ++j) {
    // Bottom fan: outward normal points to -z, so the ring is traversed clockwise seen from +z.
    push_triangle(m, 0, ring(1, j + 1), ring(1, j));
    for (std::size_t k = 1; k + 2 < K; ++k) {
      push_triangle(m, ring(k, j), ring(k, j + 1), ring(k + 1, j + 1));
      push_triangle(m, ring(k, j), ring(k + 1, j + 1), ring(k + 1, j));
    }
    push_triangle(m, ring(K - 2, j), ring(K - 2, j + 1), top);
  }
  compute_vertex_normals(m);
  return m;
}

MeshData make_uv_sphere(double radius, int segments, int rings) {
  if (!(radius > 0.0) || rings < 2)
    throw std::invalid_argument("make_uv_sphere: radius must be > 0 and rings >= 2");
  std::vector<double> zs(rings + 1), rs(rings + 1);
  for (int k = 0; k <= rings; ++k) {
    const double theta = kPi * (rings - k) / rings;  // polar angle, from the bottom pole up
    zs[k] = radius * std::cos(theta);
    rs[k] = radius * std::sin(theta);
  }
  zs.front() = -radius;
  zs.back() = radius;
  rs.front() = rs.back() = 0.0;
  MeshData m = make_revolved(zs, rs, segments);
  m.name = "sphere";
  // Exact normals of the sphere (position / r) rather than the averaged face normals.
  for (std::size_t i = 0; i < m.positions.size(); i += 3) {
    const double x = m.positions[i], y = m.positions[i + 1], z = m.positions[i + 2];
    const double len = std::sqrt(x * x + y * y + z * z);
    for (int k = 0; k < 3; ++k) m.normals[i + k] = static_cast<float>(m.positions[i + k] / len);
  }
  return m;
}

MeshData make_cylinder(double radius, double length, int segments) {
  if (!(radius > 0.0 && length > 0.0) || segments < 3)
    throw std::invalid_argument("make_cylinder: radius, length must be > 0 and segments >= 3");
  MeshData m;
  m.name = "cylinder";
  const double h = length / 2;
  std::vector<double> c(segments), s(segments);
  for (int j = 0; j < segments; ++j) {
    const double phi = 2.0 * kPi * j / segments;
    c[j] = std::cos(phi);
    s[j] = std::sin(phi);
  }
  const auto n = static_cast<std::uint32_t>(segments);
  // Side: one ring at each end (smooth radial normals).
  for (int end = 0; end < 2; ++end)
    for (int j = 0; j < segments; ++j) {
      push3(m.positions, radius * c[j], radius * s[j], end ? h : -h);
      push3(m.normals, c[j], s[j], 0.0);
      m.uvs.push_back(static_cast<float>(double(j) / segments));
      m.uvs.push_back(static_cast<float>(end));
    }
  for (std::uint32_t j = 0; j < n; ++j) {
    const std::uint32_t j1 = (j + 1) % n;
    push_triangle(m, j, j1, n + j1);
    push_triangle(m, j, n + j1, n + j);
  }
  // Caps: centre + ring with flat normals (ring positions bitwise equal to the side's).
  for (int end = 0; end < 2; ++end) {
    const double z = end ? h : -h, nz = end ? 1.0 : -1.0;
    const auto centre = static_cast<std::uint32_t>(m.num_vertices());
    push3(m.positions, 0.0, 0.0, z);
    push3(m.normals, 0.0, 0.0, nz);
    m.uvs.push_back(0.5f);
    m.uvs.push_back(0.5f);
    for (int j = 0; j < segments; ++j) {
      push3(m.positions, radius * c[j], radius * s[j], z);
      push3(m.normals, 0.0, 0.0, nz);
      m.uvs.push_back(static_cast<float>(0.5 + 0.5 * c[j]));
      m.uvs.push_back(static_cast<float>(0.5 + 0.5 * s[j]));
    }
    for (std::uint32_t j = 0; j < n; ++j) {
      const std::uint32_t a = centre + 1 + j, b = centre + 1 + (j + 1) % n;
      if (end)
        push_triangle(m, centre, a, b);
      else
        push_triangle(m, centre, b, a);
    }
  }
  return m;
}

void torpedo_profile(double length, double radius, int profile_steps, std::vector<double>& zs,
                     std::vector<double>& rs) {
  if (!(radius > 0.0) || !(length > 3.5 * radius) || profile_steps < 2)
    throw std::invalid_argument("make_torpedo: need radius > 0, length > 3.5 radius, steps >= 2");
  // Tail: tangent ogive of length 2.5 r ending in a point; nose: hemisphere of radius r.
  const double tail = 2.5 * radius;
  const double rho = (radius * radius + tail * tail) / (2.0 * radius);  // ogive arc radius
  const double z_tip = -length / 2, z_nose = length / 2 - radius;
  zs.clear();
  rs.clear();
  for (int i = 0; i <= profile_steps; ++i) {     // tail tip -> full radius
    const double sz = tail * i / profile_steps;  // distance from the tip
    zs.push_back(z_tip + sz);
    rs.push_back(i == 0 ? 0.0 : std::sqrt(rho * rho - (tail - sz) * (tail - sz)) + radius - rho);
  }
  rs.back() = radius;
  for (int i = 0; i <= profile_steps; ++i) {  // nose: from the body end to the tip
    const double a = 0.5 * kPi * i / profile_steps;
    zs.push_back(z_nose + radius * std::sin(a));
    rs.push_back(radius * std::cos(a));
  }
  zs.back() = length / 2;
  rs.back() = 0.0;
}

MeshData make_torpedo(double length, double radius, int segments, int profile_steps) {
  std::vector<double> zs, rs;
  torpedo_profile(length, radius, profile_steps, zs, rs);
  MeshData m = make_revolved(zs, rs, segments);
  // Axis z -> body x (nose forward): rotation +90 deg about y, (x, y, z) -> (z, y, -x).
  const double R[9] = {0, 0, 1, 0, 1, 0, -1, 0, 0}, t[3] = {0, 0, 0};
  transform_mesh(m, R, t);
  m.name = "torpedo";
  return m;
}

bool GridSolid::cell(int i, int j, int k) const {
  const int nx = static_cast<int>(xs.size()) - 1, ny = static_cast<int>(ys.size()) - 1,
            nz = static_cast<int>(zs.size()) - 1;
  if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return false;
  return filled[static_cast<std::size_t>((k * ny + j) * nx + i)] != 0;
}

double GridSolid::volume() const {
  double v = 0.0;
  for (std::size_t k = 0; k + 1 < zs.size(); ++k)
    for (std::size_t j = 0; j + 1 < ys.size(); ++j)
      for (std::size_t i = 0; i + 1 < xs.size(); ++i)
        if (cell(int(i), int(j), int(k)))
          v += (xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]) * (zs[k + 1] - zs[k]);
  return v;
}

MeshData make_grid_solid(const GridSolid& g, const std::string& name) {
  MeshData m;
  m.name = name;
  const int n[3] = {int(g.xs.size()) - 1, int(g.ys.size()) - 1, int(g.zs.size()) - 1};
  const std::vector<double>* coord[3] = {&g.xs, &g.ys, &g.zs};
  int idx[3];
  for (idx[2] = 0; idx[2] < n[2]; ++idx[2])
    for (idx[1] = 0; idx[1] < n[1]; ++idx[1])
      for (idx[0] = 0; idx[0] < n[0]; ++idx[0]) {
        if (!g.cell(idx[0], idx[1], idx[2])) continue;
        for (int a = 0; a < 3; ++a)
          for (int s = -1; s <= 1; s += 2) {
            int nb[3] = {idx[0], idx[1], idx[2]};
            nb[a] += s;
            if (g.cell(nb[0], nb[1], nb[2])) continue;
            const int u = (a + 1) % 3, v = (a + 2) % 3;
            const auto base = static_cast<std::uint32_t>(m.num_vertices());
            const int corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (const auto& c : corners) {
              double p[3];
              p[a] = (*coord[a])[idx[a] + (s > 0 ? 1 : 0)];
              const int cu = s > 0 ? c[0] : c[1], cv = s > 0 ? c[1] : c[0];
              p[u] = (*coord[u])[idx[u] + cu];
              p[v] = (*coord[v])[idx[v] + cv];
              push3(m.positions, p[0], p[1], p[2]);
              double nrm[3] = {0, 0, 0};
              nrm[a] = s;
              push3(m.normals, nrm[0], nrm[1], nrm[2]);
              m.uvs.push_back(static_cast<float>(c[0]));
              m.uvs.push_back(static_cast<float>(c[1]));
            }
            push_triangle(m, base, base + 1, base + 2);
            push_triangle(m, base, base + 2, base + 3);
          }
      }
  return m;
}

GridSolid box_frame_solid(double sx, double sy, double sz, double bar) {
  if (!(bar > 0.0) || !(2 * bar < sx && 2 * bar < sy && 2 * bar < sz))
    throw std::invalid_argument("box_frame_solid: need 0 < 2 bar < every size");
  GridSolid g;
  g.xs = {-sx / 2, -sx / 2 + bar, sx / 2 - bar, sx / 2};
  g.ys = {-sy / 2, -sy / 2 + bar, sy / 2 - bar, sy / 2};
  g.zs = {-sz / 2, -sz / 2 + bar, sz / 2 - bar, sz / 2};
  g.filled.assign(27, 0);
  // A cell belongs to an edge bar when at least two of its indices are on the outside (0 or 2).
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        g.filled[(k * 3 + j) * 3 + i] = ((i != 1) + (j != 1) + (k != 1)) >= 2;
  return g;
}

GridSolid lander_solid(double sx, double sy, double sz, double bar, double leg_length) {
  if (!(leg_length > 0.0)) throw std::invalid_argument("lander_solid: leg_length must be > 0");
  GridSolid frame = box_frame_solid(sx, sy, sz, bar);
  GridSolid g;
  g.xs = frame.xs;
  g.ys = frame.ys;
  g.zs = {0.0, leg_length, leg_length + bar, leg_length + sz - bar, leg_length + sz};
  g.filled.assign(3 * 3 * 4, 0);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      g.filled[(0 * 3 + j) * 3 + i] = (i != 1 && j != 1);  // legs under the corner posts
      for (int k = 0; k < 3; ++k)
        g.filled[((k + 1) * 3 + j) * 3 + i] = frame.filled[(k * 3 + j) * 3 + i];
    }
  return g;
}

MeshData make_seabed(const SeabedSpec& spec) {
  if (spec.cells_x < 1 || spec.cells_y < 1 || !(spec.size_x > 0.0 && spec.size_y > 0.0))
    throw std::invalid_argument("make_seabed: need >= 1 cell and sizes > 0");
  struct Bump {
    double x, y, inv_two_sigma2, height;
  };
  std::mt19937_64 rng(spec.seed);
  std::vector<Bump> bumps;
  for (int b = 0; b < spec.bumps; ++b) {
    const double x = (uniform01(rng) - 0.5) * spec.size_x;
    const double y = (uniform01(rng) - 0.5) * spec.size_y;
    const double sigma = (0.04 + 0.16 * uniform01(rng)) * std::min(spec.size_x, spec.size_y);
    const double height = (2.0 * uniform01(rng) - 1.0) * spec.relief;
    bumps.push_back({x, y, 1.0 / (2.0 * sigma * sigma), height});
  }
  MeshData m;
  m.name = "seabed";
  const std::size_t vx = spec.cells_x + 1, vy = spec.cells_y + 1;
  m.positions.reserve(3 * vx * vy);
  m.normals.reserve(3 * vx * vy);
  m.uvs.reserve(2 * vx * vy);
  for (std::size_t j = 0; j < vy; ++j) {
    const double v = double(j) / spec.cells_y, y = (v - 0.5) * spec.size_y;
    for (std::size_t i = 0; i < vx; ++i) {
      const double u = double(i) / spec.cells_x, x = (u - 0.5) * spec.size_x;
      double z = 0.0, dzdx = 0.0, dzdy = 0.0;
      for (const Bump& b : bumps) {
        const double dx = x - b.x, dy = y - b.y;
        const double e = b.height * std::exp(-(dx * dx + dy * dy) * b.inv_two_sigma2);
        z += e;
        dzdx -= 2.0 * dx * b.inv_two_sigma2 * e;
        dzdy -= 2.0 * dy * b.inv_two_sigma2 * e;
      }
      push3(m.positions, x, y, z);
      const double len = std::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
      push3(m.normals, -dzdx / len, -dzdy / len, 1.0 / len);
      m.uvs.push_back(static_cast<float>(u));
      m.uvs.push_back(static_cast<float>(v));
    }
  }
  m.indices.reserve(6 * std::size_t(spec.cells_x) * spec.cells_y);
  for (std::size_t j = 0; j < std::size_t(spec.cells_y); ++j)
    for (std::size_t i = 0; i < std::size_t(spec.cells_x); ++i) {
      const auto a = static_cast<std::uint32_t>(j * vx + i), b = a + 1,
                 c = static_cast<std::uint32_t>(a + vx + 1), d = static_cast<std::uint32_t>(a + vx);
      push_triangle(m, a, b, c);  // CCW seen from above (+z)
      push_triangle(m, a, c, d);
    }
  return m;
}

SeabedSpec seabed_for_triangles(std::int64_t triangles, double size, std::uint64_t seed) {
  if (triangles < 2) throw std::invalid_argument("seabed_for_triangles: need >= 2 triangles");
  SeabedSpec spec;
  const int cells = std::max(1, static_cast<int>(std::lround(std::sqrt(triangles / 2.0))));
  spec.cells_x = spec.cells_y = cells;
  spec.size_x = spec.size_y = size;
  spec.relief = 0.05 * size;
  spec.seed = seed;
  return spec;
}

double regular_polygon_area(int n, double rho) {
  return 0.5 * n * rho * rho * std::sin(2.0 * kPi / n);
}

double regular_polygon_polar_moment(int n, double rho) {
  // n isosceles triangles (apex at the centre, legs rho, apex angle a = 2 pi / n); for a triangle
  // with one vertex at the origin J = (A/6)(|p1|^2 + |p2|^2 + p1.p2) = (A rho^2 / 6)(2 + cos a).
  const double a = 2.0 * kPi / n;
  return n * std::pow(rho, 4) / 12.0 * std::sin(a) * (2.0 + std::cos(a));
}

}  // namespace hadal::assets
