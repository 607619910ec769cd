#include "hadal/geometry/shape_overlap.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>

namespace hadal::geometry {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double sign_of(double x) { return x < 0.0 ? -1.0 : 1.0; }

// What a cell needs of a shape near a point p_G (in the shape's frame G).
struct SurfaceInfo {
  double phi = 0.0;                                  // signed distance of p_G [m]
  Eigen::Vector3d n_G = Eigen::Vector3d::UnitX();    // outward normal at the nearest surface point
  // A ball of radius rho touching the surface from inside at the nearest point lies in the shape,
  // as far as cells of half-diagonal r <= rho_cell_limit around p_G are concerned (rho = 0: none).
  double rho = 0.0;
  double rho_cell_limit = kInf;
  // Cells of half-diagonal r <= flat_cell_limit around p_G meet the shape exactly in the half-space
  // below the tangent plane (they reach no other face).
  double flat_cell_limit = -1.0;
};

// > 0 outside, <= 0 inside (closed solid); not a distance for boxes and cylinders.
double outside_measure(const CollisionShape& s, const Eigen::Vector3d& p) {
  const double half_length = 0.5 * s.length;
  switch (s.type) {
    case CollisionShapeType::kBox:
      return (p.cwiseAbs() - 0.5 * s.box_size).maxCoeff();
    case CollisionShapeType::kSphere:
      return p.norm() - s.radius;
    case CollisionShapeType::kCylinder:
      return std::max(std::sqrt(p.x() * p.x() + p.y() * p.y()) - s.radius, std::abs(p.z()) - half_length);
    case CollisionShapeType::kCapsule: {
      const double z = std::clamp(p.z(), -half_length, half_length);
      return Eigen::Vector3d(p.x(), p.y(), p.z() - z).norm() - s.radius;
    }
  }
  return kInf;
}

// A ball of radius `radius` around the nearest point on the segment |z| <= half_length of the z axis.
SurfaceInfo capsule_info(double radius, double half_length, const Eigen::Vector3d& p) {
  SurfaceInfo info;
  const Eigen::Vector3d v(p.x(), p.y(), p.z() - std::clamp(p.z(), -half_length, half_length));
  const double d = v.norm();
  info.phi = d - radius;
  if (d > 0.0) info.n_G = v / d;
  info.rho = radius;
  return info;
}

SurfaceInfo box_info(const Eigen::Vector3d& size, const Eigen::Vector3d& p) {
  SurfaceInfo info;
  const Eigen::Vector3d h = 0.5 * size;
  const Eigen::Vector3d q = p.cwiseAbs() - h;
  int axis = 0;
  int outside_axes = 0;
  for (int i = 0; i < 3; ++i) {
    if (q[i] > 0.0) ++outside_axes;
    if (q[i] > q[axis]) axis = i;
  }
  if (outside_axes > 0) {
    const Eigen::Vector3d d = q.cwiseMax(0.0);
    info.phi = d.norm();
    for (int i = 0; i < 3; ++i) info.n_G[i] = sign_of(p[i]) * d[i] / info.phi;
    if (outside_axes > 1) return info;  // nearest point on an edge or a corner
  } else {
    info.phi = q[axis];
    info.n_G = sign_of(p[axis]) * Eigen::Vector3d::Unit(axis);
  }
  // Nearest point on the face normal to `axis`: the cell must stay within the other two slabs and
  // on the inner side of the opposite face.
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  info.flat_cell_limit = std::min({-q[b], -q[c], std::abs(p[axis]) + h[axis]});
  return info;
}

SurfaceInfo cylinder_info(double radius, double half_length, const Eigen::Vector3d& p) {
  SurfaceInfo info;
  const double rho_p = std::sqrt(p.x() * p.x() + p.y() * p.y());
  const Eigen::Vector3d radial =
      rho_p > 0.0 ? Eigen::Vector3d(p.x() / rho_p, p.y() / rho_p, 0.0) : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d axial = sign_of(p.z()) * Eigen::Vector3d::UnitZ();
  const double dr = rho_p - radius, dz = std::abs(p.z()) - half_length;
  if (dr > 0.0 && dz > 0.0) {  // nearest point on a rim
    info.phi = std::hypot(dr, dz);
    info.n_G = (dr * radial + dz * axial) / info.phi;
  } else if (dr > dz) {  // side: the disc of the cross-section, while the cell stays between caps
    info.phi = dr;
    info.n_G = radial;
    info.rho = radius;
    info.rho_cell_limit = -dz;
  } else {  // cap: flat while the cell stays inside the side and above the other cap
    info.phi = dz;
    info.n_G = axial;
    info.flat_cell_limit = std::min(-dr, std::abs(p.z()) + half_length);
  }
  return info;
}

SurfaceInfo surface_info(const CollisionShape& s, const Eigen::Vector3d& p) {
  switch (s.type) {
    case CollisionShapeType::kBox:
      return box_info(s.box_size, p);
    case CollisionShapeType::kSphere:
      return capsule_info(s.radius, 0.0, p);
    case CollisionShapeType::kCylinder:
      return cylinder_info(s.radius, 0.5 * s.length, p);
    case CollisionShapeType::kCapsule:
      return capsule_info(s.radius, 0.5 * s.length, p);
  }
  return {};
}

// Volume fraction of the unit cube where sum_i m_i u_i <= alpha (m_i >= 0): by inclusion-exclusion
// over the corners, F = sum_S (-1)^|S| max(alpha - m_S, 0)^n / (n! prod m_i) over the n non-zero
// m_i. Components below 1e-6 sum(m) are dropped (cancellation), which shifts alpha by at most their
// sum: `upper` selects the side so the result stays a bound.
double cube_cut_fraction(const double m[3], double alpha, bool upper) {
  const double total = m[0] + m[1] + m[2];
  if (!(alpha > 0.0)) return 0.0;
  if (!(alpha < total)) return 1.0;
  // The complement is the same cut seen from the opposite corner; take the smaller side.
  if (alpha > 0.5 * total) return 1.0 - cube_cut_fraction(m, total - alpha, !upper);
  double kept[3];
  int n = 0;
  double dropped = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (m[i] > 1e-6 * total) {
      kept[n++] = m[i];
    } else {
      dropped += m[i];
    }
  }
  const double a = upper ? alpha : alpha - dropped;
  if (!(a > 0.0)) return 0.0;
  double sum = 0.0;
  for (int subset = 0; subset < (1 << n); ++subset) {
    double t = a;
    int size = 0;
    for (int i = 0; i < n; ++i) {
      if (subset & (1 << i)) {
        t -= kept[i];
        ++size;
      }
    }
    if (t > 0.0) {
      double power = t;
      for (int i = 1; i < n; ++i) power *= t;
      sum += (size & 1) ? -power : power;
    }
  }
  double denominator = 1.0;
  for (int i = 0; i < n; ++i) denominator *= (i + 1) * kept[i];
  return std::clamp(sum / denominator, 0.0, 1.0);
}

