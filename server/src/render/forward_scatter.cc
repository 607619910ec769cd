#include "hadal/render/forward_scatter.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <array>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <utility>

#include "hadal/render/fast_math.h"

namespace hadal::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kIntervals = 2048;      // the PSF's tables
constexpr int kFinestBlockPx = 2;      // the finest level's blocks [px]; its ring is r < 3 s
constexpr double kRingBlocks = 3.0;    // then each level's ring is [1.5 s, 3 s)
constexpr int kSamplesPerAxis = 16;    // per block offset, over the two blocks' overlap (+-s)

}  // namespace

double hg_fraction_within(double g, double max_angle_rad) {
  if (!(max_angle_rad >= 0.0 && max_angle_rad <= kPi)) {
    throw std::invalid_argument("hg_fraction_within: the angle must be in [0, pi]");
  }
  const double mu = std::cos(max_angle_rad);
  if (std::abs(g) < 1e-9) return (1.0 - mu) / 2.0;
  const double f = (1.0 - g * g) / (2.0 * g) * (1.0 / (1.0 - g) - 1.0 / std::sqrt(1.0 + g * g - 2.0 * g * mu));
  return std::clamp(f, 0.0, 1.0);
}

Rgb forward_scattering_per_m(const WaterOptics& water) {
  if (!(water.forward_scatter_max_angle_rad > 0.0)) return Rgb::Zero();
  return water.scattering_per_m * hg_fraction_within(water.phase_g, water.forward_scatter_max_angle_rad);
}

ForwardScatterPsf::ForwardScatterPsf(double g, double max_angle_rad)
    : max_angle_rad_(max_angle_rad), step_rad_(max_angle_rad / kIntervals) {
  if (!(max_angle_rad > 0.0 && max_angle_rad <= kPi / 6.0)) {
    throw std::invalid_argument("forward scatter: the largest angle must be in (0, 30 deg]");
  }
  if (!(std::abs(g) < 1.0)) throw std::invalid_argument("forward scatter: phase g must be in (-1, 1)");
  // P(theta) up to the factor 1 / F, normalised below so that 2 pi int theta P = 1 on the tables.
  const auto p = [&](double theta) {
    const double sinc = theta > 0.0 ? std::sin(theta) / theta : 1.0;
    return henyey_greenstein(g, std::cos(theta)) * sinc;
  };
  q_.assign(kIntervals + 1, 0.0);
  m_.assign(kIntervals + 1, 0.0);
  double previous = p(0.0);
  for (int k = 1; k <= kIntervals; ++k) {
    const double theta = k * step_rad_, value = p(theta);
    q_[k] = q_[k - 1] + 0.5 * step_rad_ * (previous + value);
    m_[k] = m_[k - 1] + 0.5 * step_rad_ * ((theta - step_rad_) * previous + theta * value);
    previous = value;
  }
  const double norm = 2.0 * kPi * m_[kIntervals];
  for (int k = 0; k <= kIntervals; ++k) {
    q_[k] /= norm;
    m_[k] /= norm;
  }
}

double ForwardScatterPsf::tail(double alpha_rad) const {
  // Linear interpolation of Q between its nodes.
  const double x = std::clamp(alpha_rad / step_rad_, 0.0, static_cast<double>(kIntervals));
  const int k = std::min(static_cast<int>(x), kIntervals - 1);
  const double q = q_[k] + (x - k) * (q_[k + 1] - q_[k]);
  return q_[kIntervals] - q;
}

double ForwardScatterPsf::density_per_sr(double alpha_rad) const {
  if (!(alpha_rad > 0.0)) return std::numeric_limits<double>::infinity();
  if (alpha_rad >= max_angle_rad_) return 0.0;
  return tail(alpha_rad) / alpha_rad;
}

double ForwardScatterPsf::encircled(double alpha_rad) const {
  if (!(alpha_rad > 0.0)) return 0.0;
  if (alpha_rad >= max_angle_rad_) return 1.0;
  const double x = alpha_rad / step_rad_;
  const int k = std::min(static_cast<int>(x), kIntervals - 1);
  const double m = m_[k] + (x - k) * (m_[k + 1] - m_[k]);
  return 2.0 * kPi * (m + alpha_rad * tail(alpha_rad));
}

