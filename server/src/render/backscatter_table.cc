#include "hadal/render/backscatter_table.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hadal::render {
namespace {

// Pixel coordinates 0, grid, 2 grid, ... below size - 1, then size - 1.
std::vector<int> node_list(int size, int grid) {
  std::vector<int> nodes;
  for (int x = 0; x < size - 1; x += grid) nodes.push_back(x);
  nodes.push_back(size - 1);
  return nodes;
}

}  // namespace

BackscatterTable::BackscatterTable(const WaterOptics& water, const std::vector<SpotLight>& lights, const Lens& lens,
                                   const Eigen::Isometry3d& X_WC, double s0, double s_max, int samples, int grid_px,
                                   const ParallelFor& parallel)
    : grid_(grid_px), samples_(samples), s0_(s0), s_max_(s_max) {
  if (!(s0 > 0.0 && s_max > s0 && std::isfinite(s_max)) || samples < 1 || grid_px < 1) {
    throw std::invalid_argument("backscatter table: need 0 < s0 < s_max (finite), samples >= 1, grid >= 1 px");
  }
  log_ratio_ = std::log(s_max / s0);
  if (lights.empty() || (water.scattering_per_m == 0.0).all()) return;
  node_u_ = node_list(lens.width_px(), grid_px);
  node_v_ = node_list(lens.height_px(), grid_px);

  // The grid in s, shared by every node: midpoints s_k and the camera-side factor exp(-c s_k) ds_k.
  const Rgb c = water.attenuation_per_m();
  std::vector<double> s(static_cast<std::size_t>(samples));
  std::vector<Rgb> weight(static_cast<std::size_t>(samples));
  for (int k = 0; k < samples; ++k) {
    s[k] = s0 * std::exp(log_ratio_ * (k + 0.5) / samples);
    weight[k] = transmittance(c, s[k]) * (s[k] * log_ratio_ / samples);
  }
  const std::vector<LightBeam> beams(lights.begin(), lights.end());
  const Eigen::Matrix3d R_WC = X_WC.linear();
  const Eigen::Vector3d p_WC = X_WC.translation();
  const std::size_t stride = 3 * static_cast<std::size_t>(samples + 1);
  cumulative_.assign(nodes() * stride, 0.0f);
  parallel(node_v_.size(), [&](std::size_t row) {
    for (std::size_t col = 0; col < node_u_.size(); ++col) {
      const Eigen::Vector3d d_W = (R_WC * lens.ray_C(node_u_[col], node_v_[row]).cast<double>()).normalized();
      float* out = &cumulative_[(row * node_u_.size() + col) * stride];
      Rgb sum = Rgb::Zero();
      for (int k = 0; k < samples; ++k) {
        const Eigen::Vector3d x_W = p_WC + s[k] * d_W;
        Rgb from_lights = Rgb::Zero();
        for (const LightBeam& beam : beams) from_lights += backscatter_from_light(water, c, beam, x_W, d_W);
        sum += from_lights * weight[k];
        for (int ch = 0; ch < 3; ++ch) out[3 * (k + 1) + ch] = static_cast<float>(sum[ch]);
      }
    }
  });
}

void BackscatterTable::locate(const std::vector<int>& nodes, int x, std::size_t* below, double* weight) const {
  if (nodes.size() == 1) {
    *below = 0;
    *weight = 0.0;
    return;
  }
  // Nodes are grid_ apart, the last interval possibly shorter.
  const std::size_t i = std::min(static_cast<std::size_t>(x / grid_), nodes.size() - 2);
  *below = i;
  *weight = std::clamp(static_cast<double>(x - nodes[i]) / (nodes[i + 1] - nodes[i]), 0.0, 1.0);
}

Rgb BackscatterTable::cumulative(std::size_t node, std::size_t k, double f) const {
  const std::size_t stride = 3 * static_cast<std::size_t>(samples_ + 1);
  const float* lo = &cumulative_[node * stride + 3 * k];
  Rgb value;
  for (int ch = 0; ch < 3; ++ch) value[ch] = lo[ch] + f * (static_cast<double>(lo[3 + ch]) - lo[ch]);
  return value;
}

Rgb BackscatterTable::at(int u, int v, double s_end) const {
  if (node_u_.empty()) return Rgb::Zero();
  const double s = std::clamp(s_end, s0_, s_max_);
  const double t = samples_ * std::log(s / s0_) / log_ratio_;  // position in the s grid, 0..samples
  // The interval of the s grid and the position in it: the same for the four nodes.
  const std::size_t k = std::min(static_cast<std::size_t>(t), static_cast<std::size_t>(samples_ - 1));
  const double f = t - static_cast<double>(k);
  std::size_t i, j;
  double wu, wv;
  locate(node_u_, u, &i, &wu);
  locate(node_v_, v, &j, &wv);
  const std::size_t columns = node_u_.size();
  const std::size_t i1 = std::min(i + 1, columns - 1), j1 = std::min(j + 1, node_v_.size() - 1);
  return (1.0 - wv) * ((1.0 - wu) * cumulative(j * columns + i, k, f) + wu * cumulative(j * columns + i1, k, f)) +
         wv * ((1.0 - wu) * cumulative(j1 * columns + i, k, f) + wu * cumulative(j1 * columns + i1, k, f));
}

}  // namespace hadal::render
