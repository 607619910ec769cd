// Each instruction set's compilation of the face loops against the unvectorised reference (face_kernel.h): the
// baseline's SSE2 vectorisation, AVX2 and AVX-512 compiled here from the same face_kernel.inc with the library's
// flags (server/CMakeLists.txt), so every clone is checked on a CPU that has it, not only the one the loader picks.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "face_kernel.h"
#include "hadal/assets/mesh_generators.h"
#include "hadal/geometry/triangle_mesh.h"
#include "hadal/physics/surface_hydrodynamics.h"

namespace hadal::physics::face_kernel {

namespace baseline_isa {
#define HADAL_FACE_KERNEL
#include "face_kernel.inc"
#undef HADAL_FACE_KERNEL
}  // namespace baseline_isa

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
namespace avx2_isa {
#define HADAL_FACE_KERNEL __attribute__((target("avx2")))
#include "face_kernel.inc"
#undef HADAL_FACE_KERNEL
}  // namespace avx2_isa

namespace avx512_isa {
#define HADAL_FACE_KERNEL __attribute__((target("avx512f")))
#include "face_kernel.inc"
#undef HADAL_FACE_KERNEL
}  // namespace avx512_isa
#endif

namespace {

// The hull and motions of SurfaceHydrodynamicsKernelTest (surface_hydrodynamics_test.cc): every term on, an odd face
// count, submerged (uniform water's constants and the sampled path), 4000 m deep, and cut by the waterline.
void expect_reference_bits(const Kernel& kernel) {
  assets::MeshData data = assets::make_torpedo(2.0, 0.15, 37, 9);
  geometry::TriangleMesh hull;
  hull.positions = data.positions;
  hull.indices = data.indices;
  HydrodynamicCoefficients all;
  all.lift = 0.8;
  all.magnus = 0.05;
  SurfaceHydrodynamics isa(hull, all), reference(hull, all);
  isa.use_kernel(&kernel);
  reference.use_scalar_kernel(true);
  UniformWater water;
  water.current_W = Eigen::Vector3d(0.3, -0.2, 0.05);
  UniformWater denser = water;  // another density: rho A is not a constant times A
  denser.density = 1027.5;
  for (const double z : {-30.0, -4000.0, 0.02}) {
    for (const UniformWater* fluid : {&water, &denser}) {
      BodyMotion m;
      m.X_WB.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
                            .toRotationMatrix();
      m.X_WB.translation() = Eigen::Vector3d(1200.0, -300.0, z);
      m.p_WBcm = m.X_WB * Eigen::Vector3d(0.05, 0.01, -0.02);
      m.v_WBcm = Eigen::Vector3d(1.5, 0.1, -0.05);
      m.w_WB = Eigen::Vector3d(0.02, -0.05, 0.1);
      const HydrodynamicWrench a = isa.compute(m, *fluid), b = reference.compute(m, *fluid);
      EXPECT_EQ(a.f_W, b.f_W) << "z " << z << ": " << a.f_W.transpose() << " vs " << b.f_W.transpose();
      EXPECT_EQ(a.tau_W, b.tau_W) << "z " << z;
      EXPECT_EQ(a.wetted_area, b.wetted_area);
      EXPECT_EQ(a.clipped_faces, b.clipped_faces);
      EXPECT_GT(b.f_W.norm(), 1.0);
    }
  }
}

TEST(FaceKernelIsaTest, BaselineVectorisationGivesTheReferenceBits) { expect_reference_bits(baseline_isa::kernel_table()); }

TEST(FaceKernelIsaTest, Avx2GivesTheReferenceBits) {
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this CPU has no AVX2: nothing to compare";
  expect_reference_bits(avx2_isa::kernel_table());
#else
  GTEST_SKIP() << "function multiversioning is GCC on x86-64 only";
#endif
}

TEST(FaceKernelIsaTest, Avx512GivesTheReferenceBits) {
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
  if (!__builtin_cpu_supports("avx512f")) GTEST_SKIP() << "this CPU has no AVX-512: nothing to compare";
  expect_reference_bits(avx512_isa::kernel_table());
#else
  GTEST_SKIP() << "function multiversioning is GCC on x86-64 only";
#endif
}

}  // namespace
}  // namespace hadal::physics::face_kernel
