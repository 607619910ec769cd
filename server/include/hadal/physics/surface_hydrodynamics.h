// Surface-based hydrodynamics (paper: "Environmental Flow Modeling and Hydrodynamic Forces"): the
// fluid wrench on a rigid body as a sum over the faces of its hydrodynamic mesh, evaluated every
// physics step with fluid properties sampled at each face centroid.
//
// Per wetted face f (area A, unit outward normal n, centroid r_c; r = r_c - p_WBcm its offset from
// the centre of mass; everything in W):
//   relative flow  v_c = v_fluid(r_c) - (v_WBcm + w_WB x r)          (fluid seen from the face)
//   c_n = n . v_c;  |v_c|;  v_t = v_c - c_n n (tangential part)
//   buoyancy       F_b = -p A n,                 p gauge pressure at r_c (p - p_atm, 0 above water)
//   pressure drag  F_d = -1/2 rho C_D A min(c_n, 0)^2 n
//                  only faces the flow hits (c_n < 0: the fluid moves *into* the face); the
//                  overpressure pushes the face inward, i.e. along the flow.
//   skin friction  F_f = 1/2 rho C_f A |v_t| v_t      (drags the face along with the fluid)
//   lift           F_l = 1/2 rho C_L A |v_c|^2 (n . v_hat) (n - (n . v_hat) v_hat)
//   Magnus         F_m = C_M rho A |v_c| (w_WB x v_r),  v_r = -v_c (the face's velocity through the water)
//   moment about the centre of mass: tau = r x (F_b + F_d + F_f + F_l + F_m) + dtau_b
//   dtau_b = rho g A (C_W z) x n: buoyancy acts at the face's centre of pressure, not its centroid.
//            The pressure varies linearly over the face (dp/dz = -rho g), so its exact moment about
//            the centroid is -int (x - r_c) x n (p - p_c) dA = rho g A (C_W z) x n, with
//            A C = int (x - r_c)(x - r_c)^T dA the face's second area moment (A/12 sum_k d_k d_k^T
//            for a triangle, d_k = vertex - centroid). It matters for coarse hulls: a box whose
//            sides are two triangles gets its heeling moment wrong by ~30 % without it.
// The body wrench is the sum over faces: f_W, and tau_W about p_WBcm.
//
// Lift, the physically sound reading of the paper. The paper writes F = 1/2 rho C_L A (1 - |n.v_hat|)
// |v|^2 d_lift with d_lift = n x v_hat / |n x v_hat|. Taken literally, d_lift lies in the face's own
// plane (perpendicular to n), so the two sides of a thin plate, or opposite faces of any symmetric
// hull, cancel exactly and a wing never lifts; and the factor (1 - |n.v_hat|) is largest when the
// flow grazes the face (angle of attack 0), which makes per-face lift jump as the sign of n.v_hat
// flips. Lift is the part of a face's pressure force perpendicular to the flow: the force acts along
// -n (overpressure, windward, n.v_c < 0) or +n (suction, leeward), so its lift part is along
// -sign(n.v_hat) n_perp with n_perp = n - (n.v_hat) v_hat, which lies in the plane of n and v_c
// (the lift plane) and is perpendicular to v_c. The magnitude 1/2 rho C_L A |v|^2 |n.v_hat| |n_perp|
// = 1/4 rho C_L A |v|^2 |sin 2 alpha| (alpha = angle between flow and face plane) vanishes at 0 and 90
// degrees, like the paper's factor vanishes when the flow is along the normal, and is continuous. Both
// sides of a plate lift the same way, so a plate of area A gets C_L,plate = C_L sin 2 alpha (slope
// 2 C_L per radian at small alpha).
//
// Magnus: the paper's F = C_M rho A |v| (w x v) with v the body's velocity *through the water*,
// v_r = -v_c. With v_c in its place the force would point the wrong way: a cylinder spinning about +z
// at rest in a flow along +x is pushed towards -y (Kutta-Joukowski: the surface moving with the flow
// on the -y side speeds it up there, lowering the pressure), which is w x v_r, not w x v_c; and summed
// over a hull the reversed sign feeds tilt rates instead of damping them (a descending lander
// wobbles). Units: C_M rho A |v| |w x v| is N per second, so C_M carries seconds (C_M |v_c| acts as
// the length scale the paper says C_M absorbs). It must be calibrated (paper: against CFD and a
// free-fall lander); the default 0 leaves it off.
//
// Buoyancy and atmospheric pressure. Over a closed surface a uniform pressure integrates to zero
// (sum A n = 0, divergence theorem), so for a fully submerged body p_atm, and indeed any constant,
// cancels. A partially submerged body is closed only by its dry part, where the atmosphere pushes
// with p_atm too: wet part with p_atm + p_gauge plus dry part with p_atm is p_atm over the closed
// surface (zero) plus p_gauge over the wet part. So gauge pressure below the surface and zero above
// is exact for both. Faces that cross the water surface are clipped at the waterline (the submerged
// polygon of the triangle, 3 or 4 vertices); its pressure is linear in position, so pressure at the
// polygon's centroid times its area is the exact integral, and the force acts at that centroid
// plus the exact centre-of-pressure term dtau_b above, so force and moment are both exact for any
// mesh: partially submerged hulls float at the right draft and trim.
//
// Precision (float hot loop). Faces, offsets r and all per-face arithmetic are float (8 lanes per
// AVX register, 4 per SSE): offsets from the centre of mass are small, so a body 10 km from the
// origin keeps sub-millimetre resolution (the origin is added in double). Pressure is passed as the
// difference dp = p(r_c) - p(p_WBcm) relative to the centre of mass, plus p_ref = p(p_WBcm) in
// double: a fully submerged body uses dp only (p_ref cancels over the closed surface, see above),
// so 6000 m deep, where p is 6e7 Pa, buoyancy still sums terms of size rho g |r| instead of
// cancelling 6e7 Pa faces in float. Each block of kBlock faces is summed in kLanes float lanes, then
// blocks in double. Relative error of the wrench: a few 1e-7 per face, ~1e-6 for 10k faces.
//
// Performance. Faces are classified against the waterline only when the body's bounding sphere
// crosses the surface; the per-face loop has no branches (wet and facing-flow masks are arithmetic:
// a = A * wet, min(c_n, 0) a select), and GCC vectorises it, compiled for AVX-512 (16 faces at once),
// AVX2 (8) and baseline SSE2 (4), picked at load time (src/physics/face_kernel.h). Without FMA
// contraction and with IEEE sqrt and division, every version gives the bits of the unvectorised loop
// (use_scalar_kernel). A body wholly under uniform water (FluidSampler::uniform) skips the sampling
// pass. Crossing faces are clipped in a separate scalar pass and run through the same loop. Cost per
// face on one core: docs/benchmarks.md, "Surface hydrodynamics" (bench/hydrodynamics.cc), all terms on.
//
// Meshes must be closed and oriented outward (geometry::compute_mesh_properties reports `closed`);
// an open mesh gets no correct buoyancy (thin plates are fine for drag/lift tests).
// Units: SI (m, s, kg, N, Pa).
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "hadal/physics/fluid_spec.h"

