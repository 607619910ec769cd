// One frame's backscatter from a table instead of an integral per pixel (docs/ARCHITECTURE.md,
// "Cameras"). backscatter_radiance() (render/optics.h) costs ~100 samples x lights per pixel, 97 % of a
// 640x480 frame's time; the backscatter seen along a ray changes slowly with the ray's direction (a
// light's beam edge spans tens of pixels), so it is integrated exactly on a coarse grid of pixels and
// interpolated between them.
//
// Table: nodes at every grid_px-th pixel column and row of the image, plus its last column and row;
// per node the ray through that pixel's centre from the camera's origin, and the cumulative integral
// of backscatter_radiance's integrand from s0 to the end of each interval of one geometric grid of
// `samples` intervals on [s0, s_max] (the midpoint rule in log s, backscatter_radiance's rule).
// Lookup at(u, v, s_end): the cumulative integral at s_end, linear in log s inside an interval, then
// bilinear between the four nodes around pixel (u, v). Accuracy against backscatter_radiance per pixel
// is tested (backscatter_table_test.cc).
//
// Work: nodes x samples x lights evaluations (grid 8 px on 640x480: 4 941 nodes), split into rows of
// nodes, each a task for a parallel loop; rows are independent, so the table does not depend on how
// many threads build it.
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "hadal/core/parallel_for.h"
#include "hadal/render/lens.h"
#include "hadal/render/optics.h"

namespace hadal::render {


class BackscatterTable {
 public:
  // Throws std::invalid_argument unless 0 < s0 < s_max (finite), samples >= 1, grid_px >= 1. Empty (at()
  // returns zero) without lights or without scattering.
  BackscatterTable(const WaterOptics& water, const std::vector<SpotLight>& lights, const Lens& lens,
                   const Eigen::Isometry3d& X_WC, double s0, double s_max, int samples, int grid_px,
                   const ParallelFor& parallel = serial_for);

  // Backscatter radiance [W/(m^2 sr)] along pixel (u, v)'s ray from s0 to s_end (clamped to [s0, s_max]).
  Rgb at(int u, int v, double s_end) const;
  // at(u, v, s_end[u]) for every pixel u of image row v added to r[u], g[u], b[u], in single precision
  // (the log by fast::log: within ~1e-6 of at()); pixels with s_end[u] <= s0 get nothing.
  void add_row(int v, const float* s_end, float* r, float* g, float* b) const;

  std::size_t nodes() const { return node_u_.size() * node_v_.size(); }

 private:
  // Node index below pixel coordinate x in a node list, and the weight of the node after it.
  void locate(const std::vector<int>& nodes, int x, std::size_t* below, double* weight) const;
  // A node's cumulative integral at position f in interval k of the s grid.
  Rgb cumulative(std::size_t node, std::size_t k, double f) const;
  // Index in cumulative_ of a node's R at the end of interval k - 1 (k = 0: s0, where it is 0).
  std::size_t entry(std::size_t node, std::size_t k) const { return 3 * (k * nodes() + node); }

  std::vector<int> node_u_, node_v_;  // pixel columns and rows of the nodes
  std::vector<std::int32_t> column_node_;       // per pixel column: the node column at or left of it,
  std::vector<std::int32_t> column_next_node_;  // the one after it (the same at the last column)
  std::vector<float> column_weight_;            // and the weight of the one after it
  int grid_ = 1;  // [px]
  int samples_ = 0;
  double s0_ = 0.0, s_max_ = 0.0, log_ratio_ = 0.0;
  // samples + 1 planes (s0, then the end of each interval of the s grid), each with every node's
  // (row-major) R, G, B: the pixels of an image row read short runs of it.
  std::vector<float> cumulative_;
};

}  // namespace hadal::render