// The part of a cell inside one shape, bracketed by plane cuts n . (x - c) <= beta of the cell
// (centre c, half extents h): fraction(beta) = cube_cut_fraction(m, sum(m) / 2 + beta) with
// m_i = 2 |n_i| h_i.
struct Cut {
  Eigen::Vector3d n_B;
  double m[3];
  double beta_hi = 0.0;     // supporting plane: the shape lies below it
  double beta_lo = -kInf;   // the cell below this plane lies in the shape (-inf: none known)
  double lo = 0.0, hi = 0.0;  // fractions of the cell volume

  double fraction(double beta, bool upper) const {
    return cube_cut_fraction(m, 0.5 * (m[0] + m[1] + m[2]) + beta, upper);
  }
};

// Bounds on the fraction of the cell inside both a and b. Beside lo_a + lo_b - 1 <= . <= min(hi_a,
// hi_b): when the normals are nearly parallel (|n_a - n_b| = e), b's planes move by at most e r
// over the cell if turned to n_a, and two cuts with one normal nest; nearly opposite normals
// (|n_a + n_b| = e) make a slab {-beta_b <= n_a . (x - c) <= beta_a} of the same kind. This settles
// coplanar faces and tangent surfaces, where both shapes stay mixed over a whole surface.
std::pair<double, double> both_fraction(const Cut& a, const Cut& b, double r) {
  double lo = std::max(a.lo + b.lo - 1.0, 0.0);
  double hi = std::min(a.hi, b.hi);
  const double along = a.n_B.dot(b.n_B);
  if (along >= 0.0) {
    const double shift = (a.n_B - b.n_B).norm() * r;
    hi = std::min(hi, a.fraction(b.beta_hi + shift, true));
    if (a.beta_lo > -kInf && b.beta_lo > -kInf) {
      lo = std::max(lo, std::min(a.lo, a.fraction(b.beta_lo - shift, false)));
    }
  } else {
    const double shift = (a.n_B + b.n_B).norm() * r;
    hi = std::min(hi, std::max(a.hi - a.fraction(-b.beta_hi - shift, false), 0.0));
    if (a.beta_lo > -kInf && b.beta_lo > -kInf) {
      lo = std::max(lo, a.lo - a.fraction(-b.beta_lo + shift, true));
    }
  }
  return {lo, std::max(hi, lo)};
}

// Moments of a region (or a weighted sum of regions) about a point o: integral dV,
// integral (x - o) dV and integral (x - o)(x - o)^T dV.
struct Moments {
  double volume = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();

  // A box of half extents h about its centre: integral u_i^2 dV = V h_i^2 / 3.
  static Moments box(const Eigen::Vector3d& half) {
    Moments m;
    m.volume = 8.0 * half.prod();
    m.second.diagonal() = (m.volume / 3.0) * half.cwiseAbs2();
    return m;
  }

  void add(const Moments& m, double weight) {
    volume += weight * m.volume;
    first += weight * m.first;
    second += weight * m.second;
  }

  // tr of the second moment about o - a: integral |x - o + a|^2 dV.
  double shifted_trace(const Eigen::Vector3d& a) const {
    return second.trace() + 2.0 * a.dot(first) + volume * a.squaredNorm();
  }

  // The same moments about o - a (x - (o - a) = (x - o) + a).
  Moments shifted(const Eigen::Vector3d& a) const {
    Moments m;
    m.volume = volume;
    m.first = first + volume * a;
    m.second = second + a * first.transpose() + first * a.transpose() + volume * (a * a.transpose());
    return m;
  }
};

