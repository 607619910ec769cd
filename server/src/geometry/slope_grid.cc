#include "hadal/geometry/slope_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hadal::geometry {
namespace {

// x rounded up to a float (an upper bound stays an upper bound).
float round_up(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

}  // namespace

SlopeGrid::SlopeGrid(const TriangleMesh& mesh_W) {
  const std::size_t triangles = mesh_W.num_triangles();
  const auto vertex = [&](std::size_t t, int k) {
    const std::size_t v = mesh_W.indices[3 * t + static_cast<std::size_t>(k)];
    return Eigen::Vector3d(mesh_W.positions[3 * v], mesh_W.positions[3 * v + 1], mesh_W.positions[3 * v + 2]);
  };
  for (std::size_t t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) bounds_.extend(vertex(t, k).head<2>());
  }
  std::vector<float> finest(static_cast<std::size_t>(kCells) * kCells, 0.0f);
  if (!bounds_.isEmpty()) {
    cell_x_ = std::max(bounds_.sizes().x() / kCells, 1e-9);
    cell_y_ = std::max(bounds_.sizes().y() / kCells, 1e-9);
    for (std::size_t t = 0; t < triangles; ++t) {
      const Eigen::Vector3d a = vertex(t, 0), b = vertex(t, 1), c = vertex(t, 2);
      const Eigen::Vector3d n = (b - a).cross(c - a);
      if (n.squaredNorm() == 0.0 || !(n.z() > 0.0)) continue;  // degenerate (a caller checks facing up)
      const float slope = round_up(std::hypot(n.x(), n.y()) / n.z());
      Eigen::AlignedBox2d box;
      box.extend(a.head<2>()).extend(b.head<2>()).extend(c.head<2>());
      // Every cell the triangle's xy box meets (cells are closed on both sides: a box on a boundary
      // marks both neighbours).
      const auto cell = [&](double x, double origin, double size) {
        return std::clamp(static_cast<int>(std::floor((x - origin) / size)), 0, kCells - 1);
      };
      const int i0 = cell(box.min().x(), bounds_.min().x(), cell_x_), i1 = cell(box.max().x(), bounds_.min().x(), cell_x_);
      const int j0 = cell(box.min().y(), bounds_.min().y(), cell_y_), j1 = cell(box.max().y(), bounds_.min().y(), cell_y_);
      for (int j = std::max(0, j0 - 1); j <= std::min(kCells - 1, j1 + 1); ++j) {
        for (int i = std::max(0, i0 - 1); i <= std::min(kCells - 1, i1 + 1); ++i) {
          // Neighbours too: a box ending exactly on a cell edge may round into the next cell.
          float& m = finest[static_cast<std::size_t>(j) * kCells + static_cast<std::size_t>(i)];
          m = std::max(m, slope);
        }
      }
    }
  }
  levels_.push_back(std::move(finest));
  for (int size = kCells / 2; size >= 1; size /= 2) {
    const std::vector<float>& fine = levels_.back();
    std::vector<float> coarse(static_cast<std::size_t>(size) * size);
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) {
        const auto at = [&](int x, int y) { return fine[static_cast<std::size_t>(y) * (2 * size) + static_cast<std::size_t>(x)]; };
        coarse[static_cast<std::size_t>(j) * size + static_cast<std::size_t>(i)] =
            std::max(std::max(at(2 * i, 2 * j), at(2 * i + 1, 2 * j)), std::max(at(2 * i, 2 * j + 1), at(2 * i + 1, 2 * j + 1)));
      }
    }
    levels_.push_back(std::move(coarse));
  }
}

double SlopeGrid::max_slope_in(const Eigen::AlignedBox2d& region_xy) const {
  if (region_xy.isEmpty() || bounds_.isEmpty() || levels_.empty()) return 0.0;
  // The region, padded by one finest cell, in finest-cell indices clamped to the grid; nothing if it
  // lies wholly outside the (padded) grid.
  const double fx0 = (region_xy.min().x() - bounds_.min().x()) / cell_x_ - 1.0;
  const double fx1 = (region_xy.max().x() - bounds_.min().x()) / cell_x_ + 1.0;
  const double fy0 = (region_xy.min().y() - bounds_.min().y()) / cell_y_ - 1.0;
  const double fy1 = (region_xy.max().y() - bounds_.min().y()) / cell_y_ + 1.0;
  if (!(fx1 >= 0.0 && fy1 >= 0.0 && fx0 < kCells && fy0 < kCells)) {
    // Outside, or NaN: outside is slope 0; a NaN region is answered by the whole grid.
    return std::isnan(fx0 + fx1 + fy0 + fy1) ? max_slope() : 0.0;
  }
  const int i0 = static_cast<int>(std::max(0.0, std::floor(fx0)));
  const int i1 = static_cast<int>(std::min(kCells - 1.0, std::floor(fx1)));
  const int j0 = static_cast<int>(std::max(0.0, std::floor(fy0)));
  const int j1 = static_cast<int>(std::min(kCells - 1.0, std::floor(fy1)));
  // The level where the region spans at most two cells per axis (then at most 3 x 3 cells to read).
  std::size_t level = 0;
  while (level + 1 < levels_.size() && (((i1 >> level) - (i0 >> level)) > 1 || ((j1 >> level) - (j0 >> level)) > 1)) ++level;
  const int size = kCells >> level;
  const std::vector<float>& cells = levels_[level];
  float slope = 0.0f;
  for (int j = j0 >> level; j <= (j1 >> level); ++j) {
    for (int i = i0 >> level; i <= (i1 >> level); ++i) {
      slope = std::max(slope, cells[static_cast<std::size_t>(j) * static_cast<std::size_t>(size) + static_cast<std::size_t>(i)]);
    }
  }
  return slope;
}

}  // namespace hadal::geometry
