#include "hadal/render/sediment_pattern.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hadal/core/value_noise.h"

namespace hadal::render {
void validate(const SedimentPattern& pattern) {
  if (!(pattern.amplitude >= 0.0 && pattern.amplitude <= 1.0)) {
    throw std::invalid_argument("amplitude: must be in [0, 1]");
  }
  if (!(pattern.scale_m > 0.0) || !std::isfinite(pattern.scale_m)) throw std::invalid_argument("scale: must be > 0 [m]");
  if (pattern.octaves < 1 || pattern.octaves > 8) throw std::invalid_argument("octaves: must be in 1..8");
}

double sediment_noise(const SedimentPattern& pattern, double x_m, double y_m) {
  // The same values as noise::fbm, each thread remembering the last cell of every octave (a camera's
  // neighbouring pixels share them).
  thread_local noise::FbmMemo<noise::MixedLattice> fbm;
  return 0.5 * (fbm(pattern.seed, x_m / pattern.scale_m, y_m / pattern.scale_m, pattern.octaves) + 1.0);
}

Eigen::Array3d sediment_albedo(const SedimentPattern& pattern, const Eigen::Array3d& mean_albedo, double x_m,
                               double y_m) {
  if (!(pattern.amplitude > 0.0)) return mean_albedo;
  const double factor = 1.0 + pattern.amplitude * (2.0 * sediment_noise(pattern, x_m, y_m) - 1.0);
  const double brightest = mean_albedo.maxCoeff();
  return mean_albedo * std::clamp(factor, 0.0, brightest > 0.0 ? 1.0 / brightest : 1.0);
}

}  // namespace hadal::render
