// Camera previews (dds/image_preview.h): each pixel the rounded mean of its 2 x 2 block, channels kept apart,
// an odd last row and column dropped, the header and encoding kept; what cannot be previewed is refused.
#include "image_preview.h"

#include <gtest/gtest.h>

namespace hadal::dds {
namespace {

TEST(ImagePreviewTest, HalvesAnRgbImageByBlockMeans) {
  sensor_msgs::msg::Image in;
  in.header().frame_id("auv/camera_optical");
  in.header().stamp().sec(3);
  in.encoding("rgb8");
  in.width(5);  // the odd fifth column is dropped
  in.height(2);
  in.step(5 * 3 + 1);  // a padded row
  in.data(std::vector<std::uint8_t>(in.step() * 2, 0));
  // Block (0, 0): red 0, 10, 20, 31 -> 15.25 -> 15; green 255 everywhere; blue 1, 2, 1, 2 -> 1.5 -> 2.
  const std::uint8_t red[4] = {0, 10, 20, 31}, blue[4] = {1, 2, 1, 2};
  for (int k = 0; k < 4; ++k) {
    const std::size_t at = (k / 2) * in.step() + (k % 2) * 3;
    in.data()[at] = red[k];
    in.data()[at + 1] = 255;
    in.data()[at + 2] = blue[k];
  }
  sensor_msgs::msg::Image out;
  ASSERT_TRUE(half_resolution(in, &out));
  EXPECT_EQ(out.width(), 2u);
  EXPECT_EQ(out.height(), 1u);
  EXPECT_EQ(out.step(), 6u);
  EXPECT_EQ(out.encoding(), "rgb8");
  EXPECT_EQ(out.header(), in.header());
  EXPECT_EQ(out.data(), (std::vector<std::uint8_t>{15, 255, 2, 0, 0, 0}));
}

TEST(ImagePreviewTest, RefusesWhatItCannotHalve) {
  sensor_msgs::msg::Image in, out;
  in.encoding("32FC1");
  in.width(4);
  in.height(4);
  in.step(16);
  in.data(std::vector<std::uint8_t>(64, 0));
  EXPECT_FALSE(half_resolution(in, &out));
  in.encoding("mono8");
  in.step(4);
  EXPECT_TRUE(half_resolution(in, &out));
  in.height(100);  // rows the data does not hold
  EXPECT_FALSE(half_resolution(in, &out));
  in.height(1);
  EXPECT_FALSE(half_resolution(in, &out));
}

}  // namespace
}  // namespace hadal::dds
