#include "hadal/geometry/terrain.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hadal::geometry {
namespace {

TEST(ProceduralSeabedTest, SameSeedSameTerrainOtherSeedOtherTerrain) {
  ProceduralSeabedSpec spec;
  spec.size_x = 200.0;
  spec.size_y = 100.0;
  spec.resolution = 5.0;
  spec.seed = 42;
  const HeightField a = procedural_seabed(spec);
  const HeightField b = procedural_seabed(spec);
  EXPECT_EQ(a.heights, b.heights);  // bit-identical
  spec.seed = 43;
  const HeightField c = procedural_seabed(spec);
  EXPECT_NE(a.heights, c.heights);
  EXPECT_EQ(a.nx, 41);  // 200 m / 5 m + 1
  EXPECT_EQ(a.ny, 21);
  EXPECT_DOUBLE_EQ(a.x0, -100.0);
  EXPECT_DOUBLE_EQ(a.x0 + (a.nx - 1) * a.dx, 100.0);
}

TEST(ProceduralSeabedTest, SedimentPlainIsFlatAndTheTerrainBeyondItIsNot) {
  ProceduralSeabedSpec spec;
  spec.size_x = spec.size_y = 400.0;
  spec.resolution = 4.0;
  spec.plain_radius = 60.0;
  spec.z_datum = -100.0;
  spec.seed = 7;
  const HeightField f = procedural_seabed(spec);
  double max_dev_plain = 0.0, max_dev_rough = 0.0;
  for (int j = 0; j < f.ny; ++j) {
    for (int i = 0; i < f.nx; ++i) {
      const double r = std::hypot(f.x0 + i * f.dx, f.y0 + j * f.dy);
      const double dev = std::abs(f.height(i, j) - spec.z_datum);
      if (r <= spec.plain_radius) max_dev_plain = std::max(max_dev_plain, dev);
      if (r >= 2.0 * spec.plain_radius) max_dev_rough = std::max(max_dev_rough, dev);
    }
  }
  EXPECT_EQ(max_dev_plain, 0.0);  // no slope: exactly z_datum on the plain
  EXPECT_GT(max_dev_rough, 1.0);  // relief 6 m + ridges 4 m: metres of relief beyond 2 r_plain
  EXPECT_LT(max_dev_rough, spec.relief + spec.ridge_height + 1e-3);  // |fbm| <= 1, ridged in [0, 1]
}

TEST(ProceduralSeabedTest, RegionalSlopeHasTheRequestedGradient) {
  ProceduralSeabedSpec spec;
  spec.size_x = spec.size_y = 100.0;
  spec.resolution = 10.0;
  spec.relief = 0.0;
  spec.ridge_height = 0.0;
  spec.slope = 5.0 * M_PI / 180.0;
  spec.seed = 3;
  const HeightField f = procedural_seabed(spec);
  // A plane: the finite-difference gradient is exact up to float rounding of the heights (~1e-5 m).
  const double gx = (f.height(1, 0) - f.height(0, 0)) / f.dx;
  const double gy = (f.height(0, 1) - f.height(0, 0)) / f.dy;
  EXPECT_NEAR(std::hypot(gx, gy), std::tan(spec.slope), 1e-5);
  const double gx_far = (f.height(f.nx - 1, f.ny - 1) - f.height(f.nx - 2, f.ny - 1)) / f.dx;
  EXPECT_NEAR(gx_far, gx, 1e-5);
}

}  // namespace
}  // namespace hadal::geometry
