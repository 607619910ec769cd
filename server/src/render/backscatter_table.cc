#include "hadal/render/backscatter_table.h"

#include <algorithm>
#include <cmath>
#include <cstring>
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
    column_node_.push_back(static_cast<std::int32_t>(i));
    column_next_node_.push_back(static_cast<std::int32_t>(std::min(i + 1, node_u_.size() - 1)));
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
  // One float of padding: add_row's loads of the last node's last entry read one float past it.
  cumulative_.assign(3 * nodes() * static_cast<std::size_t>(samples + 1) + 1, 0.0f);
  parallel(node_v_.size(), [&](std::size_t row) {
    for (std::size_t col = 0; col < node_u_.size(); ++col) {
      const Eigen::Vector3d d_W = (R_WC * lens.ray_C(node_u_[col], node_v_[row]).cast<double>()).normalized();
      const std::size_t node = row * node_u_.size() + col;
      Rgb sum = Rgb::Zero();
      for (int k = 0; k < samples; ++k) {
        const Eigen::Vector3d x_W = p_WC + s[k] * d_W;
        Rgb from_lights = Rgb::Zero();
        for (const LightBeam& beam : beams) from_lights += backscatter_from_light(water, c, beam, x_W, d_W);
        sum += from_lights * weight[k];
        float* out = &cumulative_[entry(node, static_cast<std::size_t>(k) + 1)];
        for (int ch = 0; ch < 3; ++ch) out[ch] = static_cast<float>(sum[ch]);
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
  const float* lo = &cumulative_[entry(node, k)];
  const float* hi = &cumulative_[entry(node, k + 1)];
  Rgb value;
  for (int ch = 0; ch < 3; ++ch) value[ch] = lo[ch] + f * (static_cast<double>(hi[ch]) - lo[ch]);
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
  // Offsets in the table: of a node from its row's first, of the next node row, of the next s plane.
  const std::size_t plane = 3 * nodes();
  const float* row0 = &cumulative_[entry(node_row * columns, 0)];
  const std::size_t next_row_offset = 3 * (next_row - node_row) * columns;
  const float s0 = static_cast<float>(s0_), s_max = static_cast<float>(s_max_);
  const float scale = static_cast<float>(samples_ / log_ratio_), inv_s0 = static_cast<float>(1.0 / s0_);
  const std::int32_t last_interval = samples_ - 1;
  const std::size_t width = column_node_.size();
  constexpr std::size_t kChunk = 64;
  float position[kChunk];  // in the s grid, 0..samples
  float add_r[kChunk], add_g[kChunk], add_b[kChunk];
  for (std::size_t begin = 0; begin < width; begin += kChunk) {
    const std::size_t count = std::min(kChunk, width - begin);
    for (std::size_t j = 0; j < count; ++j) {  // the logs, vectorized
      const float s = fast::max(s0, fast::min(s_end[begin + j], s_max));
      position[j] = fast::max(0.0f, scale * fast::log(s * inv_s0));
    }
    // The four nodes around each pixel, interpolated bilinearly and in s, one pixel at a time, its three
    // channels in the lanes of one 4-float vector (GCC's vector extension: SSE on every x86-64 clone;
    // the fourth lane reads the next float of the table, padded at its end, and is ignored). For the
    // interval k of the s grid and the node column i of the pixel, the value is linear in the column
    // weight wu and in the position f inside the interval:
    //   value = (A + wu dA) + f (D + wu dD),
    // with A, A + dA the node columns' values at the interval's start, interpolated between the node
    // rows, and D, D + dD their increments over the interval. A row's neighbouring pixels mostly share
    // (i, k): the four vectors are computed (eight loads) when it changes, and kept while it does not.
    typedef float Rgbx __attribute__((vector_size(16)));
    const auto load = [](const float* p) {
      Rgbx v;
      std::memcpy(&v, p, sizeof v);
      return v;
    };
    std::int32_t kept_k = -1, kept_column = -1;
    Rgbx A = {}, dA = {}, D = {}, dD = {};
    for (std::size_t j = 0; j < count; ++j) {
      const float t = position[j], wu = column_weight_[begin + j];
      // The interval of the s grid and the position in it: the same for the four nodes around (u, v).
      const std::int32_t k = std::min(static_cast<std::int32_t>(t), last_interval);
      const float f = t - static_cast<float>(k);
      const std::int32_t column = column_node_[begin + j];
      if (k != kept_k || column != kept_column) {
        kept_k = k;
        kept_column = column;
        const float* p0 = row0 + static_cast<std::size_t>(k) * plane;  // plane k, node row below
        const float* p1 = p0 + next_row_offset;                         // plane k, node row after
        const std::size_t o0 = 3 * static_cast<std::size_t>(column);
        const std::size_t o1 = 3 * static_cast<std::size_t>(column_next_node_[begin + j]);
        const Rgbx a00 = load(p0 + o0), b00 = load(p0 + plane + o0), a10 = load(p0 + o1), b10 = load(p0 + plane + o1);
        const Rgbx a01 = load(p1 + o0), b01 = load(p1 + plane + o0), a11 = load(p1 + o1), b11 = load(p1 + plane + o1);
        const Rgbx start0 = (1.0f - wv) * a00 + wv * a01, start1 = (1.0f - wv) * a10 + wv * a11;
        const Rgbx end0 = (1.0f - wv) * b00 + wv * b01, end1 = (1.0f - wv) * b10 + wv * b11;
        A = start0;
        dA = start1 - start0;
        D = end0 - start0;
        dD = (end1 - start1) - D;
      }
      const float keep = s_end[begin + j] > s0 ? 1.0f : 0.0f;  // beyond the start of the water's path only
      const Rgbx out = keep * ((A + wu * dA) + f * (D + wu * dD));
      add_r[j] = out[0];
      add_g[j] = out[1];
      add_b[j] = out[2];
    }
    // Added to the row's sums afterwards, vectorized (not three scalar read-modify-writes per pixel).
    float* __restrict out_r = r + begin;
    float* __restrict out_g = g + begin;
    float* __restrict out_b = b + begin;
    for (std::size_t j = 0; j < count; ++j) {
      out_r[j] += add_r[j];
      out_g[j] += add_g[j];
      out_b[j] += add_b[j];
    }
  }
}

}  // namespace hadal::render