namespace hadal::geometry {
struct TriangleMesh;
}

namespace hadal::physics {

namespace face_kernel {
struct Kernel;
}

// Output of a FluidSampler batch (all arrays hold n floats).
struct FluidSamples {
  float* rho;  // density [kg/m^3]
  float* dp;   // p_g(z_i) - p_g(origin_z), gauge pressure difference to the batch origin [Pa]
  float* u_x;  // fluid velocity in W [m/s]
  float* u_y;
  float* u_z;
};

// The water column as the face kernel sees it. The ocean model implements this; a sampler is a view
// of the fluid at one instant (it holds whatever time/state it needs), so calls are const.
class FluidSampler {
 public:
  virtual ~FluidSampler() = default;
  // Height of the mean water surface in W [m]; depth d = surface_z_W() - z.
  virtual double surface_z_W() const = 0;
  // The surface near a body at p_W as a plane: its height at p_W's (x, y) [m, W] and its slopes d/dx, d/dy; by
  // default the flat mean surface. A body is classified and its faces clipped against this plane (waves much longer
  // than the body: physics/waves.h).
  struct SurfacePlane {
    double height = 0.0;
    double slope_x = 0.0, slope_y = 0.0;
  };
  virtual SurfacePlane surface_plane(const Eigen::Vector3d& /*p_W*/) const { return {surface_z_W(), 0.0, 0.0}; }
  // Gauge pressure p(z) - p_atm at height z [Pa]; 0 at and above the surface.
  virtual double gauge_pressure(double z_W) const = 0;
  // Gauge pressure at a point [Pa]: gauge_pressure(z) unless the sea state makes it depend on (x, y) too. The
  // reference of sample()'s dp for a body that crosses the surface.
  virtual double gauge_pressure_at(const Eigen::Vector3d& p_W) const { return gauge_pressure(p_W.z()); }
  // The waves near a body sampled about origin_W, the same for all its faces (zero without waves): the orbital
  // velocity and acceleration (sample() adds the velocity to the current; a vehicle's added mass feels both), and the
  // gradient of the dynamic pressure, which the kernel's centre-of-pressure moments add to the hydrostatic one
  // (docs/ARCHITECTURE.md, "Waves").
  struct WavesNear {
    Eigen::Vector3d velocity_W = Eigen::Vector3d::Zero();           // orbital velocity [m/s, W]
    Eigen::Vector3d acceleration_W = Eigen::Vector3d::Zero();       // its rate [m/s^2, W] (for the added mass)
    Eigen::Vector3d pressure_gradient_W = Eigen::Vector3d::Zero();  // grad p_d [Pa/m, W]
    double density = 0.0;  // the density p_d is scaled with [kg/m^3]
  };
  virtual WavesNear waves_near(const Eigen::Vector3d& /*origin_W*/) const { return {}; }
  // Water that is the same everywhere under the surface: constant density, the hydrostatic pressure alone (no waves)
  // and one current. When it is, a body wholly under the surface is evaluated without sample(): density and current
  // are the kernel's constants and the pressure difference to the centre of mass is -rho g dz (the bits sample()
  // would give in float: UniformWater's formula). Empty otherwise (the default).
  struct Uniform {
    double density = 0.0;                                 // [kg/m^3]
    Eigen::Vector3d current_W = Eigen::Vector3d::Zero();  // [m/s]
  };
  virtual std::optional<Uniform> uniform() const { return std::nullopt; }
  // g [m/s^2]: the hydrostatic gradient dp/dz = -rho g (centre-of-pressure moments).
  virtual double gravity_magnitude() const = 0;
  // Fluid at the n points origin_W + (dx_i, dy_i, dz_i) (offsets in W axes). Called per block of at
  // most SurfaceHydrodynamics::kBlock points, so implementations may keep small scratch on the stack.
  virtual void sample(const Eigen::Vector3d& origin_W, std::size_t n, const float* dx,
                      const float* dy, const float* dz, const FluidSamples& out) const = 0;
};

// Constant density, flat surface, hydrostatic pressure p = p_atm + rho g d (d >= 0), uniform current.
// For tests and simple scenes.
class UniformWater final : public FluidSampler {
 public:
  double density = 1025.0;                              // rho [kg/m^3]
  double surface_z = 0.0;                               // [m]
  double gravity = 9.80665;                             // g [m/s^2]
  double atmospheric_pressure = 101325.0;               // p_atm [Pa] (reported only; cancels)
  Eigen::Vector3d current_W = Eigen::Vector3d::Zero();  // [m/s]

