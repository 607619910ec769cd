// Shared by the render module's tests: a plate to look at, calibrations used throughout, and OpenCV's projection of points
// in the optical frame with the same K and D (the reference the lens and camera tests compare with).
#pragma once

#include <opencv2/calib3d.hpp>

#include <atomic>
#include <functional>
#include <thread>
#include <vector>

#include "hadal/geometry/triangle_mesh.h"
#include "hadal/render/lens.h"

namespace hadal::render::testing {

// A parallel loop on two threads (the test's and one more), tasks taken in turn: for checking that a result
// does not depend on the threads.
inline void two_threads(std::size_t count, const std::function<void(std::size_t)>& task) {
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i = next++; i < count; i = next++) task(i);
  };
  std::thread helper(work);
  work();
  helper.join();
}

// A square plate perpendicular to x_W at x [m], centred on (y, z), half size h [m], its front face
// towards -x.
inline geometry::TriangleMesh plate(float x, float y, float z, float h) {
  geometry::TriangleMesh m;
  m.positions = {x, y - h, z - h, x, y + h, z - h, x, y + h, z + h, x, y - h, z + h};
  m.indices = {0, 2, 1, 0, 3, 2};
  return m;
}

// An undistorted lens with an off-centre principal point and non-square pixels, 640 x 480.
inline LensSpec pinhole_lens() {
  LensSpec l;
  l.fx = 512.3;
  l.fy = 508.9;
  l.cx = 322.7;
  l.cy = 236.1;
  return l;
}

// Barrel distortion of a wide-angle underwater housing: strong negative k1, small tangential terms.
inline LensSpec barrel_lens() {
  LensSpec l = pinhole_lens();
  l.model = LensModel::kRadialTangential;
  l.distortion = {-0.28, 0.09, 1.2e-3, -6.0e-4, -0.01};
  return l;
}

// A fisheye whose image corners see 76 deg off the axis.
inline LensSpec fisheye_lens() {
  LensSpec l;
  l.fx = 300.0;
  l.fy = 299.2;
  l.cx = 318.4;
  l.cy = 241.6;
  l.model = LensModel::kEquidistant;
  l.distortion = {0.03, -0.012, 0.004, -0.0006, 0.0};
  return l;
}

// cv::projectPoints (pinhole, plumb_bob) or cv::fisheye::projectPoints (equidistant) of points given
// in the optical frame (identity pose).
inline std::vector<cv::Point2d> opencv_project(const LensSpec& l, const std::vector<cv::Point3d>& points_C) {
  std::vector<cv::Point2d> pixels;
  const cv::Mat K = (cv::Mat_<double>(3, 3) << l.fx, 0.0, l.cx, 0.0, l.fy, l.cy, 0.0, 0.0, 1.0);
  const cv::Mat zero = cv::Mat::zeros(3, 1, CV_64F);
  if (l.model == LensModel::kEquidistant) {
    const cv::Mat D = (cv::Mat_<double>(4, 1) << l.distortion[0], l.distortion[1], l.distortion[2], l.distortion[3]);
    cv::fisheye::projectPoints(points_C, pixels, zero, zero, K, D);
  } else {
    const cv::Mat D = (cv::Mat_<double>(1, 5) << l.distortion[0], l.distortion[1], l.distortion[2], l.distortion[3],
                       l.distortion[4]);
    cv::projectPoints(points_C, zero, zero, K, D, pixels);
  }
  return pixels;
}

}  // namespace hadal::render::testing