ForwardScatterKernel make_forward_scatter_kernel(const ForwardScatterPsf& psf, double fx_px, double fy_px) {
  if (!(fx_px > 0.0 && fy_px > 0.0 && std::isfinite(fx_px) && std::isfinite(fy_px))) {
    throw std::invalid_argument("forward scatter: focal lengths must be positive");
  }
  // Rings in r = alpha sqrt(fx fy) [px]: r < 6 at s = 2, then [1.5 s, 3 s) at s = 4, 8, ...
  const double f_px = std::sqrt(fx_px * fy_px);
  const double r_max = psf.max_angle_rad() * f_px;
  const double aspect = std::sqrt(std::max(fx_px, fy_px) / std::min(fx_px, fy_px));  // pixels per r, at most
  ForwardScatterKernel kernel;
  double total = 0.0;
  for (int s = kFinestBlockPx;; s *= 2) {
    const double r_lo = s == kFinestBlockPx ? 0.0 : 0.5 * kRingBlocks * s, r_hi = kRingBlocks * s;
    if (r_lo >= r_max) break;
    ForwardScatterKernel::Level level;
    level.block_px = s;
    level.reach = static_cast<int>(std::ceil((r_hi * aspect + s) / s));
    const int side = 2 * level.reach + 1;
    level.weight.assign(static_cast<std::size_t>(side) * side, 0.0);
    // Weight of the offset (dx, dy) blocks: int K_px(delta) (1 - |t_x| / s) (1 - |t_y| / s) d^2 delta over
    // delta = (dx s + t_x, dy s + t_y), |t| < s: light spread uniformly over one block, landing in the other.
    const double step = 2.0 * s / kSamplesPerAxis;
    for (int dy = -level.reach; dy <= level.reach; ++dy) {
      for (int dx = -level.reach; dx <= level.reach; ++dx) {
        double w = 0.0;
        for (int j = 0; j < kSamplesPerAxis; ++j) {
          const double ty = -s + (j + 0.5) * step;
          const double y = dy * s + ty;
          for (int i = 0; i < kSamplesPerAxis; ++i) {
            const double tx = -s + (i + 0.5) * step;
            const double x = dx * s + tx;
            const double alpha = std::hypot(x / fx_px, y / fy_px);
            const double r = alpha * f_px;
            if (r < r_lo || r >= r_hi) continue;
            w += psf.density_per_sr(alpha) / (fx_px * fy_px) * (1.0 - std::abs(tx) / s) * (1.0 - std::abs(ty) / s);
          }
        }
        w *= step * step;
        level.weight[static_cast<std::size_t>(dy + level.reach) * side + (dx + level.reach)] = w;
        total += w;
      }
    }
    kernel.levels.push_back(std::move(level));
  }
  // The 1/alpha peak at the centre is where sampling errs most: the centre block takes what the rest
  // leaves, so that the weights sum to 1 exactly.
  ForwardScatterKernel::Level& finest = kernel.levels.front();
  finest.weight[static_cast<std::size_t>(finest.reach) * (2 * finest.reach + 1) + finest.reach] += 1.0 - total;
  return kernel;
}