// Moments of a union of tetrahedra with a common vertex 0, from sums kept by hand (the hot loop of
// the second moments). For vertices 0, a, b, c: V = a . (b x c) / 6, integral x dV = V (a + b + c)
// / 4, integral x x^T dV = V/20 (a a^T + b b^T + c c^T + (a + b + c)(a + b + c)^T).
class TetrahedronSums {
 public:
  void add(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const double six_v = a.dot(b.cross(c));
    const Eigen::Vector3d s = a + b + c;
    six_volume_ += six_v;
    for (int i = 0; i < 3; ++i) first_[i] += six_v * s[i];
    const auto sum = [&](int i, int j) { return a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]; };
    second_[0] += six_v * sum(0, 0);
    second_[1] += six_v * sum(1, 1);
    second_[2] += six_v * sum(2, 2);
    second_[3] += six_v * sum(0, 1);
    second_[4] += six_v * sum(0, 2);
    second_[5] += six_v * sum(1, 2);
  }

  Moments moments() const {
    Moments m;
    m.volume = six_volume_ / 6.0;
    m.first = Eigen::Vector3d(first_[0], first_[1], first_[2]) / 24.0;
    m.second << second_[0], second_[3], second_[4], second_[3], second_[1], second_[5], second_[4], second_[5],
        second_[2];
    m.second /= 120.0;
    return m;
  }

 private:
  double six_volume_ = 0.0;
  double first_[3] = {0.0, 0.0, 0.0};
  double second_[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};  // xx, yy, zz, xy, xz, yz
};

// A cell's box [-h, h] (about its centre) cut by up to two half-spaces n . u <= beta: a convex
// polyhedron kept as faces, each a set of edges oriented counter-clockwise seen from outside. A
// face needs no vertex order, only its edges, so a cut closes each face it crosses with one edge
// and collects the reversed edges as the new face on the plane.
class ClippedBox {
 public:
  explicit ClippedBox(const Eigen::Vector3d& half) : half_(half) {
    for (int axis = 0; axis < 3; ++axis) {
      const int j = (axis + 1) % 3, k = (axis + 2) % 3;
      for (double side : {-1.0, 1.0}) {
        // Corners counter-clockwise about +e_axis (e_j x e_k = e_axis); reversed on the - side.
        Eigen::Vector3d corners[4];
        const double uj[4] = {-1.0, 1.0, 1.0, -1.0}, uk[4] = {-1.0, -1.0, 1.0, 1.0};
        for (int c = 0; c < 4; ++c) {
          corners[c][axis] = side * half[axis];
          corners[c][j] = uj[c] * half[j];
          corners[c][k] = side * uk[c] * half[k];
        }
        Face& face = faces_[face_count_++];
        for (int c = 0; c < 4; ++c) face.add(corners[c], corners[(c + 1) % 4]);
      }
    }
  }

  // Keeps the part with n . u <= beta. Returns false if a face crossed the plane other than once
  // out and once in (possible only with vertices within rounding of the plane, e.g. the face left
  // by a previous cut on the same plane); the polyhedron is then unusable. Callers cut slightly
  // outside their planes (see leaf_moments) so that vertices of coplanar cuts are clearly inside.
  bool cut(const Eigen::Vector3d& n, double beta) {
    const double reach = n.cwiseAbs().dot(half_);
    if (beta >= reach) return true;
    if (beta < -reach) {
      face_count_ = 0;
      return true;
    }
    bool ok = true;
    // In place: each edge gives at most one, so a face is rewritten behind its reading position.
    Face cap;
    int kept = 0;
    for (int f = 0; f < face_count_; ++f) {
      Face& face = faces_[f];
      Face& out = faces_[kept];
      const int count = face.count;
      int written = 0;
      int exits = 0, entries = 0;
      Eigen::Vector3d exit = Eigen::Vector3d::Zero(), entry = Eigen::Vector3d::Zero();
      for (int e = 0; e < count; ++e) {
        const Eigen::Vector3d a = face.from[e];
        const Eigen::Vector3d b = face.to[e];
        const double da = n.dot(a) - beta, db = n.dot(b) - beta;
        if (da <= 0.0 && db <= 0.0) {
          out.set(written++, a, b);
        } else if (da <= 0.0) {
          exit = a + (da / (da - db)) * (b - a);
          ++exits;
          out.set(written++, a, exit);
        } else if (db <= 0.0) {
          entry = a + (da / (da - db)) * (b - a);
          ++entries;
          out.set(written++, entry, b);
        }
      }
      if (exits != entries || exits > 1) ok = false;
      if (exits == 1 && entries == 1) {
        out.set(written++, exit, entry);
        cap.add(entry, exit);
      }
      out.count = written;
      if (written > 0) ++kept;
    }
    if (cap.count > 0) faces_[kept++] = cap;
    face_count_ = kept;
    return ok;
  }

  // Moments about the box centre: tetrahedra from the centre over a fan of each face (from its
  // first vertex).
  Moments moments() const {
    TetrahedronSums sums;
    for (int f = 0; f < face_count_; ++f) {
      const Face& face = faces_[f];
      for (int e = 1; e < face.count; ++e) sums.add(face.from[0], face.from[e], face.to[e]);
    }
    return sums.moments();
  }