  double surface_z_W() const override { return surface_z; }
  double gravity_magnitude() const override { return gravity; }
  double gauge_pressure(double z_W) const override;
  double absolute_pressure(double z_W) const { return atmospheric_pressure + gauge_pressure(z_W); }
  void sample(const Eigen::Vector3d& origin_W, std::size_t n, const float* dx, const float* dy,
              const float* dz, const FluidSamples& out) const override;
  std::optional<Uniform> uniform() const override { return Uniform{density, current_W}; }
};

// Kinematics of body B at one step.
struct BodyMotion {
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  Eigen::Vector3d p_WBcm = Eigen::Vector3d::Zero();  // centre of mass in W [m]
  Eigen::Vector3d v_WBcm = Eigen::Vector3d::Zero();  // velocity of the centre of mass in W [m/s]
  Eigen::Vector3d w_WB = Eigen::Vector3d::Zero();    // angular velocity in W [rad/s]
};

struct HydrodynamicWrench {
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();    // total force [N]
  Eigen::Vector3d tau_W = Eigen::Vector3d::Zero();  // total moment about p_WBcm [N m]
  double wetted_area = 0.0;                         // [m^2]
  std::size_t clipped_faces = 0;                    // faces crossing the water surface
  bool fully_submerged = false;
};

// Face arrays of a hydrodynamic mesh in B (SoA, float, padded with zero-area faces to a multiple of
// kLanes so the hot loop has no remainder).
struct HydroFaces {
  std::vector<float> area;                          // A [m^2]
  std::vector<float> n_x, n_y, n_z;                 // unit outward normal in B
  std::vector<float> c_x, c_y, c_z;                 // centroid in B [m]
  // C = (1/A) int (x - c)(x - c)^T dA, second area moment about the centroid per area, in B [m^2]
  std::vector<float> s_xx, s_yy, s_zz, s_xy, s_xz, s_yz;
  // 1 for faces the flow reaches, 0 for faces inside another part of the hull (drag, friction, lift
  // and Magnus off; buoyancy kept so every closed part still integrates its pressure).
  std::vector<float> exposed;
  std::size_t size() const { return area.size(); }
};

class SurfaceHydrodynamics {
 public:
  static constexpr std::size_t kLanes = 16;   // accumulator lanes / padding
  static constexpr std::size_t kBlock = 256;  // faces per fluid-sampling block

