#include "hadal/geometry/seabed_height.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hadal::geometry {

namespace {

constexpr double kMinUpwardNormal = 1e-6;  // |n_z| below this: a wall seen edge-on, no height
// Cells per triangle: a height field has two triangles per grid cell, so one bin per two triangles
// keeps a sample's candidate list at a few triangles. At most 4M cells (16 MB of CSR starts).
constexpr double kCellsPerTriangle = 0.5;
constexpr double kMaxCells = 4.0e6;

}  // namespace

SeabedHeight SeabedHeight::plane(double height_W) {
  SeabedHeight out;
  out.is_plane_ = true;
  out.plane_z_ = height_W;
  return out;
}

SeabedHeight::SeabedHeight(const TriangleMesh& mesh, bool height_field) : height_field_(height_field) {
  const std::size_t nt = mesh.num_triangles();
  const std::size_t nv = mesh.num_vertices();
  Eigen::AlignedBox2d bounds;
  vertices_.reserve(9 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    double v[9];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t index = mesh.indices[3 * t + k];
      if (index >= nv) throw std::invalid_argument("SeabedHeight: vertex index out of range");
      for (int c = 0; c < 3; ++c) v[3 * k + c] = mesh.positions[3 * index + c];
    }
    const Eigen::Vector3d a(v[0], v[1], v[2]), b(v[3], v[4], v[5]), c(v[6], v[7], v[8]);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double length = n.norm();
    if (!(length > 0.0) || std::abs(n.z()) < kMinUpwardNormal * length) continue;
    vertices_.insert(vertices_.end(), v, v + 9);
    for (int k = 0; k < 3; ++k) bounds.extend(Eigen::Vector2d(v[3 * k], v[3 * k + 1]));
  }
  const std::size_t count = vertices_.size() / 9;
  if (count == 0) return;
  const Eigen::Vector2d size = bounds.sizes().cwiseMax(1e-9);
  const double cells = std::clamp(kCellsPerTriangle * static_cast<double>(count), 1.0, kMaxCells);
  nx_ = std::max(1, static_cast<int>(std::ceil(std::sqrt(cells * size.x() / size.y()))));
  ny_ = std::max(1, static_cast<int>(std::ceil(cells / nx_)));
  x0_ = bounds.min().x();
  y0_ = bounds.min().y();
  cell_x_ = size.x() / nx_;
  cell_y_ = size.y() / ny_;
  const auto cell_range = [&](std::size_t t, int* i0, int* i1, int* j0, int* j1) {
    const double* v = &vertices_[9 * t];
    const double lo_x = std::min({v[0], v[3], v[6]}), hi_x = std::max({v[0], v[3], v[6]});
    const double lo_y = std::min({v[1], v[4], v[7]}), hi_y = std::max({v[1], v[4], v[7]});
    *i0 = std::clamp(static_cast<int>(std::floor((lo_x - x0_) / cell_x_)), 0, nx_ - 1);
    *i1 = std::clamp(static_cast<int>(std::floor((hi_x - x0_) / cell_x_)), 0, nx_ - 1);
    *j0 = std::clamp(static_cast<int>(std::floor((lo_y - y0_) / cell_y_)), 0, ny_ - 1);
    *j1 = std::clamp(static_cast<int>(std::floor((hi_y - y0_) / cell_y_)), 0, ny_ - 1);
  };
  const std::size_t num_cells = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  cell_start_.assign(num_cells + 1, 0);
  cell_max_z_.assign(num_cells, -std::numeric_limits<float>::infinity());
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::uint32_t> fill;
    if (pass == 1) {
      for (std::size_t k = 0; k < num_cells; ++k) cell_start_[k + 1] += cell_start_[k];
      cell_triangles_.resize(cell_start_.back());
      fill.assign(cell_start_.begin(), cell_start_.end() - 1);
    }
    for (std::size_t t = 0; t < count; ++t) {
      int i0, i1, j0, j1;
      cell_range(t, &i0, &i1, &j0, &j1);
      const double* v = &vertices_[9 * t];
      const float top = static_cast<float>(std::max({v[2], v[5], v[8]}));
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          const std::size_t cell = static_cast<std::size_t>(j) * nx_ + i;
          if (pass == 0) {
            ++cell_start_[cell + 1];
            cell_max_z_[cell] = std::max(cell_max_z_[cell], top);
          } else {
            cell_triangles_[fill[cell]++] = static_cast<std::uint32_t>(t);
          }
        }
      }
    }
  }
}