 private:
  // A face gains at most one edge per cut and a cap at most one per face: 6 after two cuts, 8
  // faces.
  static constexpr int kMaxEdges = 8;
  struct Face {
    int count = 0;
    Eigen::Vector3d from[kMaxEdges], to[kMaxEdges];
    void set(int index, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      from[index] = a;
      to[index] = b;
    }
    void add(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { set(count++, a, b); }
  };
  Eigen::Vector3d half_;
  Face faces_[8];
  int face_count_ = 0;
};

struct PosedShape {
  CollisionShape shape;
  Eigen::Isometry3d X_GB;
  Eigen::Matrix3d R_BG;
  Eigen::AlignedBox3d box_B;
};

// A cell of the refinement: an axis-aligned box in B.
struct Cell {
  Eigen::Vector3d center;
  Eigen::Vector3d half;
  std::uint32_t first = 0;  // into the index pool: n_inside shapes containing the cell, then n_mixed
  std::uint32_t n_inside = 0;
  std::uint32_t n_mixed = 0;
  double lo = 0.0, hi = 0.0;  // bounds on the integral of max(count - 1, 0) over the cell [m^3]
  double floor = 0.0;         // max(n_inside - 1, 0) * cell volume [m^3]
  std::uint32_t first_plane = 0;  // into the plane pool: the n_mixed shapes' cuts
};

// A mixed shape's cuts of a cell, n_B . (x - center) <= beta (see Cut).
struct CutPlanes {
  Eigen::Vector3d n_B;
  double beta_lo, beta_hi;
  double lo, hi;  // fractions of the cell below them (bounds, as Cut)
};

bool overlaps_with_volume(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
  return (a.min().array() < b.max().array()).all() && (b.min().array() < a.max().array()).all();
}

// Appends the parts of `p` outside `d` (at most six boxes) to `out`.
void subtract_box(const Eigen::AlignedBox3d& p, const Eigen::AlignedBox3d& d,
                  std::vector<Eigen::AlignedBox3d>* out) {
  if (!overlaps_with_volume(p, d)) {
    out->push_back(p);
    return;
  }
  Eigen::AlignedBox3d rest = p;
  for (int a = 0; a < 3; ++a) {
    if (rest.min()[a] < d.min()[a]) {
      Eigen::AlignedBox3d piece = rest;
      piece.max()[a] = d.min()[a];
      out->push_back(piece);
      rest.min()[a] = d.min()[a];
    }
    if (rest.max()[a] > d.max()[a]) {
      Eigen::AlignedBox3d piece = rest;
      piece.min()[a] = d.max()[a];
      out->push_back(piece);
      rest.max()[a] = d.max()[a];
    }
  }
}

class OverlapIntegrator {
 public:
  // origin: the point the exact cells' second moments are taken about (near the search regions,
  // so the final shift to the centroid does not cancel).
  OverlapIntegrator(std::vector<PosedShape> shapes, double margin, const Eigen::Vector3d& origin)
      : shapes_(std::move(shapes)), margin_(margin), origin_(origin),
        overlapping_(shapes_.size() * shapes_.size(), 0) {}

  std::size_t cells_evaluated() const { return cells_evaluated_; }
  double exact_volume() const { return exact_volume_; }
  const Moments& exact_moments() const { return exact_moments_; }  // about origin
  const CutPlanes* planes(const Cell& cell) const { return &planes_[cell.first_plane]; }
  double slack() const { return slack_; }
  double margin() const { return margin_; }
  const std::vector<Cell>& cells() const { return cells_; }

