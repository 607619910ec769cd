// The per-face loops of SurfaceHydrodynamics (the model: hadal/physics/surface_hydrodynamics.h), compiled twice from
// face_kernel.inc: vectorised in surface_hydrodynamics.cc (HADAL_VECTOR_KERNEL: AVX-512, AVX2 or the baseline's SSE2,
// picked at load time), and without vectorisation in face_kernel_scalar.cc, the reference the vector clones are
// tested against. Both are built with HADAL_VECTOR_LOOP_FLAGS (server/CMakeLists.txt: no FMA contraction, sqrt
// without errno), so every version does the same IEEE operations per face in the same order: the wrenches agree to
// the bit (hydrodynamics_test, "KernelTest"), and a lockstep run gives the same digests on any x86-64 CPU.
#pragma once

#include <cstddef>

#include "hadal/physics/surface_hydrodynamics.h"

namespace hadal::physics::face_kernel {

constexpr std::size_t kLanes = SurfaceHydrodynamics::kLanes;

// Per-step constants of the face loops, in float.
struct Params {
  float R[9];     // R_WB, row-major
  float t[3];     // R_WB p_BBcm offset: r = R c_B + t (offset of a B point from p_WBcm, W axes)
  float v[3];     // v_WBcm
  float w[3];     // w_WB
  float drag;     // 1/2 C_D
  float friction; // 1/2 C_f
  float lift;     // 1/2 C_L
  float magnus;   // C_M
  float buoyancy; // 1 or 0
  float g;        // gravity magnitude (0 if buoyancy is off)
  float up_B[3];  // z_W expressed in B (third row of R_WB); with waves z_W - grad p_d / (rho g)
  float p_ref;    // gauge pressure at p_WBcm, or 0 for a fully submerged body [Pa]
  // Uniform water only (face_forces_uniform): density, rho g, and the current in W.
  float rho;
  float rho_g;
  float u[3];
};

// Sums of one block into kLanes independent float accumulators per component (kept apart so the loops vectorise
// without reassociating a single sum): the force and its moment r x F about the centre of mass in W, and the
// centre-of-pressure moment in B (rotated to W once per block by the caller).
struct LaneSums {
  alignas(64) float f[9][kLanes];  // fx fy fz, tx ty tz (W), cx cy cz (B)
  alignas(64) float area[kLanes];
};

// The face arrays of one block (HydroFaces' from some offset on).
struct FaceBlock {
  const float *area, *n_x, *n_y, *n_z, *c_x, *c_y, *c_z, *s_xx, *s_yy, *s_zz, *s_xy, *s_xz, *s_yz, *exposed;
};

// One compilation of the loops (face_kernel.inc has their contracts).
struct Kernel {
  void (*transform_centroids)(const FaceBlock& f, std::size_t n, const Params& k, float* rx, float* ry, float* rz);
  void (*face_forces)(const FaceBlock& f, const float* mask, const float* rx, const float* ry, const float* rz,
                      const FluidSamples& water, std::size_t n, const Params& k, LaneSums& s);
  void (*face_forces_uniform)(const FaceBlock& f, std::size_t n, const Params& k, LaneSums& s);
  void (*classify)(const float* const* v, std::size_t n, float h0, float gx, float gy, float gz, float* wet,
                   float* cross);
};

const Kernel& vector_kernel();  // surface_hydrodynamics.cc
const Kernel& scalar_kernel();  // face_kernel_scalar.cc

}  // namespace hadal::physics::face_kernel