namespace {

// Planar single-precision images, one plane per channel; each row has `pad` zero cells on either side
// (a convolution's source: its taps then read zeros past the edges, and whole rows vectorize).
struct Planes {
  int width = 0, height = 0, pad = 0;
  std::size_t stride = 0;
  std::vector<float> c[3];
  Planes(int w, int h, int p = 0) : width(w), height(h), pad(p), stride(static_cast<std::size_t>(w) + 2 * p) {
    for (auto& plane : c) plane.assign(stride * h, 0.0f);
  }
  float* row(int ch, int y) { return c[ch].data() + static_cast<std::size_t>(y) * stride + pad; }
  const float* row(int ch, int y) const { return c[ch].data() + static_cast<std::size_t>(y) * stride + pad; }
};

constexpr int kRowsPerTask = 16;

void for_rows(int rows, const ParallelFor& parallel, const std::function<void(int, int)>& body) {
  const int tasks = (rows + kRowsPerTask - 1) / kRowsPerTask;
  parallel(static_cast<std::size_t>(tasks), [&](std::size_t t) {
    const int begin = static_cast<int>(t) * kRowsPerTask;
    body(begin, std::min(begin + kRowsPerTask, rows));
  });
}

struct Tap {
  int dx, dy;
  float weight;
};

// One row of a convolution (below): dst[x] += sum over taps of weight * sources[t][x] for x in [0, w),
// where sources[t] is the tap's source row shifted by its dx (read past the row's ends: the source's
// zero padding) and the taps are those whose source row exists; sixteen outputs at a time accumulate
// over all taps (one store each, not one per tap).
HADAL_VECTOR_KERNEL void convolve_row(const std::vector<Tap>& taps, const std::vector<const float*>& sources, int w,
                                      float* dst) {
  // GCC's vector extension: sixteen floats, one AVX-512 register, two AVX ones or four SSE ones (per
  // clone); unaligned loads and stores by memcpy. Lane by lane the sums of the scalar tail's order.
  typedef float Lanes __attribute__((vector_size(64)));
  constexpr int kLanes = 16;
  int x = 0;
  for (; x + kLanes <= w; x += kLanes) {
    Lanes acc = {}, s;
    for (std::size_t t = 0; t < taps.size(); ++t) {
      std::memcpy(&s, sources[t] + x, sizeof s);
      acc += taps[t].weight * s;
    }
    std::memcpy(&s, dst + x, sizeof s);
    s += acc;
    std::memcpy(dst + x, &s, sizeof s);
  }
  for (; x < w; ++x) {
    float sum = 0.0f;
    for (std::size_t t = 0; t < taps.size(); ++t) sum += taps[t].weight * sources[t][x];
    dst[x] += sum;
  }
}

// out += the level's weights applied to `in` (both w x h cells): out(x, y) = sum w(dx, dy) in(x - dx, y - dy).
// `in` is padded by at least the level's reach.
void convolve(const ForwardScatterKernel::Level& level, const Planes& in, Planes& out, const ParallelFor& parallel) {
  const int w = in.width, h = in.height, reach = level.reach, side = 2 * reach + 1;
  if (in.pad < reach) throw std::logic_error("forward scatter: a level's source padded less than its reach");
  std::vector<Tap> taps;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const float weight = static_cast<float>(level.weight[static_cast<std::size_t>(dy + reach) * side + (dx + reach)]);
      if (weight != 0.0f) taps.push_back({dx, dy, weight});
    }
  }
  for_rows(h, parallel, [&](int row_begin, int row_end) {
    std::vector<Tap> row_taps;
    std::vector<const float*> sources;
    for (int y = row_begin; y < row_end; ++y) {
      row_taps.clear();
      for (const Tap& tap : taps) {
        if (y - tap.dy >= 0 && y - tap.dy < h) row_taps.push_back(tap);
      }
      for (int ch = 0; ch < 3; ++ch) {
        sources.clear();
        for (const Tap& tap : row_taps) sources.push_back(in.row(ch, y - tap.dy) - tap.dx);
        convolve_row(row_taps, sources, w, out.row(ch, y));
      }
    }
  });
}

// dst[m] += row[2 m] + row[2 m + 1] (the sums in that order), for the width cells of a row.
HADAL_VECTOR_KERNEL void add_pairs(const float* row, int width, float* dst) {
  const int pairs = width / 2;
  for (int m = 0; m < pairs; ++m) {  // vectorized
    const float a = row[2 * m], b = row[2 * m + 1];
    dst[m] = (dst[m] + a) + b;
  }
  if (width % 2 != 0) dst[pairs] += row[width - 1];
}

// Sums over blocks of 2 x 2 cells of a grid of width x height cells (the last row and column of blocks
// may hold fewer), padded by `pad` zero cells; row(ch, y) is a row of cells.
template <typename Row>
Planes pair_sums(int width, int height, int pad, const ParallelFor& parallel, const Row& row) {
  Planes out((width + 1) / 2, (height + 1) / 2, pad);
  for_rows(out.height, parallel, [&](int row_begin, int row_end) {
    for (int ch = 0; ch < 3; ++ch) {
      for (int y = 2 * row_begin; y < std::min(2 * row_end, height); ++y) add_pairs(row(ch, y), width, out.row(ch, y / 2));
    }
  });
  return out;
}