  // Classifies the cell (center, half) against `candidates` (shapes not known to be outside it),
  // given `inside` (shapes known to contain it). Constant-integrand cells are summed at once and
  // return -1; others are stored and their index returned.
  int classify(const Eigen::Vector3d& center, const Eigen::Vector3d& half, const std::vector<int>& inside,
               const std::vector<int>& candidates) {
    ++cells_evaluated_;
    const double r = half.norm();
    const double volume = 8.0 * half.prod();
    std::vector<int>& now_inside = scratch_inside_;
    now_inside = inside;
    mixed_.clear();
    cuts_.clear();
    for (int index : candidates) {
      const PosedShape& s = shapes_[index];
      const Eigen::Vector3d c_G = s.X_GB * center;
      const SurfaceInfo info = surface_info(s.shape, c_G);
      if (info.phi > r) continue;
      if (info.phi < -r) {
        now_inside.push_back(index);
        continue;
      }
      if (info.phi <= 0.0) {
        // Convex shape: the cell is inside if its 8 corners are. Corners a rounding error outside
        // (within margin_) count as inside; the volume so misattributed is below margin_ times
        // the cell's surface area times sqrt(3).
        const Eigen::Matrix3d axes_G = s.X_GB.linear() * half.asDiagonal();
        double worst = -kInf;
        for (int k = 0; k < 8 && worst <= margin_; ++k) {
          const Eigen::Vector3d corner = c_G + axes_G * Eigen::Vector3d((k & 1) ? 1.0 : -1.0,
                                                                        (k & 2) ? 1.0 : -1.0,
                                                                        (k & 4) ? 1.0 : -1.0);
          worst = std::max(worst, outside_measure(s.shape, corner));
        }
        if (worst <= margin_) {
          if (worst > 0.0) {
            slack_ += std::sqrt(3.0) * margin_ * 8.0 * (half.x() * half.y() + half.y() * half.z() +
                                                         half.z() * half.x());
          }
          now_inside.push_back(index);
          continue;
        }
      }
      // Mixed: the part of the cell inside lies between two plane cuts (see the header).
      Cut cut;
      cut.n_B = s.R_BG * info.n_G;
      const Eigen::Vector3d& n_B = cut.n_B;
      for (int i = 0; i < 3; ++i) cut.m[i] = 2.0 * std::abs(n_B[i]) * half[i];
      cut.beta_hi = -info.phi;
      if (r <= info.flat_cell_limit) {
        cut.beta_lo = cut.beta_hi;
      } else if (info.rho > 0.0 && 2.0 * r <= info.rho && r <= info.rho_cell_limit) {
        // Cell points lie within `lateral` of the normal line through c and at most 2 r deep, so
        // those deeper than rho - sqrt(rho^2 - lateral^2) below the plane are in the ball.
        double along = kInf;  // min over corners of |(x - c) . n|
        for (int k = 0; k < 4; ++k) {
          along = std::min(along, std::abs(half.x() * n_B.x() + ((k & 1) ? 1.0 : -1.0) * half.y() * n_B.y() +
                                            ((k & 2) ? 1.0 : -1.0) * half.z() * n_B.z()));
        }
        const double lateral2 = std::max(r * r - along * along, 0.0);
        cut.beta_lo = cut.beta_hi - lateral2 / (info.rho + std::sqrt(info.rho * info.rho - lateral2));
      }
      cut.hi = cut.fraction(cut.beta_hi, true);
      cut.lo = cut.beta_lo > -kInf ? cut.fraction(cut.beta_lo, false) : 0.0;
      mixed_.push_back(index);
      cuts_.push_back(cut);
    }

    const int k0 = static_cast<int>(now_inside.size());
    const int n_mixed = static_cast<int>(mixed_.size());
    const double f_min = std::max(k0 - 1, 0);
    const double f_max = std::max(k0 + n_mixed - 1, 0);
    // Overlaps shown: two shapes containing the cell; a shape containing it and the certain part
    // of another's cut; two certain cut parts adding to more than the cell.
    for (int i = 0; i < k0; ++i) {
      for (int j = i + 1; j < k0; ++j) mark_overlap(now_inside[i], now_inside[j]);
      for (int j = 0; j < n_mixed; ++j) {
        if (cuts_[j].lo > 0.0) mark_overlap(now_inside[i], mixed_[j]);
      }
    }
    // With nothing inside and two shapes mixed (the common case on an overlap's edge, and the
    // whole surface for coplanar faces or tangent shapes) the integrand is 1_a 1_b.
    std::pair<double, double> both{0.0, 0.0};
    if (k0 == 0 && n_mixed == 2) {
      both = both_fraction(cuts_[0], cuts_[1], r);
      if (both.first > 0.0) mark_overlap(mixed_[0], mixed_[1]);
    }
    for (int i = 0; i < n_mixed; ++i) {
      for (int j = i + 1; j < n_mixed; ++j) {
        if (cuts_[i].lo + cuts_[j].lo > 1.0) mark_overlap(mixed_[i], mixed_[j]);
      }
    }

    if (f_min == f_max) {
      exact_volume_ += f_min * volume;
      if (f_min > 0.0) exact_moments_.add(Moments::box(half).shifted(center - origin_), f_min);
      return -1;
    }
    double sum_lo = 0.0, sum_hi = 0.0, max_lo = 0.0;
    for (int j = 0; j < n_mixed; ++j) {
      sum_lo += cuts_[j].lo;
      sum_hi += cuts_[j].hi;
      max_lo = std::max(max_lo, cuts_[j].lo);
    }
    Cell cell;
    cell.center = center;
    cell.half = half;
    cell.floor = f_min * volume;
    if (k0 >= 1) {  // max(count - 1, 0) = k0 - 1 + sum of the mixed shapes' indicators
      cell.lo = (k0 - 1 + sum_lo) * volume;
      cell.hi = (k0 - 1 + sum_hi) * volume;
    } else if (n_mixed == 2) {
      cell.lo = both.first * volume;
      cell.hi = both.second * volume;
    } else {  // sum 1_m - 1[in any] lies between sum 1_m - 1 and sum 1_m - 1_(any one m)
      cell.lo = std::max(sum_lo - 1.0, 0.0) * volume;
      cell.hi = std::min(f_max, sum_hi - max_lo) * volume;
    }
    cell.hi = std::max(cell.hi, cell.lo);
    cell.first = static_cast<std::uint32_t>(pool_.size());
    cell.n_inside = static_cast<std::uint32_t>(k0);
    cell.n_mixed = static_cast<std::uint32_t>(n_mixed);
    cell.first_plane = static_cast<std::uint32_t>(planes_.size());
    for (const Cut& cut : cuts_) planes_.push_back({cut.n_B, cut.beta_lo, cut.beta_hi, cut.lo, cut.hi});
    pool_.insert(pool_.end(), now_inside.begin(), now_inside.end());
    pool_.insert(pool_.end(), mixed_.begin(), mixed_.end());
    cells_.push_back(cell);
    return static_cast<int>(cells_.size()) - 1;
  }

  // Children of cell `index`: each axis at least half as long as the longest is halved.
  template <typename Visit>
  void for_each_child(int index, Visit visit) {
    const Cell parent = cells_[index];
    // Copies: classify() appends to pool_.
    const auto lists = pool_.begin() + parent.first;
    parent_inside_.assign(lists, lists + parent.n_inside);
    parent_candidates_.assign(lists + parent.n_inside, lists + parent.n_inside + parent.n_mixed);
    const double longest = parent.half.maxCoeff();
    bool split[3];
    Eigen::Vector3d half = parent.half;
    for (int a = 0; a < 3; ++a) {
      split[a] = parent.half[a] >= 0.5 * longest;
      if (split[a]) half[a] *= 0.5;
    }
    for (int k = 0; k < 8; ++k) {
      Eigen::Vector3d center = parent.center;
      bool valid = true;
      for (int a = 0; a < 3; ++a) {
        const bool upper = (k >> a) & 1;
        if (!split[a]) {
          valid = valid && !upper;
        } else {
          center[a] += upper ? half[a] : -half[a];
        }
      }
      if (valid) visit(classify(center, half, parent_inside_, parent_candidates_));
    }
  }

