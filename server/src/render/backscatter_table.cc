#include "hadal/render/backscatter_table.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hadal/render/fast_math.h"

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
  for (int u = 0; u < lens.width_px(); ++u) {
    std::size_t i;
    double w;
    locate(node_u_, u, &i, &w);
    column_node_.push_back(static_cast<std::uint32_t>(i));
    column_weight_.push_back(static_cast<float>(w));
  }

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

HADAL_VECTOR_KERNEL void BackscatterTable::add_row(int v, const float* s_end, float* r, float* g, float* b) const {
  if (node_u_.empty()) return;
  std::size_t node_row;
  double wv_d;
  locate(node_v_, v, &node_row, &wv_d);
  const float wv = static_cast<float>(wv_d);
  const std::size_t columns = node_u_.size();
  const std::size_t next_row = std::min(node_row + 1, node_v_.size() - 1);
  const std::size_t stride = 3 * static_cast<std::size_t>(samples_ + 1);
  const float* row0 = &cumulative_[node_row * columns * stride];
  const float* row1 = &cumulative_[next_row * columns * stride];
  const float s0 = static_cast<float>(s0_), s_max = static_cast<float>(s_max_);
  const float scale = static_cast<float>(samples_ / log_ratio_), inv_s0 = static_cast<float>(1.0 / s0_);
  const std::size_t last_interval = static_cast<std::size_t>(samples_ - 1);
  const std::size_t width = column_node_.size();
  constexpr std::size_t kChunk = 64;
  float position[kChunk];  // in the s grid, 0..samples
  for (std::size_t begin = 0; begin < width; begin += kChunk) {
    const std::size_t count = std::min(kChunk, width - begin);
    for (std::size_t j = 0; j < count; ++j) {  // the logs, vectorized
      const float s = fast::max(s0, fast::min(s_end[begin + j], s_max));
      position[j] = fast::max(0.0f, scale * fast::log(s * inv_s0));
    }
    for (std::size_t j = 0; j < count; ++j) {
      const std::size_t u = begin + j;
      if (!(s_end[u] > s0)) continue;
      // The interval of the s grid and the position in it: the same for the four nodes around (u, v).
      const std::size_t k = std::min(static_cast<std::size_t>(position[j]), last_interval);
      const float f = position[j] - static_cast<float>(k);
      const std::size_t i = column_node_[u], i1 = std::min(i + 1, columns - 1);
      const float wu = column_weight_[u];
      const float* n00 = row0 + i * stride + 3 * k;
      const float* n10 = row0 + i1 * stride + 3 * k;
      const float* n01 = row1 + i * stride + 3 * k;
      const float* n11 = row1 + i1 * stride + 3 * k;
      float out[3];
      for (int ch = 0; ch < 3; ++ch) {
        const float v00 = n00[ch] + f * (n00[3 + ch] - n00[ch]), v10 = n10[ch] + f * (n10[3 + ch] - n10[ch]);
        const float v01 = n01[ch] + f * (n01[3 + ch] - n01[ch]), v11 = n11[ch] + f * (n11[3 + ch] - n11[ch]);
        out[ch] = (1.0f - wv) * ((1.0f - wu) * v00 + wu * v10) + wv * ((1.0f - wu) * v01 + wu * v11);
      }
      r[u] += out[0];
      g[u] += out[1];
      b[u] += out[2];
    }
  }
}

}  // namespace hadal::render
