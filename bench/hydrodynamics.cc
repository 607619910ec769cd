// Surface hydrodynamics throughput: SurfaceHydrodynamics::compute on one core for a torpedo hull of
// ~11k faces (make_torpedo, 2 m x 0.15 m), every term on (buoyancy, pressure drag, skin friction,
// lift, Magnus) with a current and a translating and rotating body.
//   submerged   30 m deep (bounding sphere under water: the unmasked loop, no classification)
//   partial     centre on the waterline, pitched and rolled (classification, masked loop, clipping
//               of the faces that cross the surface)
// Each is measured with the vectorised loops ("kernel": "vector", the CPU's best clone: src/physics/face_kernel.h);
// three once more with the unvectorised reference ("scalar"), which gives the same bits.
// Fluids ("fluid" in the output): uniform (UniformWater, both cases), and the scenario ocean through
// OceanFluid (submerged case only, at 30 m and at 3000 m): constant (1025 kg/m^3), ramp (the paper's
// pycnocline defaults, 1025 + 3.075 kg/m^3 over 1000 m) and ctd (a four-row cast to 6000 m, EOS-80,
// the tabulated pressure). Same uniform current in all of them, no shear, no Gauss-Markov part.
// Each measurement is the median over --repetitions batches of compute() calls (each batch ~50 ms);
// face_evals_per_s = faces / seconds per call (a clipped face counts once). Prints one JSON object
// per measurement. Issue 4's target: >= 1e8 face evaluations per second per core (Stonefish ~3.3e7).
//   build/bin/hadal_bench_hydrodynamics [--repetitions N] [--segments S] [--profile-steps P]
// Defaults (128 segments, 22 profile steps) give 11 264 faces.
// Waves (issue 44): the partial case through OceanFluid in calm constant water and in a JONSWAP sea (Hs 2 m, Tp 8 s,
// 128 components, spread), a fresh OceanFluid per call as the simulation makes one per body and step (the waves'
// linearisation about the body, physics/ocean_fluid.h, is then paid every call): "waves_per_call" is the
// difference, the waves' cost per body and step.
// Soil contact in the same run ("benchmark": "soil_contact", issue 12): SoilContact::compute for a
// crawler track's box (1.8 m x 0.3 m x 0.35 m, its faces split to 10 cm: physics/terramechanics.h) sunk
// 4 cm into the deep-sea ooze preset and driven with a belt, over a plane and over a 2 m height field
// (the procedural seabed's grid); ns_per_face is per face in contact, ns_per_step per call.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "hadal/assets/mesh_generators.h"
#include "hadal/geometry/triangle_mesh.h"
#include "hadal/physics/ocean.h"
#include "hadal/physics/ocean_fluid.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/seabed_height.h"
#include "hadal/geometry/terrain.h"
#include "hadal/physics/soil_presets.h"
#include "hadal/physics/surface_hydrodynamics.h"
#include "hadal/physics/terramechanics.h"