  static int child_count(const Cell& cell) {
    const double longest = cell.half.maxCoeff();
    int n = 1;
    for (int a = 0; a < 3; ++a) {
      if (cell.half[a] >= 0.5 * longest) n *= 2;
    }
    return n;
  }

  std::vector<std::pair<int, int>> overlapping_pairs() const {
    std::vector<std::pair<int, int>> pairs;
    const int n = static_cast<int>(shapes_.size());
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        if (overlapping_[i * n + j]) pairs.emplace_back(i, j);
      }
    }
    return pairs;
  }

 private:
  void mark_overlap(int a, int b) {
    const std::size_t n = shapes_.size();
    overlapping_[std::min(a, b) * n + std::max(a, b)] = 1;
  }

  std::vector<PosedShape> shapes_;
  double margin_;
  Eigen::Vector3d origin_;
  std::vector<char> overlapping_;
  std::vector<Cell> cells_;
  std::vector<int> pool_;
  std::size_t cells_evaluated_ = 0;
  double exact_volume_ = 0.0;
  Moments exact_moments_;  // about origin_
  std::vector<CutPlanes> planes_;
  double slack_ = 0.0;
  std::vector<int> scratch_inside_, mixed_, parent_inside_, parent_candidates_;
  std::vector<Cut> cuts_;
};

// Moments about the box centre of the part of the box [-h, h] with n . u <= beta (|n| = 1):
// tetrahedra from a point q on the plane over a fan of each box face clipped to the half-space
// (the face on the plane adds none). With more than four corners kept, the box less the other
// side, which has fewer tetrahedra. One cut; ClippedBox does several. The hot loop of the moments,
// so it keeps sums by hand (corner k has signs (k & 1, k & 2, k & 4) on x, y, z).
Moments half_space_moments(const Eigen::Vector3d& half, const Eigen::Vector3d& n, double beta) {
  const Eigen::Vector3d along = n.cwiseProduct(half);
  const double reach = along.cwiseAbs().sum();
  if (beta >= reach) return Moments::box(half);
  if (beta <= -reach) return Moments();
  // Faces counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
  static constexpr int kFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  const Eigen::Vector3d q = beta * n;
  Eigen::Vector3d corner[8];
  double d[8];
  int below = 0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d sign((k & 1) ? 1.0 : -1.0, (k & 2) ? 1.0 : -1.0, (k & 4) ? 1.0 : -1.0);
    corner[k] = sign.cwiseProduct(half) - q;
    d[k] = sign.dot(along) - beta;
    if (d[k] <= 0.0) ++below;
  }
  const bool complement = below > 4;  // integrate the side d >= 0 instead
  if (complement) {
    for (double& dk : d) dk = -dk;
  }
  TetrahedronSums sums;  // about q
  for (const auto& face : kFaces) {
    Eigen::Vector3d kept[8];  // the face clipped to d <= 0 (Sutherland-Hodgman)
    int count = 0;
    for (int c = 0; c < 4; ++c) {
      const int a = face[c], b = face[(c + 1) % 4];
      if (d[a] <= 0.0) kept[count++] = corner[a];
      if ((d[a] <= 0.0) != (d[b] <= 0.0)) {
        kept[count++] = corner[a] + (d[a] / (d[a] - d[b])) * (corner[b] - corner[a]);
      }
    }
    for (int t = 1; t + 1 < count; ++t) sums.add(kept[0], kept[t], kept[t + 1]);
  }
  const Moments part = sums.moments().shifted(q);
  if (!complement) return part;
  Moments rest = Moments::box(half);
  rest.add(part, -1.0);
  return rest;
}

// Estimates the moments (about the cell centre) of a leaf's integrand f = max(count - 1, 0) by
// those of a function f_est built from the mixed shapes' cut planes, and adds to *envelope the
// moments of a function g >= |f - f_est| (pointwise). Each mixed shape's part S of the cell lies
// between its cuts, L <= S <= U (L the lower cut, U the upper; L = U for a flat cut), so:
//   a shape contains the cell: f = (n_inside - 1) + sum over the mixed shapes of 1_S, each 1_S
//     estimated by 1_U for a flat cut (g = 0), (1_L + 1_U) / 2 otherwise (g = (1_U - 1_L) / 2, with
//     L empty where no lower cut is known);
//   nothing inside, two mixed: f = 1_Sa 1_Sb, between 1_La 1_Lb and 1_Ua 1_Ub (clipped boxes),
//     estimated by their mean (g = half their difference);
//   otherwise (nothing inside, three or more mixed) returns false, as it does if a clip failed.
// The clips cut outside the planes, a's by `offset` and b's by twice that (rounding: where the faces
// of two shapes are coplanar, the vertices the first cut leaves on its plane are then clearly inside
// the second); the volume that may move is added to *slack.
bool leaf_moments(const Cell& cell, const CutPlanes* planes, double offset, Moments* estimate, Moments* envelope,
                  double* slack) {
  *estimate = Moments();
  if (cell.n_inside >= 1) {
    estimate->add(Moments::box(cell.half), cell.n_inside - 1.0);
    for (std::uint32_t j = 0; j < cell.n_mixed; ++j) {
      const CutPlanes& cut = planes[j];
      const Moments upper = half_space_moments(cell.half, cut.n_B, cut.beta_hi);
      if (cut.beta_lo == cut.beta_hi) {
        estimate->add(upper, 1.0);
        continue;
      }
      estimate->add(upper, 0.5);
      envelope->add(upper, 0.5);
      if (cut.beta_lo > -kInf) {
        const Moments lower = half_space_moments(cell.half, cut.n_B, cut.beta_lo);
        estimate->add(lower, 0.5);
        envelope->add(lower, -0.5);
      }
    }
    return true;
  }
  if (cell.n_mixed != 2) return false;
  const CutPlanes& a = planes[0];
  const CutPlanes& b = planes[1];
  ClippedBox upper_cut(cell.half);
  bool ok = upper_cut.cut(a.n_B, a.beta_hi + offset);
  ok = upper_cut.cut(b.n_B, b.beta_hi + 2.0 * offset) && ok;
  const Moments upper = upper_cut.moments();
  Moments lower;
  if (a.beta_lo == a.beta_hi && b.beta_lo == b.beta_hi) {
    lower = upper;
  } else if (a.beta_lo > -kInf && b.beta_lo > -kInf) {
    ClippedBox lower_cut(cell.half);
    ok = lower_cut.cut(a.n_B, a.beta_lo + offset) && ok;
    ok = lower_cut.cut(b.n_B, b.beta_lo + 2.0 * offset) && ok;
    lower = lower_cut.moments();
  }
  if (!ok) return false;
  estimate->add(upper, 0.5);
  estimate->add(lower, 0.5);
  envelope->add(upper, 0.5);
  envelope->add(lower, -0.5);
  // A plane cuts the cell in at most sqrt(3) times its largest face (projected along the normal's
  // largest component); the clips' planes moved by 6 offsets in all.
  const Eigen::Vector3d& h = cell.half;
  *slack += 6.0 * offset * 4.0 * std::sqrt(3.0) * std::max({h.x() * h.y(), h.y() * h.z(), h.z() * h.x()});
  return true;
}

}  // namespace

