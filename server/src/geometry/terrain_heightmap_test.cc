#include "hadal/geometry/terrain.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace hadal::geometry {
namespace {

std::string temp_path(const std::string& name) {
  return "/tmp/hadal-heightmap-" + std::to_string(::getpid()) + "-" + name;
}

TEST(HeightmapTest, SixteenBitPngMapsPixelValuesLinearlyOntoTheHeightRange) {
  // 4 x 3 pixels; row 0 is the north (largest y) edge.
  cv::Mat image(3, 4, CV_16UC1);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) image.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(r * 20000 + c * 1000);
  }
  image.at<std::uint16_t>(2, 3) = 65535;
  const std::string path = temp_path("a.png");
  ASSERT_TRUE(cv::imwrite(path, image));

  const HeightmapLoad load = load_heightmap({path, 2.0, -120.0, -100.0});
  std::remove(path.c_str());
  ASSERT_TRUE(load.field) << load.error;
  const HeightField& f = *load.field;
  EXPECT_EQ(f.nx, 4);
  EXPECT_EQ(f.ny, 3);
  EXPECT_DOUBLE_EQ(f.dx, 2.0);
  EXPECT_DOUBLE_EQ(f.x0, -3.0);  // centred: (nx - 1) dx / 2
  EXPECT_DOUBLE_EQ(f.y0, -2.0);
  // Pixel (row 0, col 2) = 2000 is the north edge: j = ny - 1. Heights are floats (7 digits): 1e-4 m.
  EXPECT_NEAR(f.height(2, 2), -120.0 + 20.0 * 2000.0 / 65535.0, 1e-4);
  EXPECT_NEAR(f.height(3, 0), -100.0, 1e-4);  // 65535 -> height_max
  EXPECT_NEAR(f.height(0, 0), -120.0 + 20.0 * 40000.0 / 65535.0, 1e-4);
}

TEST(HeightmapTest, EightBitImagesUse255AsFullScale) {
  cv::Mat image(2, 2, CV_8UC1, cv::Scalar(255));
  image.at<std::uint8_t>(1, 0) = 0;
  const std::string path = temp_path("b.png");
  ASSERT_TRUE(cv::imwrite(path, image));
  const HeightmapLoad load = load_heightmap({path, 1.0, -50.0, -40.0});
  std::remove(path.c_str());
  ASSERT_TRUE(load.field) << load.error;
  EXPECT_NEAR(load.field->height(0, 0), -50.0, 1e-5);
  EXPECT_NEAR(load.field->height(1, 1), -40.0, 1e-5);
}

TEST(HeightmapTest, BadInputIsAClearError) {
  EXPECT_EQ(load_heightmap({"/nonexistent/h.png", 1.0, -10.0, 0.0}).error,
            "/nonexistent/h.png: cannot open heightmap (file not found)");
  const std::string garbage = temp_path("c.png");
  std::ofstream(garbage) << "not an image at all";
  EXPECT_EQ(load_heightmap({garbage, 1.0, -10.0, 0.0}).error,
            garbage + ": cannot decode image (not a PNG/TIFF OpenCV can read, or corrupt)");
  std::remove(garbage.c_str());

  const std::string tiny = temp_path("d.png");
  ASSERT_TRUE(cv::imwrite(tiny, cv::Mat(1, 5, CV_16UC1, cv::Scalar(7))));
  EXPECT_EQ(load_heightmap({tiny, 1.0, -10.0, 0.0}).error, tiny + ": heightmap must be at least 2x2 pixels");
  EXPECT_EQ(load_heightmap({tiny, 0.0, -10.0, 0.0}).error, tiny + ": meters_per_pixel must be > 0");
  EXPECT_EQ(load_heightmap({tiny, 1.0, 0.0, -10.0}).error, tiny + ": height range must have max > min");
  std::remove(tiny.c_str());
}

}  // namespace
}  // namespace hadal::geometry
