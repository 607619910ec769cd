// Marine snow: the organic particles that drift in the deep sea and glitter in a vehicle's lights
// (docs/ARCHITECTURE.md, "Cameras"). A seeded field of small particles fixed in the world (one per cubic
// cell of side (1 / density)^(1/3), at a hashed position in its cell, with a hashed radius), so that
// the same seed gives the same particles in every frame and they stream past with parallax as the
// camera moves.
//
// Per frame, every particle within max_range of the camera and in front of what the pixel sees (its
// depth) adds the light it scatters back: a Lambertian sphere of albedo `albedo` lit by each light,
// seen through the water, as a disc of its projected size (sub-pixel discs add their area's share to
// one pixel). Particles are not shadowed and cast no shadows; they do not occlude the backscatter.
//   radiance added  = albedo / pi  sum_l I_l(u) / r_l^2 exp(-c r_l)  exp(-c d)  min(1, disc area [px^2])
//   (d the particle's distance from the camera, r_l from light l).
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

#include "hadal/core/parallel_for.h"
#include "hadal/render/lens.h"
#include "hadal/render/optics.h"
#include "hadal/render/optics_spec.h"

namespace hadal::render {

// Throws std::invalid_argument naming the field: density >= 0 (at most 1e5 /m^3), radius > 0, range > 0,
// albedo in [0, 1].
void validate(const MarineSnow& snow);

// Adds the particles' radiance to `radiance` (row-major, lens-sized), not where `depth_m` (metres along
// the optical axis, NaN: nothing hit) is nearer. Returns the number of particles drawn. Slabs of cells
// are the tasks of `parallel`; the sums are the same whatever the threads.
std::size_t add_marine_snow(const MarineSnow& snow, const Lens& lens, const Eigen::Isometry3d& X_WC,
                            const WaterOptics& water, const std::vector<SpotLight>& lights,
                            const std::vector<float>& depth_m, std::vector<Eigen::Array3f>& radiance,
                            const ParallelFor& parallel = serial_for);

}  // namespace hadal::render