bool contains(const CollisionShape& shape, const Eigen::Isometry3d& X_BG, const Eigen::Vector3d& p_B) {
  return outside_measure(shape, X_BG.inverse() * p_B) <= 0.0;
}

double signed_distance(const CollisionShape& shape, const Eigen::Isometry3d& X_BG,
                       const Eigen::Vector3d& p_B) {
  return surface_info(shape, X_BG.inverse() * p_B).phi;
}

Eigen::AlignedBox3d bounding_box(const CollisionShape& shape, const Eigen::Isometry3d& X_BG) {
  const Eigen::Matrix3d R = X_BG.linear();
  const double half_length = 0.5 * shape.length;
  Eigen::Vector3d extent = Eigen::Vector3d::Zero();
  switch (shape.type) {
    case CollisionShapeType::kBox:
      extent = R.cwiseAbs() * (0.5 * shape.box_size);
      break;
    case CollisionShapeType::kSphere:
      extent.setConstant(shape.radius);
      break;
    case CollisionShapeType::kCylinder:
      // The cap disc (normal z_G) reaches radius * sqrt(1 - (e_i . z_G)^2) along B's axis i.
      for (int i = 0; i < 3; ++i) {
        extent[i] = half_length * std::abs(R(i, 2)) +
                    shape.radius * std::sqrt(std::max(0.0, 1.0 - R(i, 2) * R(i, 2)));
      }
      break;
    case CollisionShapeType::kCapsule:
      extent = half_length * R.col(2).cwiseAbs() + Eigen::Vector3d::Constant(shape.radius);
      break;
  }
  const Eigen::Vector3d p_BG = X_BG.translation();
  return Eigen::AlignedBox3d(p_BG - extent, p_BG + extent);
}

