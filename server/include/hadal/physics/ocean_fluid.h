// OceanFluid: the scenario's water column (physics::Ocean) at one sim time, as the surface
// hydrodynamics kernel samples it (FluidSampler).
//
//   surface_z_W        Ocean::surface_z
//   gauge_pressure(z)  p(d) - p_atm with d = surface_z - z, 0 above the surface
//   gravity_magnitude  Ocean::gravity
//   sample             rho(d_i); dp_i = p_g(z_i) - p_g(z_origin), both gauge pressures evaluated in
//                      double before the difference is rounded to float (no cancellation of the
//                      absolute 6e7 Pa at 6000 m); current v(p_i, time) from Ocean::sample_current.
// rho and p are evaluated in double in one vectorised loop per density model, with the Ocean's own
// formulas: closed forms for constant and ramp water (rho(d) = rho0 + drho min(d, d_pyc) / d_pyc and its
// integral), and for CTD water the Ocean's table (Ocean::table_pressure / table_density) with the cubic
// Hermite of p and linear rho that Ocean::pressure / density use, read at the two nodes around each
// point. So they equal the point queries up to double rounding (a few 1e-16 of the absolute pressure)
// and then one rounding to float; ocean_fluid_test checks this at many depths. Constant water without waves or
// shear is not sampled at all: uniform() gives the kernel its density and current as constants. Cost of the whole
// kernel per face (bench/hydrodynamics.cc, 11k faces, submerged; docs/benchmarks.md): ramp ~1.5x, CTD ~2.4x
// constant.
// Waves (Ocean::waves, physics/waves.h): a body sees them as linear about the point it is sampled about (its centre
// of mass): the surface as the tangent plane under its bounding sphere's centre (surface_plane), the waves' dynamic
// pressure as its value and gradient there (or at the surface under it when the centre of mass is in the air, carried
// linearly up to it; Waves::kinematics: one evaluation of the components per body and step, not per face), and
// the orbital velocity there added to the current at every face (waves_near gives these, and the orbital
// acceleration, to the kernel's centre-of-pressure moments and the vehicle's added mass). The hydrostatic part is
// then signed (rho(0) g d above the mean surface, d < 0): with the dynamic pressure it is near zero at the moving
// waterline, and the kernel leaves out the faces above the plane. Exact for waves much longer than the body (a 10 m barge in 100 m waves
// sees the pressure's curvature across it as a few per cent of its heave force); short waves on a big hull are
// averaged over it.
// A view: holds a reference to the Ocean, which must outlive it. Units SI.
#pragma once

#include <limits>

#include "hadal/physics/ocean.h"
#include "hadal/physics/surface_hydrodynamics.h"

namespace hadal::physics {

class OceanFluid final : public FluidSampler {
 public:
  OceanFluid(const Ocean& ocean, double time) : ocean_(ocean), time_(time) {}

  double surface_z_W() const override { return ocean_.surface_z(); }
  SurfacePlane surface_plane(const Eigen::Vector3d& p_W) const override;
  double gauge_pressure(double z_W) const override;
  double gauge_pressure_at(const Eigen::Vector3d& p_W) const override;
  WavesNear waves_near(const Eigen::Vector3d& origin_W) const override;
  double gravity_magnitude() const override { return ocean_.gravity(); }
  // Constant-density water without waves and without a shear current (the Gauss-Markov part is the same everywhere).
  std::optional<Uniform> uniform() const override;
  void sample(const Eigen::Vector3d& origin_W, std::size_t n, const float* dx, const float* dy,
              const float* dz, const FluidSamples& out) const override;

 private:
  // The waves about a sampling origin: the dynamic pressure and its gradient there, the orbital velocity (computed
  // when the origin changes; a view serves one body at a time).
  struct WavesAbout {
    Eigen::Vector3d origin_W = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    double p_d = 0.0;
    Eigen::Vector3d grad_p_d = Eigen::Vector3d::Zero();
    Eigen::Vector3d v_orbital_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d a_orbital_W = Eigen::Vector3d::Zero();
  };
  const WavesAbout& waves_about(const Eigen::Vector3d& origin_W) const;
  // The current at the n points (sample()'s), into out's u arrays.
  void sample_currents(const Eigen::Vector3d& origin_W, std::size_t n, const float* dx, const float* dy,
                       const float* dz, const FluidSamples& out) const;

  const Ocean& ocean_;
  double time_;  // sim time for the currents and waves [s]
  mutable WavesAbout about_;
};

}  // namespace hadal::physics
