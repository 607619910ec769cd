// The steepest slope of a height field over a region of the plane (docs/ARCHITECTURE.md, "Cameras":
// shadow rays proved clear). A height field z = h(x, y) made of triangles has, over any region R of the
// xy plane, a steepest slope L(R) = max |grad h| over the triangles whose xy extent meets R; along any
// straight path inside R, |h(q) - h(p)| <= L(R) |q - p|_xy. A camera's shadow rays from the seabed to
// lights a few metres away need only the slope of the ground between them, not of the whole terrain
// (the default scenario's plain slopes 1 deg; its ridges 400 m away, 40 deg).
//
// Grid: kCells x kCells cells over the triangles' xy bounding box; each cell holds the largest slope of
// the triangles whose xy bounding box meets it, and a pyramid of coarser grids holds the maximum of each
// 2 x 2 block. max_slope_in(region) reads at most 3 x 3 cells of the level where the region spans at most
// two cells, so it answers in constant time with an upper bound of L(region) (the cells cover the
// region, maybe more of the plane). Outside the grid there is no triangle: slope 0.
#pragma once

#include <Eigen/Geometry>

#include <vector>

#include "hadal/geometry/triangle_mesh.h"

namespace hadal::geometry {

class SlopeGrid {
 public:
  static constexpr int kCells = 256;  // per axis at the finest level

  SlopeGrid() = default;
  // From a height field's triangles (each facing up; degenerate ones have no slope). Empty mesh: every
  // region has slope 0.
  explicit SlopeGrid(const TriangleMesh& mesh_W);

  // The steepest slope |grad h| over every triangle anywhere.
  double max_slope() const { return levels_.empty() ? 0.0 : levels_.back().front(); }
  // An upper bound of the steepest slope over the triangles whose xy extent meets `region_xy` [m]
  // (header). An empty region gives 0.
  double max_slope_in(const Eigen::AlignedBox2d& region_xy) const;

 private:
  Eigen::AlignedBox2d bounds_;     // the triangles' xy bounding box
  double cell_x_ = 1.0, cell_y_ = 1.0;  // finest cell size [m]
  // levels_[k]: (kCells >> k)^2 maxima, row-major by y then x, each rounded up to float; the last
  // level is one cell.
  std::vector<std::vector<float>> levels_;
};

}  // namespace hadal::geometry