OverlapExcess overlap_excess(const std::vector<std::pair<CollisionShape, Eigen::Isometry3d>>& shapes_B,
                             const OverlapExcessOptions& options) {
  OverlapExcess result;
  const int n = static_cast<int>(shapes_B.size());
  std::vector<PosedShape> posed;
  posed.reserve(n);
  double scale = 0.0;
  for (const auto& [shape, X_BG] : shapes_B) {
    PosedShape p{shape, X_BG.inverse(), X_BG.linear(), bounding_box(shape, X_BG)};
    scale = std::max({scale, p.box_B.min().cwiseAbs().maxCoeff(), p.box_B.max().cwiseAbs().maxCoeff()});
    posed.push_back(std::move(p));
  }

  // Regions where two shapes may overlap: pairwise bounding-box intersections, made disjoint.
  std::vector<Eigen::AlignedBox3d> regions;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (!overlaps_with_volume(posed[i].box_B, posed[j].box_B)) continue;
      std::vector<Eigen::AlignedBox3d> pieces{posed[i].box_B.intersection(posed[j].box_B)};
      for (const Eigen::AlignedBox3d& taken : regions) {
        std::vector<Eigen::AlignedBox3d> rest;
        for (const Eigen::AlignedBox3d& piece : pieces) subtract_box(piece, taken, &rest);
        pieces.swap(rest);
      }
      regions.insert(regions.end(), pieces.begin(), pieces.end());
    }
  }
  if (regions.empty()) return result;

  Eigen::AlignedBox3d all_regions;
  for (const Eigen::AlignedBox3d& region : regions) all_regions.extend(region);
  const double diameter = all_regions.diagonal().norm();

  // Rounding allowance for corner tests (transforming a corner rounds a few ulps of the largest
  // coordinate): without it a region that is exactly a box face to face with the cells would be
  // refined along all its faces instead of taken whole.
  OverlapIntegrator integrator(posed, 32 * std::numeric_limits<double>::epsilon() * scale,
                               all_regions.center());
  using Entry = std::pair<double, int>;  // (hi - lo, cell index); widest first
  std::priority_queue<Entry> queue;
  double active_estimate = 0.0, active_width = 0.0;
  auto add = [&](int index) {
    if (index < 0) return;
    const Cell& cell = integrator.cells()[index];
    queue.emplace(cell.hi - cell.lo, index);
    active_estimate += 0.5 * (cell.lo + cell.hi);
    active_width += 0.5 * (cell.hi - cell.lo);
  };
  for (const Eigen::AlignedBox3d& region : regions) {
    std::vector<int> candidates;
    for (int i = 0; i < n; ++i) {
      if (overlaps_with_volume(posed[i].box_B, region)) candidates.push_back(i);
    }
    add(integrator.classify(region.center(), 0.5 * region.sizes(), {}, candidates));
  }

  while (!queue.empty()) {
    const double estimate = integrator.exact_volume() + active_estimate;
    const double bound = active_width + integrator.slack();
    if (bound <= std::max(options.relative_tolerance * estimate, options.absolute_tolerance)) break;
    const int index = queue.top().second;
    const Cell& cell = integrator.cells()[index];
    if (integrator.cells_evaluated() + OverlapIntegrator::child_count(cell) > options.max_cells) {
      result.converged = false;
      break;
    }
    queue.pop();
    active_estimate -= 0.5 * (cell.lo + cell.hi);
    active_width -= 0.5 * (cell.hi - cell.lo);
    integrator.for_each_child(index, add);
  }

  // Final sums over the leaves, recomputed (the running sums drift).
  std::vector<int> leaves;
  leaves.reserve(queue.size());
  for (; !queue.empty(); queue.pop()) leaves.push_back(queue.top().second);
  double volume = integrator.exact_volume();
  double width = integrator.slack();
  for (int index : leaves) {
    const Cell& cell = integrator.cells()[index];
    const double estimate = 0.5 * (cell.lo + cell.hi);
    volume += estimate;
    width += 0.5 * (cell.hi - cell.lo);
  }
  result.volume = volume;
  result.volume_error_bound = width;
  result.cells_evaluated = integrator.cells_evaluated();
  result.overlapping_pairs = integrator.overlapping_pairs();

  // Centroid and second moment from the leaves' estimated integrands f_est (derivation in the
  // header): raw moments about o, shifted to p = centroid_B at the end. The envelope G >= |f - f_est|
  // gathers the leaves' error functions; the few leaves spread evenly are bounded on their own.
  // While volume is 0 every leaf has hi = 0, and only the corner tests' slack remains.
  const Eigen::Vector3d o = all_regions.center();
  Moments sum = integrator.exact_moments();  // about o
  Moments envelope;                          // about o
  double slack = integrator.slack();
  std::vector<int> spread;
  if (volume > 0.0) {
    for (int index : leaves) {
      const Cell& cell = integrator.cells()[index];
      Moments estimate, error;
      if (leaf_moments(cell, integrator.planes(cell), integrator.margin(), &estimate, &error, &slack)) {
        envelope.add(error.shifted(cell.center - o), 1.0);
      } else {
        estimate = Moments::box(cell.half);
        estimate.volume = 0.5 * (cell.lo + cell.hi);
        estimate.second *= estimate.volume / (8.0 * cell.half.prod());
        spread.push_back(index);
      }
      sum.add(estimate.shifted(cell.center - o), 1.0);
    }
  }
  double first_moment_bound = slack * diameter;
  double second_moment_bound = slack * diameter * diameter;
  if (volume > 0.0 && sum.volume > 0.0) {
    const Eigen::Vector3d p = o + sum.first / sum.volume;
    result.centroid_B = p;
    // The estimate's error about p: |integral (f - f_est)(x - p)| <= integral G |x - p|
    // <= sqrt(integral G * integral G |x - p|^2) (Cauchy-Schwarz), and |integral (f - f_est)
    // (x - p)(x - p)^T|_F <= integral G |x - p|^2.
    const double envelope_trace = std::max(envelope.shifted_trace(o - p), 0.0);
    first_moment_bound += std::sqrt(std::max(envelope.volume, 0.0) * envelope_trace);
    second_moment_bound += envelope_trace;
    for (int index : spread) {
      // f_est = w / V: with f = f_min + f' (f' >= 0, integral F' <= hi - floor), a = c - p,
      // u = x - c, the first moment's error is (F - w) a + integral f' u; the second moment's is in
      // the header.
      const Cell& cell = integrator.cells()[index];
      const double a = (cell.center - p).norm();
      const double r = cell.half.norm();
      const double d = cell.half.cwiseAbs2().norm();  // |diag(h_i^2)|_F
      first_moment_bound += 0.5 * (cell.hi - cell.lo) * a + (cell.hi - cell.floor) * r;
      second_moment_bound += 0.5 * (cell.hi - cell.lo) * (a * a + d / 3.0) +
                             (cell.hi - cell.floor) * (2.0 * a * r + std::sqrt(r * r * r * r + d * d / 9.0));
    }
    const Eigen::Matrix3d second = sum.shifted(o - p).second;
    result.second_moment_B = 0.5 * (second + second.transpose());  // symmetric to the last bit
  } else if (volume > 0.0) {  // the clips found nothing where the fractions did (rounding)
    first_moment_bound = second_moment_bound = kInf;
  }
  // |p_true - p| = |integral (f - f_est)(x - p)| / E_true, as integral f_est (x - p) = 0.
  result.centroid_error_bound = volume > width ? first_moment_bound / (volume - width) : kInf;
  result.second_moment_error_bound = second_moment_bound;
  return result;
}

}  // namespace hadal::geometry
