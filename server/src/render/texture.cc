#include "hadal/render/texture.h"

#include <array>
#include <cmath>
#include <stdexcept>

namespace hadal::render {
namespace {

// srgb_to_linear of the 256 8-bit codes.
const std::array<double, 256>& linear_of_code() {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (int k = 0; k < 256; ++k) t[static_cast<std::size_t>(k)] = srgb_to_linear(k / 255.0);
    return t;
  }();
  return table;
}

// a mod n in [0, n).
int wrap(long a, int n) {
  const long r = a % n;
  return static_cast<int>(r < 0 ? r + n : r);
}

}  // namespace

double srgb_to_linear(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

Rgb sample_texture(const geometry::Texture& texture, float u, float v) {
  const int w = texture.width, h = texture.height, channels = texture.channels;
  if (w < 1 || h < 1 || (channels != 3 && channels != 4) ||
      texture.pixels.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(channels)) {
    throw std::invalid_argument("sample_texture: need an RGB or RGBA texture of at least one texel");
  }
  // Continuous texel coordinates with texel centres at integers.
  const double x = static_cast<double>(u) * w - 0.5, y = (1.0 - static_cast<double>(v)) * h - 0.5;
  const double x_floor = std::floor(x), y_floor = std::floor(y);
  const double fx = x - x_floor, fy = y - y_floor;
  const int x0 = wrap(static_cast<long>(x_floor), w), x1 = wrap(static_cast<long>(x_floor) + 1, w);
  const int y0 = wrap(static_cast<long>(y_floor), h), y1 = wrap(static_cast<long>(y_floor) + 1, h);
  const std::array<double, 256>& linear = linear_of_code();
  const auto texel = [&](int column, int row) {
    const std::uint8_t* p = &texture.pixels[(static_cast<std::size_t>(row) * w + column) * channels];
    return Rgb(linear[p[0]], linear[p[1]], linear[p[2]]);
  };
  return (1.0 - fy) * ((1.0 - fx) * texel(x0, y0) + fx * texel(x1, y0)) +
         fy * ((1.0 - fx) * texel(x0, y1) + fx * texel(x1, y1));
}

}  // namespace hadal::render
