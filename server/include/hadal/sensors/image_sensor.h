// A camera's image sensor: scene radiance per pixel to 8-bit counts, with the noise of a real sensor
// (the linear camera model of EMVA 1288), seeded so that the same seed and frame give the same image.
//
// Per pixel and channel (R, G, B), with L the radiance reaching the lens [W/(m^2 sr)] and theta the
// angle of the pixel's ray off the optical axis:
//   mean electrons   mu = sensitivity * L * exposure_s * cos^4(theta)      (cos^4: natural vignetting)
//   shot noise       Poisson(mu): drawn exactly (inversion) below 30 electrons, as mu + sqrt(mu) N(0,1)
//                    above (the normal approximation's error there is below 1 % of sigma)
//   full well        electrons clipped to full_well_e
//   read noise       + read_noise_e N(0,1)
//   counts           DN = gain_dn_per_e * electrons clipped to [0, 255], rounded half up
// 'sensitivity' [electrons per second per W/(m^2 sr)] lumps the lens (f-number, transmission), the pixel
// area, the quantum efficiency and the photon energy of each channel: it is the one figure to fit to a
// real camera's exposure. Noise off (shot_noise false, read_noise_e 0) gives the rounded mean.
//
// Where mu >= 30 and the full well is at least 6 sigma above mu, shot and read noise are one normal
// draw, mu + sqrt(mu + read_noise_e^2) N(0,1): the sum of the two independent normals, exact while
// neither clip can act (each is beyond 5.4 sigma: probability < 1e-7 per pixel). Half the draws on a
// well-exposed frame.
//
// Random numbers are counter-based, not streams: sample j = 3 pixel + channel of frame k draws
// 32-bit hashes mix32(K ^ j C) (hadal/core/value_noise.h; C odd, so distinct samples get distinct
// hashes) under four keys K of the frame, from splitmix64 of the camera's noise key
// (channel_key(seed, vehicle, camera, "image")) and k. Its normal N(0,1) is Box and Muller's
// sqrt(-2 ln u1) cos(2 pi u2) from two of them (u in (0, 1) from the top 24 bits: the tails stop at
// 5.8 sigma, a probability of 7e-9); where the Poisson variate is needed, it inverts a third uniform
// (or, above 30 electrons near the full well, takes a fourth normal), and its read noise is the first
// normal. So a pixel's noise depends on nothing but the seed, the frame and where it is: exposed in any
// order, on any threads, the image is the same; the per-channel passes run vectorized
// (render/fast_math.h's functions: the same bits on every x86-64 CPU).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "hadal/core/parallel_for.h"
#include "hadal/sensors/camera_spec.h"

namespace hadal::sensors {



// Radiance [W/(m^2 sr)] per channel below which a change of the scene's radiance moves the mean count
// of any pixel by less than `counts`: counts / (gain_dn_per_e sensitivity exposure_s) (vignetting and
// the full well only lower the count's slope). The camera's renderer leaves out daylight that adds
// less than kNegligibleCounts' worth (render/frame.h, "Negligible daylight"): a twentieth of a count,
// under a fifth of the rounding's own rms error (1/sqrt(12) count) and far below the daylight model's
// own uncertainty where daylight is that faint (a 1 % error in Kd at 100 m is a 14 % error in
// daylight). In the default scenario (96 m, Jerlov III, lights set to fill the counts) daylight's bound
// is at most 0.023 counts, so it is left out of every band.
constexpr double kNegligibleCounts = 0.05;
Eigen::Array3d negligible_radiance(const ImageSensorSpec& spec, double counts = kNegligibleCounts);

// Throws std::invalid_argument naming the field: sensitivity, exposure, gain, full well must be
// positive and finite, read noise >= 0.
void validate(const ImageSensorSpec& spec);

// Counts of one frame: `radiance` and `cos_theta` (the z of each pixel's unit ray in the optical frame,
// render::Lens::rays_C) per pixel, row-major; returns rgb8, 3 bytes per pixel. `key` is the camera's
// noise key (channel_key(seed, vehicle, camera, "image")), `frame_index` the frame's number.
constexpr std::size_t kExposureBlockPixels = 8192;  // pixels per task of the parallel loop
constexpr std::size_t kMaxExposurePixels = (std::size_t{1} << 32) / 3;  // j must fit in 32 bits
std::vector<std::uint8_t> expose_rgb8(const ImageSensorSpec& spec, const std::vector<Eigen::Array3f>& radiance,
                                      const std::vector<float>& cos_theta, std::uint64_t key, std::uint64_t frame_index,
                                      const ParallelFor& parallel = serial_for);

}  // namespace hadal::sensors
