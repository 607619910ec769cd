#include "hadal/geometry/terrain.h"

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <fstream>

namespace hadal::geometry {

HeightmapLoad load_heightmap(const HeightmapSpec& spec) {
  HeightmapLoad result;
  auto fail = [&](const std::string& problem) {
    result.error = spec.file + ": " + problem;
    return result;
  };
  if (!std::ifstream(spec.file).good()) return fail("cannot open heightmap (file not found)");
  if (!(spec.meters_per_pixel > 0.0) || !std::isfinite(spec.meters_per_pixel)) {
    return fail("meters_per_pixel must be > 0");
  }
  if (!(spec.height_max > spec.height_min)) return fail("height range must have max > min");
  cv::Mat image;
  try {
    image = cv::imread(spec.file, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    return fail(std::string("cannot decode image (") + e.what() + ")");
  }
  if (image.empty()) return fail("cannot decode image (not a PNG/TIFF OpenCV can read, or corrupt)");
  double full_scale = 0.0;
  if (image.depth() == CV_16U) {
    full_scale = 65535.0;
  } else if (image.depth() == CV_8U) {
    full_scale = 255.0;
  } else {
    return fail("unsupported pixel depth (use 8- or 16-bit unsigned single-channel images)");
  }
  if (image.cols < 2 || image.rows < 2) return fail("heightmap must be at least 2x2 pixels");

  HeightField field;
  field.nx = image.cols;
  field.ny = image.rows;
  field.dx = spec.meters_per_pixel;
  field.dy = spec.meters_per_pixel;
  field.x0 = -0.5 * (field.nx - 1) * field.dx;
  field.y0 = -0.5 * (field.ny - 1) * field.dy;
  field.heights.resize(static_cast<std::size_t>(field.nx) * field.ny);
  const double span = spec.height_max - spec.height_min;
  // Image row 0 is the top (north) edge: it becomes the largest y, so the map reads as seen from above.
  for (int row = 0; row < image.rows; ++row) {
    const int j = image.rows - 1 - row;
    for (int i = 0; i < image.cols; ++i) {
      const double value = image.depth() == CV_16U ? image.at<std::uint16_t>(row, i) : image.at<std::uint8_t>(row, i);
      field.heights[static_cast<std::size_t>(j) * field.nx + i] =
          static_cast<float>(spec.height_min + span * value / full_scale);
    }
  }
  result.field = std::move(field);
  return result;
}

}  // namespace hadal::geometry
