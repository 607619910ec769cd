// Base-colour texture sampling: the sRGB transfer function's closed form, texel centres, bilinear
// weights and repeat wrapping.
#include "hadal/render/texture.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hadal::render {
namespace {

// A 3 x 2 RGB texture; texel (i, j) = (10 i + 40 j, 200 - 50 i, 7 j).
geometry::Texture small_texture(int channels = 3) {
  geometry::Texture t;
  t.width = 3;
  t.height = 2;
  t.channels = channels;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 3; ++i) {
      t.pixels.push_back(static_cast<std::uint8_t>(10 * i + 40 * j));
      t.pixels.push_back(static_cast<std::uint8_t>(200 - 50 * i));
      t.pixels.push_back(static_cast<std::uint8_t>(7 * j));
      if (channels == 4) t.pixels.push_back(255);
    }
  }
  return t;
}

Rgb texel(int i, int j) {
  return Rgb(srgb_to_linear((10 * i + 40 * j) / 255.0), srgb_to_linear((200 - 50 * i) / 255.0),
             srgb_to_linear(7 * j / 255.0));
}

TEST(TextureTest, SrgbDecodingFollowsIec61966) {
  EXPECT_EQ(srgb_to_linear(0.0), 0.0);
  EXPECT_DOUBLE_EQ(srgb_to_linear(1.0), 1.0);
  EXPECT_DOUBLE_EQ(srgb_to_linear(0.04), 0.04 / 12.92);                      // linear segment
  EXPECT_DOUBLE_EQ(srgb_to_linear(0.5), std::pow(0.555 / 1.055, 2.4));     // 0.2140
  EXPECT_NEAR(srgb_to_linear(0.5), 0.2140, 1e-4);
  // The two pieces meet at 0.04045 (to 1e-7: the standard's rounded constants).
  EXPECT_NEAR(0.04045 / 12.92, std::pow((0.04045 + 0.055) / 1.055, 2.4), 1e-7);
}

TEST(TextureTest, TexelCentresBilinearWeightsAndRepeat) {
  for (int channels : {3, 4}) {
    const geometry::Texture t = small_texture(channels);
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 3; ++i) {
        const float u = (i + 0.5f) / 3.0f, v = 1.0f - (j + 0.5f) / 2.0f;  // texel (i, j)'s centre
        EXPECT_TRUE(((sample_texture(t, u, v) - texel(i, j)).abs() < 1e-6).all()) << i << " " << j;
        // Repeat: one period away in u and in v is the same texel.
        EXPECT_TRUE(((sample_texture(t, u + 1.0f, v - 2.0f) - texel(i, j)).abs() < 1e-6).all());
      }
    }
    // A quarter of the way from texel (0, 0) to (1, 0), and halfway down to row 1.
    const float u = (0.5f + 0.25f) / 3.0f, v = 1.0f - 1.0f / 2.0f;
    const Rgb expected = 0.5 * (0.75 * texel(0, 0) + 0.25 * texel(1, 0)) + 0.5 * (0.75 * texel(0, 1) + 0.25 * texel(1, 1));
    EXPECT_TRUE(((sample_texture(t, u, v) - expected).abs() < 1e-6).all());
    // Left of texel 0's centre the weights wrap to the last column.
    const Rgb wrapped = 0.5 * texel(2, 0) + 0.5 * texel(0, 0);
    EXPECT_TRUE(((sample_texture(t, 0.0f, 1.0f - 0.25f) - wrapped).abs() < 1e-6).all());
  }
  geometry::Texture gray;
  gray.width = gray.height = 1;
  gray.channels = 1;
  gray.pixels = {9};
  EXPECT_THROW(sample_texture(gray, 0.5f, 0.5f), std::invalid_argument);
}

}  // namespace
}  // namespace hadal::render
