#include "image_preview.h"

#include <cstdint>

namespace hadal::dds {

bool half_resolution(const sensor_msgs::msg::Image& in, sensor_msgs::msg::Image* out) {
  std::uint32_t channels = 0;
  if (in.encoding() == "rgb8" || in.encoding() == "bgr8") channels = 3;
  if (in.encoding() == "mono8") channels = 1;
  const std::uint64_t width = in.width(), height = in.height(), step = in.step();
  if (channels == 0 || width < 2 || height < 2 || step < width * channels || in.data().size() < step * height) {
    return false;
  }
  const std::uint32_t w = in.width() / 2, h = in.height() / 2;
  out->header(in.header());
  out->encoding(in.encoding());
  out->is_bigendian(in.is_bigendian());
  out->width(w);
  out->height(h);
  out->step(w * channels);
  std::vector<std::uint8_t>& data = out->data();
  data.resize(static_cast<std::size_t>(w) * h * channels);
  const std::uint8_t* src = in.data().data();
  for (std::uint32_t v = 0; v < h; ++v) {
    const std::uint8_t* row0 = src + (2 * v) * step;
    const std::uint8_t* row1 = row0 + step;
    std::uint8_t* dst = data.data() + static_cast<std::size_t>(v) * w * channels;
    for (std::uint32_t u = 0; u < w; ++u) {
      for (std::uint32_t c = 0; c < channels; ++c) {
        const std::uint32_t k = 2 * u * channels + c;
        dst[u * channels + c] =
            static_cast<std::uint8_t>((row0[k] + row0[k + channels] + row1[k] + row1[k + channels] + 2) / 4);
      }
    }
  }
  return true;
}

}  // namespace hadal::dds
