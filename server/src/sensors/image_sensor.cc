#include "hadal/sensors/image_sensor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hadal/sensors/noise.h"
#include "hadal/core/validation_error.h"

namespace hadal::sensors {
namespace {

constexpr double kExactPoissonBelow = 30.0;  // electrons (header)
constexpr double kMergeSigmas = 6.0;         // shot and read noise drawn as one normal (header)

using validation::invalid;

// Poisson variate of mean mu (header): inversion of the cumulative distribution below 30, the normal
// approximation above, never negative.
double poisson(RandomStream& stream, double mu) {
  if (mu <= 0.0) return 0.0;
  if (mu < kExactPoissonBelow) {
    const double u = stream.uniform();
    double p = std::exp(-mu), cumulative = p;
    int k = 0;
    while (u >= cumulative && k < 1000) {
      ++k;
      p *= mu / k;
      cumulative += p;
    }
    return k;
  }
  return std::max(0.0, mu + std::sqrt(mu) * stream.ziggurat_normal());
}

}  // namespace

void validate(const ImageSensorSpec& spec) {
  if (!spec.sensitivity.allFinite() || !(spec.sensitivity > 0.0).all()) invalid("sensitivity", "must be positive per channel");
  if (!(spec.exposure_s > 0.0) || !std::isfinite(spec.exposure_s)) invalid("exposure_s", "must be positive [s]");
  if (!(spec.gain_dn_per_e > 0.0) || !std::isfinite(spec.gain_dn_per_e)) invalid("gain", "must be positive [DN/e-]");
  if (!(spec.full_well_e > 0.0) || !std::isfinite(spec.full_well_e)) invalid("full_well_e", "must be positive [e-]");
  if (!(spec.read_noise_e >= 0.0) || !std::isfinite(spec.read_noise_e)) invalid("read_noise_e", "must be >= 0 [e-]");
}

std::vector<std::uint8_t> expose_rgb8(const ImageSensorSpec& spec, const std::vector<Eigen::Array3d>& radiance,
                                      const std::vector<float>& cos_theta, std::uint64_t key, std::uint64_t frame_index,
                                      const ParallelFor& parallel) {
  validate(spec);
  if (cos_theta.size() != radiance.size()) throw std::invalid_argument("expose_rgb8: one cos_theta per pixel needed");
  std::vector<std::uint8_t> rgb(3 * radiance.size());
  const std::string frame = "frame " + std::to_string(frame_index) + " block ";
  const std::size_t blocks = (radiance.size() + kExposureBlockPixels - 1) / kExposureBlockPixels;
  const Eigen::Array3d scale = spec.sensitivity * spec.exposure_s;  // electrons per W/(m^2 sr)
  const double read_variance = spec.read_noise_e * spec.read_noise_e;
  parallel(blocks, [&](std::size_t block) {
    RandomStream stream(derive_key(key, frame + std::to_string(block)));
    const std::size_t end = std::min(radiance.size(), (block + 1) * kExposureBlockPixels);
    for (std::size_t i = block * kExposureBlockPixels; i < end; ++i) {
      double falloff = 1.0;
      if (spec.vignetting) {
        const double c = std::max(0.0, static_cast<double>(cos_theta[i]));
        falloff = (c * c) * (c * c);
      }
      for (int ch = 0; ch < 3; ++ch) {
        const double mu = scale[ch] * std::max(0.0, radiance[i][ch]) * falloff;
        double electrons = 0.0;
        if (spec.shot_noise && mu >= kExactPoissonBelow && mu + kMergeSigmas * std::sqrt(mu) <= spec.full_well_e) {
          // Shot and read noise in one draw (header): the clips at 0 and at the full well lie beyond
          // kMergeSigmas sigma, so the sum of the two normals is the whole story.
          electrons = mu + std::sqrt(mu + read_variance) * stream.ziggurat_normal();
        } else {
          electrons = std::min(spec.shot_noise ? poisson(stream, mu) : mu, spec.full_well_e);
          if (spec.read_noise_e > 0.0) electrons += spec.read_noise_e * stream.ziggurat_normal();
        }
        const double dn = std::clamp(spec.gain_dn_per_e * electrons, 0.0, 255.0);
        rgb[3 * i + ch] = static_cast<std::uint8_t>(dn + 0.5);  // round half up (dn >= 0)
      }
    }
  });
  return rgb;
}

}  // namespace hadal::sensors
