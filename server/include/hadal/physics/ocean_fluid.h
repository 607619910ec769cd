// OceanFluid: the scenario's water column (physics::Ocean) at one sim time, as the surface
// hydrodynamics kernel samples it (FluidSampler).
//
//   surface_z_W        Ocean::surface_z
//   gauge_pressure(z)  p(d) - p_atm with d = surface_z - z, 0 above the surface
//   gravity_magnitude  Ocean::gravity
//   sample             rho(d_i); dp_i = p_g(z_i) - p_g(z_origin), both gauge pressures evaluated in
//                      double before the difference is rounded to float (no cancellation of the
//                      absolute 6e7 Pa at 6000 m); current v(p_i, time) from Ocean::sample_current.
// Points are evaluated one by one through Ocean::density / Ocean::pressure (exact for every density
// model); cheap next to the face loop for the constant and ramp models.
// A view: holds a reference to the Ocean, which must outlive it. Units SI.
#pragma once

#include "hadal/physics/ocean.h"
#include "hadal/physics/surface_hydrodynamics.h"

namespace hadal::physics {

class OceanFluid final : public FluidSampler {
 public:
  OceanFluid(const Ocean& ocean, double time) : ocean_(ocean), time_(time) {}

  double surface_z_W() const override { return ocean_.surface_z(); }
  double gauge_pressure(double z_W) const override;
  double gravity_magnitude() const override { return ocean_.gravity(); }
  void sample(const Eigen::Vector3d& origin_W, std::size_t n, const float* dx, const float* dy,
              const float* dz, const FluidSamples& out) const override;

 private:
  const Ocean& ocean_;
  double time_;  // sim time for the currents [s]
};

}  // namespace hadal::physics
