// SlopeGrid against the height field it was made from: the regional bound holds along random segments,
// is tight where the ground is uniform, and sees steep ground only where it is.
#include "hadal/geometry/slope_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

namespace hadal::geometry {
namespace {

// A grid height field over [0, 100] x [0, 50] m at 1 m spacing, h = height(x, y), two triangles per
// cell facing up.
TriangleMesh grid(const std::function<double(double, double)>& height) {
  TriangleMesh m;
  const int nx = 101, ny = 51;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      m.positions.insert(m.positions.end(), {static_cast<float>(i), static_cast<float>(j), static_cast<float>(height(i, j))});
    }
  }
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const auto v = [&](int a, int b) { return static_cast<std::uint32_t>(b * nx + a); };
      m.indices.insert(m.indices.end(), {v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  }
  return m;
}

// A plane rising 0.05 per metre along x, with a ridge of slope 2 between x = 60 and x = 65.
double ground(double x, double /*y*/) { return 0.05 * x + (x > 60.0 ? 2.0 * (std::min(x, 65.0) - 60.0) : 0.0); }

// Linear interpolation on the grid's triangles (the surface itself).
double surface(double x, double y) {
  const double i = std::floor(x), j = std::floor(y);
  const double fx = x - i, fy = y - j;
  const double h00 = ground(i, j), h10 = ground(i + 1, j), h11 = ground(i + 1, j + 1), h01 = ground(i, j + 1);
  // Triangles (00, 10, 11) below the diagonal fx >= fy, (00, 11, 01) above it.
  return fx >= fy ? h00 + fx * (h10 - h00) + fy * (h11 - h10) : h00 + fy * (h01 - h00) + fx * (h11 - h01);
}

TEST(SlopeGridTest, WholeFieldAndRegions) {
  const SlopeGrid slopes(grid(ground));
  EXPECT_NEAR(slopes.max_slope(), 2.05, 1e-6);
  // On the plane, away from the ridge: the plane's slope (rounded up to float).
  const double plane = slopes.max_slope_in(Eigen::AlignedBox2d(Eigen::Vector2d(5, 5), Eigen::Vector2d(40, 30)));
  EXPECT_GE(plane, 0.05);
  EXPECT_NEAR(plane, 0.05, 1e-6);
  // Touching the ridge: its slope.
  EXPECT_NEAR(slopes.max_slope_in(Eigen::AlignedBox2d(Eigen::Vector2d(50, 5), Eigen::Vector2d(61, 6))), 2.05, 1e-6);
  // Wholly outside the field: no ground.
  EXPECT_EQ(slopes.max_slope_in(Eigen::AlignedBox2d(Eigen::Vector2d(200, 0), Eigen::Vector2d(300, 10))), 0.0);
  EXPECT_EQ(slopes.max_slope_in(Eigen::AlignedBox2d()), 0.0);  // empty region
  EXPECT_EQ(SlopeGrid(TriangleMesh{}).max_slope_in(Eigen::AlignedBox2d(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1))), 0.0);
}

// The property the renderer relies on: for p, q in a region R, |h(q) - h(p)| <= L(R) |q - p|.
TEST(SlopeGridTest, BoundHoldsAlongRandomSegments) {
  const SlopeGrid slopes(grid(ground));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.0, 99.99), uy(0.0, 49.99), size(0.1, 20.0);
  int tight = 0;
  for (int k = 0; k < 20000; ++k) {
    const Eigen::Vector2d p(ux(rng), uy(rng));
    const Eigen::Vector2d q(std::clamp(p.x() + size(rng) - 10.0, 0.0, 99.99), std::clamp(p.y() + size(rng) - 10.0, 0.0, 49.99));
    Eigen::AlignedBox2d region;
    region.extend(p).extend(q);
    const double L = slopes.max_slope_in(region);
    const double rise = std::abs(surface(q.x(), q.y()) - surface(p.x(), p.y()));
    ASSERT_LE(rise, L * (q - p).norm() + 1e-9) << p.transpose() << " -> " << q.transpose();
    tight += L < 0.06;
  }
  EXPECT_GT(tight, 5000);  // most short segments lie on the plane and get its slope, not the ridge's
}

}  // namespace
}  // namespace hadal::geometry
