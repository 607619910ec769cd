// Surface hydrodynamics throughput: SurfaceHydrodynamics::compute on one core for a torpedo hull of
// ~11k faces (make_torpedo, 2 m x 0.15 m), every term on (buoyancy, pressure drag, skin friction,
// lift, Magnus) with a current, a translating and rotating body, and UniformWater as the fluid.
//   submerged   30 m deep (bounding sphere under water: the unmasked loop, no classification)
//   partial     centre on the waterline, pitched and rolled (classification, masked loop, clipping
//               of the faces that cross the surface)
// Each measurement is the median over --repetitions batches of compute() calls (each batch ~50 ms);
// face_evals_per_s = faces / seconds per call (a clipped face counts once). Prints one JSON object
// per measurement. Issue 4's target: >= 1e8 face evaluations per second per core (Stonefish ~3.3e7).
//   build/bin/hadal_bench_hydrodynamics [--repetitions N] [--segments S] [--profile-steps P]
// Defaults (128 segments, 22 profile steps) give 11 264 faces.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "hadal/assets/mesh_generators.h"
#include "hadal/geometry/triangle_mesh.h"
#include "hadal/physics/surface_hydrodynamics.h"

namespace {

using Clock = std::chrono::steady_clock;
using hadal::physics::BodyMotion;
using hadal::physics::HydrodynamicWrench;
using hadal::physics::SurfaceHydrodynamics;
using hadal::physics::UniformWater;

struct Result {
  double seconds_per_call;
  HydrodynamicWrench wrench;
};

Result measure(SurfaceHydrodynamics& hydro, const BodyMotion& motion, const UniformWater& water,
               int repetitions) {
  // Calibrate the batch size to ~50 ms.
  int calls = 1;
  for (;;) {
    const auto start = Clock::now();
    for (int i = 0; i < calls; ++i) hydro.compute(motion, water);
    const double s = std::chrono::duration<double>(Clock::now() - start).count();
    if (s > 0.05) break;
    calls *= 2;
  }
  std::vector<double> per_call;
  HydrodynamicWrench w;
  BodyMotion m = motion;
  for (int r = 0; r < repetitions; ++r) {
    const auto start = Clock::now();
    for (int i = 0; i < calls; ++i) {
      m.v_WBcm.x() = motion.v_WBcm.x() + 1e-9 * i;  // defeat any hoisting of the call
      w = hydro.compute(m, water);
    }
    per_call.push_back(std::chrono::duration<double>(Clock::now() - start).count() / calls);
  }
  std::sort(per_call.begin(), per_call.end());
  return {per_call[per_call.size() / 2], w};
}

}  // namespace

int main(int argc, char** argv) {
  int repetitions = 15, segments = 128, profile_steps = 22;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--repetitions")) repetitions = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--segments")) segments = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--profile-steps")) profile_steps = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: %s [--repetitions N] [--segments S] [--profile-steps P]\n", argv[0]);
      return 2;
    }
  }
  const hadal::assets::MeshData data = hadal::assets::make_torpedo(2.0, 0.15, segments, profile_steps);
  hadal::geometry::TriangleMesh mesh;
  mesh.positions = data.positions;
  mesh.indices = data.indices;
  hadal::physics::HydrodynamicCoefficients all;
  all.magnus = 0.05;
  SurfaceHydrodynamics hydro(mesh, all);

  UniformWater water;
  water.current_W = Eigen::Vector3d(0.3, -0.2, 0.05);
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  struct Case {
    const char* name;
    double z;
  };
  for (const Case& c : {Case{"submerged", -30.0}, Case{"partial", 0.0}}) {
    BodyMotion m;
    m.X_WB.linear() = R;
    m.X_WB.translation() = Eigen::Vector3d(1200.0, -300.0, c.z);
    m.p_WBcm = m.X_WB * Eigen::Vector3d(0.05, 0.0, -0.01);
    m.v_WBcm = R * Eigen::Vector3d(1.5, 0.1, -0.05);
    m.w_WB = Eigen::Vector3d(0.02, -0.05, 0.1);
    const Result r = measure(hydro, m, water, repetitions);
    const double faces = static_cast<double>(hydro.num_faces());
    std::printf(
        "{\"benchmark\": \"surface_hydrodynamics\", \"case\": \"%s\", \"faces\": %zu, "
        "\"clipped_faces\": %zu, \"terms\": \"buoyancy+drag+friction+lift+magnus\", "
        "\"seconds_per_call\": %.4g, \"ns_per_face\": %.3f, \"face_evals_per_s\": %.4g, "
        "\"calls_per_s\": %.1f, \"f_W\": [%.6g, %.6g, %.6g]}\n",
        c.name, hydro.num_faces(), r.wrench.clipped_faces, r.seconds_per_call,
        1e9 * r.seconds_per_call / faces, faces / r.seconds_per_call, 1.0 / r.seconds_per_call,
        r.wrench.f_W.x(), r.wrench.f_W.y(), r.wrench.f_W.z());
  }
  return 0;
}
