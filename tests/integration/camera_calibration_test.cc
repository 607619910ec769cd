// Calibration round trip, as a user would do it (issue 11): configs/scenarios/camera_calibration.yaml
// runs in a real hadald; the frames published on rt/rig/camera/image_raw go through OpenCV's
// cv::findChessboardCorners and cv::calibrateCamera, which must recover the configured calibration:
// fx, fy, cx, cy within 0.5 % and k1 within 5 % (the bounds), from 15 or more usable frames.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

#include "lockstep_server.h"

namespace hadal::test {
namespace {

TEST(CameraCalibrationTest, OpenCvRecoversTheConfiguredCalibrationFromPublishedFrames) {
  LockstepServer s("configs/scenarios/camera_calibration.yaml");
  SampleLog<Image> images;
  s.client().on_image("rig", "camera", [&](const Image& m) { images.add(m); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  const double t = s.client().step(4000);  // 20 s at 200 Hz: 40 frames at 2 Hz
  // Each frame is published one frame period (0.5 s, the default latency_s) after its snapshot: the last one
  // out by t is the snapshot of t - 0.5 s.
  ASSERT_TRUE(wait_until([&] { return images.has(t - 0.5); }, kWait));

  // The target: 10 x 7 squares of 0.12 m, so 9 x 6 inner corners (the scenario's comment).
  const cv::Size pattern(9, 6);
  std::vector<cv::Point3f> board;
  for (int row = 0; row < pattern.height; ++row) {
    for (int column = 0; column < pattern.width; ++column) board.emplace_back(0.12f * column, 0.12f * row, 0.0f);
  }
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  int frames = 0;
  for (const auto& [stamp, image] : images.all()) {
    ++frames;
    ASSERT_EQ(image.encoding, "rgb8");
    const cv::Mat rgb(static_cast<int>(image.height), static_cast<int>(image.width), CV_8UC3,
                      const_cast<std::uint8_t*>(image.data.data()), image.step);
    cv::Mat gray;
    cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);
    std::vector<cv::Point2f> corners;
    if (!cv::findChessboardCorners(gray, pattern, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE)) {
      continue;
    }
    cv::cornerSubPix(gray, corners, cv::Size(5, 5), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
    image_points.push_back(corners);
    object_points.push_back(board);
  }
  std::printf("%d frames, %zu with the whole checkerboard found\n", frames, image_points.size());
  ASSERT_GE(image_points.size(), 15u);

  cv::Mat K, D;
  std::vector<cv::Mat> rvecs, tvecs;
  const double rms = cv::calibrateCamera(object_points, image_points, cv::Size(640, 480), K, D, rvecs, tvecs,
                                         cv::CALIB_FIX_K3);
  const double fx = K.at<double>(0, 0), fy = K.at<double>(1, 1), cx = K.at<double>(0, 2), cy = K.at<double>(1, 2);
  const double k1 = D.at<double>(0), k2 = D.at<double>(1);
  std::printf("recovered: fx %.3f fy %.3f cx %.3f cy %.3f k1 %.5f k2 %.5f p1 %.2e p2 %.2e, rms %.3f px\n", fx, fy, cx,
              cy, k1, k2, D.at<double>(2), D.at<double>(3), rms);
  EXPECT_NEAR(fx, 520.0, 0.005 * 520.0);
  EXPECT_NEAR(fy, 515.0, 0.005 * 515.0);
  EXPECT_NEAR(cx, 322.0, 0.005 * 322.0);
  EXPECT_NEAR(cy, 236.0, 0.005 * 236.0);
  EXPECT_NEAR(k1, -0.18, 0.05 * 0.18);
}

}  // namespace
}  // namespace hadal::test