  // Builds the face arrays from `mesh_B` (positions in B). Zero-area faces are dropped. `exposed`:
  // empty (every face meets the flow) or one flag per triangle (false: the face lies inside another
  // part of the hull, so only its pressure counts). Throws std::invalid_argument for malformed index
  // arrays or a flag count that is neither 0 nor the triangle count.
  explicit SurfaceHydrodynamics(const geometry::TriangleMesh& mesh_B,
                                HydrodynamicCoefficients coefficients = {},
                                const std::vector<bool>& exposed = {});

  // Fluid wrench for body motion `motion` in fluid `fluid`. Reuses internal scratch (not thread
  // safe per object; one object per body).
  HydrodynamicWrench compute(const BodyMotion& motion, const FluidSampler& fluid);

  const HydroFaces& faces() const { return faces_; }
  std::size_t num_faces() const { return num_faces_; }  // without padding
  double surface_area() const { return surface_area_; }
  const HydrodynamicCoefficients& coefficients() const { return coefficients_; }
  void set_coefficients(const HydrodynamicCoefficients& c) { coefficients_ = c; }
  // The loops compiled without vectorisation instead of the CPU's vector clones (src/physics/face_kernel.h): the
  // reference the clones are tested against, and the bench's scalar figure. The same bits either way.
  void use_scalar_kernel(bool on);
  // Another compilation of the loops (tests: each instruction set's), or null for the CPU's vector clones.
  void use_kernel(const face_kernel::Kernel* kernel) { kernel_ = kernel; }

 private:
  struct Accumulator;
  void accumulate(const HydroFaces& faces, std::size_t begin, std::size_t end, const float* mask,
                  const BodyMotion& motion, const FluidSampler& fluid, double p_ref,
                  const FluidSampler::Uniform* uniform, Accumulator& acc);
  // The crossing faces clipped against h(x_B) = h0 + g . x_B <= 0 (the surface plane's height above a B point).
  void clip_crossing_faces(const Eigen::Vector3d& g, double h0);

  HydrodynamicCoefficients coefficients_;
  HydroFaces faces_;
  std::size_t num_faces_ = 0;
  double surface_area_ = 0.0;
  // Vertices per face in B (a.x a.y a.z b.x ... c.z), for classification and clipping.
  std::vector<float> v_[9];
  const face_kernel::Kernel* kernel_ = nullptr;  // null: the vector clones
  const face_kernel::Kernel& kernel() const;     // the loops in use
  Eigen::Vector3d sphere_center_B_ = Eigen::Vector3d::Zero();
  double sphere_radius_ = 0.0;
  // Per-step scratch.
  std::vector<float> wet_mask_;
  std::vector<float> ones_;
  std::vector<float> crossing_flags_;
  std::vector<std::size_t> crossing_;
  HydroFaces clipped_;
};

}  // namespace hadal::physics