// Per cell of a grid of `n` cells: the two cells of the grid half as fine (n2 = (n + 1) / 2 cells)
// whose centres bracket it, and the second's weight (bilinear; clamped at the edges).
struct Bracket {
  std::vector<int> lo, hi;
  std::vector<float> f;
  Bracket(int n, int n2) : lo(static_cast<std::size_t>(n)), hi(static_cast<std::size_t>(n)), f(static_cast<std::size_t>(n)) {
    for (int i = 0; i < n; ++i) {
      const double u = std::clamp((i + 0.5) / 2.0 - 0.5, 0.0, static_cast<double>(n2 - 1));
      lo[i] = std::min(static_cast<int>(u), n2 - 1);
      hi[i] = std::min(lo[i] + 1, n2 - 1);
      f[i] = static_cast<float>(u - lo[i]);
    }
  }
};

// dst[x] = src[lo[x]] + f[x] (src[hi[x]] - src[lo[x]]) for the width cells of a row twice as fine as src
// (Bracket's weights): interior cells in pairs, x = 2 m (lo m - 1, f 3/4) and 2 m + 1 (lo m, f 1/4), as
// Bracket gives them; the edges from Bracket itself.
HADAL_VECTOR_KERNEL void upsample_row(const Bracket& b, const float* src, int width, int coarse_width, float* dst) {
  const auto at = [&](int x) { dst[x] = src[b.lo[x]] + b.f[x] * (src[b.hi[x]] - src[b.lo[x]]); };
  // Pairs (2 m, 2 m + 1) with 1 <= m and m + 1 <= coarse_width - 1: both brackets inside the grid.
  const int pairs_end = std::min(coarse_width - 1, width / 2);
  at(0);
  if (width > 1) at(1);
  for (int m = 1; m < pairs_end; ++m) {  // vectorized
    const float left = src[m - 1], centre = src[m], right = src[m + 1];
    dst[2 * m] = left + 0.75f * (centre - left);
    dst[2 * m + 1] = centre + 0.25f * (right - centre);
  }
  for (int x = std::max(2, 2 * pairs_end); x < width; ++x) at(x);
}

// Adds `coarse` interpolated bilinearly between cell centres to each cell of a grid twice as fine, of
// width x height cells: add(y, row) receives row y's three channels (row[ch][x]).
template <typename Add>
void upsample(const Planes& coarse, int width, int height, const ParallelFor& parallel, const Add& add) {
  const Bracket bx(width, coarse.width), by(height, coarse.height);
  for_rows(height, parallel, [&](int row_begin, int row_end) {
    // Per channel, the last two coarse rows upsampled in x (fine rows 2 m and 2 m + 1 share row m).
    std::array<std::array<std::vector<float>, 2>, 3> kept;
    std::array<std::array<int, 2>, 3> kept_row;
    for (int ch = 0; ch < 3; ++ch) {
      for (auto& r : kept[ch]) r.resize(static_cast<std::size_t>(width));
      kept_row[ch] = {-1, -1};
    }
    // Coarse row cy of channel ch upsampled in x, without evicting coarse row `other`.
    const auto upsampled = [&](int ch, int cy, int other) -> const float* {
      for (int slot = 0; slot < 2; ++slot) {
        if (kept_row[ch][slot] == cy) return kept[ch][slot].data();
      }
      const int slot = kept_row[ch][0] == other ? 1 : 0;
      upsample_row(bx, coarse.row(ch, cy), width, coarse.width, kept[ch][slot].data());
      kept_row[ch][slot] = cy;
      return kept[ch][slot].data();
    };
    std::array<std::vector<float>, 3> row;
    for (auto& r : row) r.resize(static_cast<std::size_t>(width));
    for (int y = row_begin; y < row_end; ++y) {
      for (int ch = 0; ch < 3; ++ch) {
        const float* top = upsampled(ch, by.lo[y], by.hi[y]);
        const float* bottom = upsampled(ch, by.hi[y], by.lo[y]);
        const float fy = by.f[y];
        float* out = row[ch].data();
        for (int x = 0; x < width; ++x) out[x] = top[x] + fy * (bottom[x] - top[x]);
      }
      add(y, row);
    }
  });
}

// Cells of a grid of s x s px blocks over `pixels` px: s px each but the last, which may hold fewer.
float cell_px(int cell, int s, int pixels) { return static_cast<float>(std::min(s, pixels - cell * s)); }

// The kernel's processed-once tables, kept for the cameras of a run (a few at most).
std::mutex kernel_cache_mutex;
std::vector<std::pair<std::array<double, 4>, std::shared_ptr<const ForwardScatterKernel>>> kernel_cache;

}  // namespace

