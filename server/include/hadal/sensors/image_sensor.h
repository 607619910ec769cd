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
// Random streams of frame k: one per block of kExposureBlockPixels pixels in row-major order,
// derive_key(key, "frame <k> block <j>") (sensors/noise.h), drawn pixel by pixel, R, G, B; a pixel
// draws its Poisson variate first, then its read noise (or the one merged draw); normals are
// RandomStream::ziggurat_normal. Blocks are independent tasks of a parallel loop, so the image does not
// depend on the threads that expose it.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "hadal/core/parallel_for.h"

namespace hadal::sensors {

struct ImageSensorSpec {
  Eigen::Array3d sensitivity = Eigen::Array3d::Constant(2.0e5);  // [e- / s / (W/(m^2 sr))] per channel
  double exposure_s = 0.01;
  double gain_dn_per_e = 0.05;  // counts per electron (analog gain)
  double full_well_e = 10000.0;
  double read_noise_e = 3.0;  // rms [electrons]
  bool shot_noise = true;
  bool vignetting = true;  // the cos^4 law
};

// Throws std::invalid_argument naming the field: sensitivity, exposure, gain, full well must be
// positive and finite, read noise >= 0.
void validate(const ImageSensorSpec& spec);

// Counts of one frame: `radiance` and `cos_theta` (the z of each pixel's unit ray in the optical frame,
// render::Lens::rays_C) per pixel, row-major; returns rgb8, 3 bytes per pixel. `key` is the camera's
// noise key (channel_key(seed, vehicle, camera, "image")), `frame_index` the frame's number.
constexpr std::size_t kExposureBlockPixels = 8192;
std::vector<std::uint8_t> expose_rgb8(const ImageSensorSpec& spec, const std::vector<Eigen::Array3d>& radiance,
                                      const std::vector<float>& cos_theta, std::uint64_t key, std::uint64_t frame_index,
                                      const ParallelFor& parallel = serial_for);

}  // namespace hadal::sensors
