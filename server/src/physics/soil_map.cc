#include "hadal/physics/soil_map.h"

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <fstream>

namespace hadal::physics {

SoilMapLoad load_soil_region_map(const std::string& file, double meters_per_pixel, const Eigen::Vector2d& center_W,
                                 std::size_t num_regions) {
  SoilMapLoad result;
  const auto fail = [&](const std::string& problem) {
    result.error = file + ": " + problem;
    return result;
  };
  if (!std::ifstream(file).good()) return fail("cannot open soil map (file not found)");
  cv::Mat image;
  try {
    image = cv::imread(file, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    return fail(std::string("cannot decode image (") + e.what() + ")");
  }
  if (image.empty()) return fail("cannot decode image (not a PNG/TIFF OpenCV can read, or corrupt)");
  if (image.type() != CV_8UC1) {
    return fail("a soil map is an 8-bit single-channel image of region numbers (this one has " +
                std::to_string(image.channels()) + " channel(s) of " + (image.depth() == CV_8U ? "8" : "more than 8") +
                " bits)");
  }
  auto map = std::make_shared<SoilRegionMap>();
  map->columns = image.cols;
  map->rows = image.rows;
  map->meters_per_pixel = meters_per_pixel;
  map->center_W = center_W;
  map->index.resize(static_cast<std::size_t>(image.cols) * static_cast<std::size_t>(image.rows));
  for (int row = 0; row < image.rows; ++row) {
    for (int column = 0; column < image.cols; ++column) {
      const std::uint8_t value = image.at<std::uint8_t>(row, column);
      if (value > num_regions) {
        return fail("pixel (row " + std::to_string(row) + ", column " + std::to_string(column) + ") names region " +
                    std::to_string(value) + ", but there " + (num_regions == 1 ? "is " : "are ") +
                    std::to_string(num_regions) + (num_regions == 1 ? " region" : " regions") +
                    " (0 is the world's soil)");
      }
      map->index[static_cast<std::size_t>(row) * static_cast<std::size_t>(image.cols) + static_cast<std::size_t>(column)] =
          value;
    }
  }
  result.map = std::move(map);
  return result;
}

}  // namespace hadal::physics