std::shared_ptr<const ForwardScatterKernel> forward_scatter_kernel(const WaterOptics& water, double fx_px, double fy_px) {
  const std::array<double, 4> key = {water.phase_g, water.forward_scatter_max_angle_rad, fx_px, fy_px};
  std::lock_guard<std::mutex> lock(kernel_cache_mutex);
  for (const auto& [k, kernel] : kernel_cache) {
    if (k == key) return kernel;
  }
  auto kernel = std::make_shared<const ForwardScatterKernel>(make_forward_scatter_kernel(
      ForwardScatterPsf(water.phase_g, water.forward_scatter_max_angle_rad), fx_px, fy_px));
  if (kernel_cache.size() >= 16) kernel_cache.erase(kernel_cache.begin());
  kernel_cache.emplace_back(key, kernel);
  return kernel;
}

void add_forward_scatter(const ForwardScatterKernel& kernel, int width, int height,
                         const std::array<std::vector<float>, 3>& source, std::vector<Eigen::Array3f>& radiance,
                         const ParallelFor& parallel) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (width < 1 || height < 1 || source[0].size() != n || source[1].size() != n || source[2].size() != n ||
      radiance.size() != n) {
    throw std::invalid_argument("add_forward_scatter: source and radiance must hold width x height pixels");
  }
  if (kernel.levels.empty()) throw std::invalid_argument("add_forward_scatter: a kernel without levels");
  for (std::size_t k = 0; k < kernel.levels.size(); ++k) {
    if (kernel.levels[k].block_px != (2 << k)) {
      throw std::invalid_argument("add_forward_scatter: the kernel's levels must be blocks of 2, 4, 8, ... px");
    }
  }
  // Each level's block sums are its finer neighbour's in pairs; each level's spread, as light per
  // pixel, is added to the next finer level's after interpolating the coarser ones' (coarsest first),
  // and the finest level's reaches the pixels the same way.
  std::vector<Planes> sums;  // sums[k]: blocks of 2^(k + 1) px
  sums.push_back(pair_sums(width, height, kernel.levels[0].reach, parallel, [&](int ch, int y) {
    return source[static_cast<std::size_t>(ch)].data() + static_cast<std::size_t>(y) * width;
  }));
  for (std::size_t k = 1; k < kernel.levels.size(); ++k) {
    const Planes& finer = sums.back();
    sums.push_back(pair_sums(finer.width, finer.height, kernel.levels[k].reach, k == 1 ? parallel : ParallelFor(serial_for),
                             [&](int ch, int y) { return finer.row(ch, y); }));
  }
  std::optional<Planes> coarser;  // the spread of the levels coarser than the current one, per pixel
  for (std::size_t k = kernel.levels.size(); k-- > 0;) {
    const Planes& blocks = sums[k];
    const int s = kernel.levels[k].block_px;
    // The two finest levels (blocks of 2 and 4 px: ~95 % of the work) on the workers, the rest on this
    // thread (a parallel loop's wake-up would cost more than their rows).
    const ParallelFor& level_parallel = k <= 1 ? parallel : ParallelFor(serial_for);
    Planes density(blocks.width, blocks.height);
    convolve(kernel.levels[k], blocks, density, level_parallel);
    for_rows(density.height, level_parallel, [&](int row_begin, int row_end) {
      for (int y = row_begin; y < row_end; ++y) {
        const float row_px = cell_px(y, s, height);
        for (int ch = 0; ch < 3; ++ch) {
          float* cells = density.row(ch, y);
          for (int x = 0; x < density.width; ++x) cells[x] /= row_px * cell_px(x, s, width);
        }
      }
    });
    if (coarser) {
      upsample(*coarser, density.width, density.height, level_parallel, [&](int y, const std::array<std::vector<float>, 3>& row) {
        for (int ch = 0; ch < 3; ++ch) {
          float* cells = density.row(ch, y);
          for (int x = 0; x < density.width; ++x) cells[x] += row[ch][x];
        }
      });
    }
    coarser = std::move(density);
  }
  upsample(*coarser, width, height, parallel, [&](int y, const std::array<std::vector<float>, 3>& row) {
    Eigen::Array3f* out = radiance.data() + static_cast<std::size_t>(y) * width;
    for (int x = 0; x < width; ++x) out[x] += Eigen::Array3f(row[0][x], row[1][x], row[2][x]);
  });
}

}  // namespace hadal::render