namespace {

using Clock = std::chrono::steady_clock;
using hadal::DensityModel;
using hadal::physics::BodyMotion;
using hadal::physics::FluidSampler;
using hadal::physics::HydrodynamicWrench;
using hadal::physics::Ocean;
using hadal::physics::OceanFluid;
using hadal::physics::SurfaceHydrodynamics;
using hadal::physics::UniformWater;

struct Result {
  double seconds_per_call;
  HydrodynamicWrench wrench;
};

Result measure(SurfaceHydrodynamics& hydro, const BodyMotion& motion, const FluidSampler& water,
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

  const Eigen::Vector3d current_W(0.3, -0.2, 0.05);
  UniformWater uniform;
  uniform.current_W = current_W;
  hadal::WaterSpec water;
  water.current.uniform_W = current_W;
  water.ctd = {{0.0, 20.0, 35.5}, {200.0, 12.0, 35.0}, {1000.0, 4.0, 34.6}, {6000.0, 1.5, 34.7}};
  const hadal::WaterSpec constant = water;
  hadal::WaterSpec ramp = water;
  ramp.density_model = DensityModel::kRamp;
  hadal::WaterSpec ctd = water;
  ctd.density_model = DensityModel::kCtd;
  const double g = 9.80665;
  const Ocean constant_ocean(constant, g, 1), ramp_ocean(ramp, g, 1), ctd_ocean(ctd, g, 1);
  const OceanFluid constant_fluid(constant_ocean, 0.0), ramp_fluid(ramp_ocean, 0.0),
      ctd_fluid(ctd_ocean, 0.0);

  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  struct Case {
    const char* name;
    const char* fluid_name;
    const FluidSampler* fluid;
    double z;
    bool scalar = false;  // the unvectorised reference loops (SurfaceHydrodynamics::use_scalar_kernel)
  };
  const Case cases[] = {{"submerged", "uniform", &uniform, -30.0},
                        {"partial", "uniform", &uniform, 0.0},
                        {"submerged", "constant", &constant_fluid, -30.0},
                        {"submerged", "ramp", &ramp_fluid, -30.0},
                        {"submerged", "ctd", &ctd_fluid, -30.0},
                        {"submerged_3000m", "constant", &constant_fluid, -3000.0},
                        {"submerged_3000m", "ramp", &ramp_fluid, -3000.0},
                        {"submerged_3000m", "ctd", &ctd_fluid, -3000.0},
                        {"submerged", "constant", &constant_fluid, -30.0, true},
                        {"submerged", "ramp", &ramp_fluid, -30.0, true},
                        {"partial", "uniform", &uniform, 0.0, true}};
  for (const Case& c : cases) {
    BodyMotion m;
    m.X_WB.linear() = R;
    m.X_WB.translation() = Eigen::Vector3d(1200.0, -300.0, c.z);
    m.p_WBcm = m.X_WB * Eigen::Vector3d(0.05, 0.0, -0.01);
    m.v_WBcm = R * Eigen::Vector3d(1.5, 0.1, -0.05);
    m.w_WB = Eigen::Vector3d(0.02, -0.05, 0.1);
    hydro.use_scalar_kernel(c.scalar);
    const Result r = measure(hydro, m, *c.fluid, repetitions);
    hydro.use_scalar_kernel(false);
    const double faces = static_cast<double>(hydro.num_faces());
    std::printf(
        "{\"benchmark\": \"surface_hydrodynamics\", \"case\": \"%s\", \"fluid\": \"%s\", \"kernel\": \"%s\", "
        "\"faces\": %zu, \"clipped_faces\": %zu, \"terms\": \"buoyancy+drag+friction+lift+magnus\", "
        "\"seconds_per_call\": %.4g, \"ns_per_face\": %.3f, \"face_evals_per_s\": %.4g, "
        "\"calls_per_s\": %.1f, \"f_W\": [%.6g, %.6g, %.6g]}\n",
        c.name, c.fluid_name, c.scalar ? "scalar" : "vector", hydro.num_faces(), r.wrench.clipped_faces, r.seconds_per_call,
        1e9 * r.seconds_per_call / faces, faces / r.seconds_per_call, 1.0 / r.seconds_per_call,
        r.wrench.f_W.x(), r.wrench.f_W.y(), r.wrench.f_W.z());
  }
  // Waves: the partial case, a fresh OceanFluid per call (as per body and step in the simulation).
  {
    hadal::WorldSpec calm_world, sea_world;
    calm_world.water = constant;
    sea_world.water = constant;
    sea_world.waves.spectrum = hadal::physics::WaveSpectrum::kJonswap;
    sea_world.waves.significant_height = 2.0;
    sea_world.waves.peak_period = 8.0;
    sea_world.waves.spreading = 10.0;
    const Ocean calm_ocean(calm_world), sea_ocean(sea_world);
    BodyMotion m;
    m.X_WB.linear() = R;
    m.X_WB.translation() = Eigen::Vector3d(1200.0, -300.0, 0.0);
    m.p_WBcm = m.X_WB * Eigen::Vector3d(0.05, 0.0, -0.01);
    m.v_WBcm = R * Eigen::Vector3d(1.5, 0.1, -0.05);
    m.w_WB = Eigen::Vector3d(0.02, -0.05, 0.1);
    const auto per_call = [&](const Ocean& ocean, HydrodynamicWrench* last) {
      int calls = 1;
      for (;;) {
        const auto start = Clock::now();
        for (int i = 0; i < calls; ++i) *last = hydro.compute(m, OceanFluid(ocean, 3.7 + 1e-6 * i));
        if (std::chrono::duration<double>(Clock::now() - start).count() > 0.05) break;
        calls *= 2;
      }
      std::vector<double> seconds;
      for (int r = 0; r < repetitions; ++r) {
        const auto start = Clock::now();
        for (int i = 0; i < calls; ++i) *last = hydro.compute(m, OceanFluid(ocean, 3.7 + 1e-6 * i));
        seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count() / calls);
      }
      std::sort(seconds.begin(), seconds.end());
      return seconds[seconds.size() / 2];
    };
    HydrodynamicWrench calm_w, sea_w;
    const double calm_s = per_call(calm_ocean, &calm_w), sea_s = per_call(sea_ocean, &sea_w);
    const double faces = static_cast<double>(hydro.num_faces());
    std::printf(
        "{\"benchmark\": \"surface_hydrodynamics\", \"case\": \"partial_waves\", \"fluid\": \"constant\", "
        "\"faces\": %zu, \"clipped_faces\": %zu, \"components\": 128, \"calm_seconds_per_call\": %.4g, "
        "\"waves_seconds_per_call\": %.4g, \"waves_per_call\": %.4g, \"calm_ns_per_face\": %.3f, "
        "\"waves_ns_per_face\": %.3f}\n",
        hydro.num_faces(), sea_w.clipped_faces, calm_s, sea_s, sea_s - calm_s, 1e9 * calm_s / faces,
        1e9 * sea_s / faces);
  }
  // Soil contact: one track link, its bottom 4 cm into the sediment, driving at 0.3 m/s with 5 % slip.
  hadal::CollisionShape track;
  track.type = hadal::CollisionShapeType::kBox;
  track.box_size = Eigen::Vector3d(1.8, 0.3, 0.35);
  const hadal::geometry::TriangleMesh track_mesh = hadal::geometry::tessellate(track);
  hadal::geometry::HeightField field;
  field.nx = field.ny = 101;
  field.dx = field.dy = 2.0;
  field.x0 = field.y0 = -100.0;
  field.heights.assign(static_cast<std::size_t>(field.nx * field.ny), -100.0f);
  const hadal::geometry::SeabedHeight plane = hadal::geometry::SeabedHeight::plane(-100.0);
  const hadal::geometry::SeabedHeight grid(hadal::geometry::heightfield_to_mesh(field), true);
  const struct {
    const char* name;
    const hadal::geometry::SeabedHeight* seabed;
  } soils[] = {{"plane", &plane}, {"height_field_2m", &grid}};
  for (const auto& soil_case : soils) {
    hadal::physics::SoilContact contact(track_mesh, hadal::config::find_preset(hadal::physics::soil_presets(), "deep_sea_ooze")->figures, 700.0,
                                        0.005);
    hadal::physics::SoilShearState shear;
    BodyMotion m;
    m.X_WB.translation() = Eigen::Vector3d(10.3, -20.1, -100.0 + 0.175 - 0.04);
    m.p_WBcm = m.X_WB.translation();
    m.v_WBcm = Eigen::Vector3d(0.285, 0.0, 0.0);
    const std::vector<Eigen::Vector3d> belt = {Eigen::Vector3d(-0.3, 0.0, 0.0)};
    hadal::physics::SoilWrench w;
    int calls = 1;
    for (;;) {
      const auto start = Clock::now();
      for (int i = 0; i < calls; ++i) w = contact.compute(m, *soil_case.seabed, shear, belt);
      if (std::chrono::duration<double>(Clock::now() - start).count() > 0.05) break;
      calls *= 2;
    }
    std::vector<double> per_call;
    for (int r = 0; r < repetitions; ++r) {
      const auto start = Clock::now();
      for (int i = 0; i < calls; ++i) w = contact.compute(m, *soil_case.seabed, shear, belt);
      per_call.push_back(std::chrono::duration<double>(Clock::now() - start).count() / calls);
    }
    std::sort(per_call.begin(), per_call.end());
    const double seconds = per_call[per_call.size() / 2];
    std::printf(
        "{\"benchmark\": \"soil_contact\", \"case\": \"track_1.8x0.3m_sunk_4cm\", \"seabed\": \"%s\", "
        "\"faces\": %zu, \"faces_in_contact\": %zu, \"seconds_per_call\": %.4g, \"ns_per_face\": %.3f, "
        "\"traction_N\": %.6g, \"normal_N\": %.6g}\n",
        soil_case.name, contact.num_faces(), w.faces_in_contact, seconds,
        1e9 * seconds / static_cast<double>(std::max<std::size_t>(w.faces_in_contact, 1)), w.shear_force_W.x(),
        w.normal_force_W.z());
  }
  return 0;
}