namespace {

// (x, y) in triangle v's xy projection (inclusive edges, a few ulp of slack so that a point on a shared
// edge finds a triangle): its height there and its upward unit normal.
bool height_in_triangle(const double* v, double x, double y, double* height, Eigen::Vector3d* normal) {
  const double e1x = v[3] - v[0], e1y = v[4] - v[1], e2x = v[6] - v[0], e2y = v[7] - v[1];
  const double det = e1x * e2y - e1y * e2x;
  const double px = x - v[0], py = y - v[1];
  const double s = (px * e2y - py * e2x) / det, t = (e1x * py - e1y * px) / det;
  constexpr double kSlack = 1e-12;
  if (!(s >= -kSlack && t >= -kSlack && s + t <= 1.0 + kSlack)) return false;
  *height = v[2] + s * (v[5] - v[2]) + t * (v[8] - v[2]);
  if (normal) {
    Eigen::Vector3d n = Eigen::Vector3d(e1x, e1y, v[5] - v[2]).cross(Eigen::Vector3d(e2x, e2y, v[8] - v[2]));
    if (n.z() < 0.0) n = -n;
    *normal = n.normalized();
  }
  return true;
}

}  // namespace

bool SeabedHeight::sample(double x, double y, Sample* out, std::uint32_t* hint) const {
  if (is_plane_) {
    out->height = plane_z_;
    out->normal_W = Eigen::Vector3d::UnitZ();
    return true;
  }
  if (nx_ == 0) return false;
  // On a height field the triangle over the point is the only one: the hint's, if it still holds it.
  if (height_field_ && hint && *hint != kNoHint &&
      height_in_triangle(&vertices_[9 * static_cast<std::size_t>(*hint)], x, y, &out->height, &out->normal_W)) {
    return true;
  }
  const double fx = (x - x0_) / cell_x_, fy = (y - y0_) / cell_y_;
  // The last row and column of cells are closed on their far side (the mesh's edge belongs to it).
  if (!(fx >= 0.0 && fx <= nx_ && fy >= 0.0 && fy <= ny_)) return false;
  const int i = std::min(static_cast<int>(fx), nx_ - 1), j = std::min(static_cast<int>(fy), ny_ - 1);
  const std::size_t cell = static_cast<std::size_t>(j) * nx_ + i;
  bool found = false;
  for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
    const double* v = &vertices_[9 * cell_triangles_[k]];
    double h = 0.0;
    if (!height_in_triangle(v, x, y, &h, nullptr) || (found && h <= out->height)) continue;
    height_in_triangle(v, x, y, &out->height, &out->normal_W);
    if (hint) *hint = cell_triangles_[k];
    found = true;
    if (height_field_) break;
  }
  return found;
}

double SeabedHeight::max_height_in(const Eigen::AlignedBox2d& region) const {
  if (is_plane_) return plane_z_;
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  if (nx_ == 0 || region.isEmpty()) return kNone;
  const double lo_x = (region.min().x() - x0_) / cell_x_, hi_x = (region.max().x() - x0_) / cell_x_;
  const double lo_y = (region.min().y() - y0_) / cell_y_, hi_y = (region.max().y() - y0_) / cell_y_;
  if (hi_x < 0.0 || lo_x > nx_ || hi_y < 0.0 || lo_y > ny_) return kNone;
  const int i0 = std::clamp(static_cast<int>(std::floor(lo_x)), 0, nx_ - 1);
  const int i1 = std::clamp(static_cast<int>(std::floor(hi_x)), 0, nx_ - 1);
  const int j0 = std::clamp(static_cast<int>(std::floor(lo_y)), 0, ny_ - 1);
  const int j1 = std::clamp(static_cast<int>(std::floor(hi_y)), 0, ny_ - 1);
  double top = kNone;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) top = std::max(top, static_cast<double>(cell_max_z_[static_cast<std::size_t>(j) * nx_ + i]));
  }
  return top;
}

}  // namespace hadal::geometry
