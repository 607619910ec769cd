// The seabed as a height function, for contact models (physics/terramechanics.h): its height h(x, y)
// in W and unit upward normal at a point of the horizontal plane, and an upper bound of h over a region.
//
// A plane is h = z with normal +z everywhere. A surface mesh in W (a height field's two triangles per
// cell, or any mesh file) is binned once into a uniform grid of cells over its xy bounding box; each cell
// lists the triangles whose xy bounding box meets it and keeps the highest vertex among them. A sample
// finds the triangles over (x, y) in its cell (barycentric test in xy, inclusive edges) and takes the
// highest: where a mesh folds over itself (an overhang), a body coming from above meets the top layer.
// Triangles seen edge-on from above (|n_z| < 1e-6) carry no height. Outside the mesh's xy extent, and
// over holes, there is no seabed: sample() reports none.
// Units: m.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

#include "hadal/geometry/triangle_mesh.h"

namespace hadal::geometry {

class SeabedHeight {
 public:
  // The plane z = height_W.
  static SeabedHeight plane(double height_W);
  // The top surface of a mesh in W. height_field: the mesh is single-valued over the plane (a height
  // field's triangles never overlap in xy), so a sample may stop at the first triangle over the point.
  explicit SeabedHeight(const TriangleMesh& mesh_W, bool height_field = false);

  struct Sample {
    double height = 0.0;                                 // h [m]
    Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();  // unit, n_z > 0
  };
  // The seabed at (x, y) in W; false where there is none. hint: the triangle a previous nearby sample
  // found (updated; start with kNoHint), tried first on a height field, where neighbouring samples mostly
  // fall in the same triangle.
  static constexpr std::uint32_t kNoHint = 0xffffffffu;
  bool sample(double x_W, double y_W, Sample* out, std::uint32_t* hint = nullptr) const;
  // An upper bound of h over the region (the highest vertex of the cells it meets; the plane's z);
  // -infinity where there is no seabed.
  double max_height_in(const Eigen::AlignedBox2d& region_xy) const;

 private:
  SeabedHeight() = default;
  bool is_plane_ = false;
  bool height_field_ = false;
  double plane_z_ = 0.0;
  // Grid over the triangles' xy bounding box: cell (i, j) covers [x0 + i cx, x0 + (i + 1) cx) x ...
  double x0_ = 0.0, y0_ = 0.0, cell_x_ = 1.0, cell_y_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> cell_start_;  // CSR: cell k's triangles are cell_triangles_[start[k] .. start[k+1])
  std::vector<std::uint32_t> cell_triangles_;
  std::vector<float> cell_max_z_;          // per cell; -inf for an empty cell
  // Per triangle: its vertices (a, b, c) as 9 doubles.
  std::vector<double> vertices_;
};

}  // namespace hadal::geometry
