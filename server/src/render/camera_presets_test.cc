// The camera presets: each one's lens is usable (its ray table inverts the distortion inside the image)
// and reports exactly the published numbers; a downscaled calibration projects points where OpenCV
// puts them with the full-size calibration, scaled.
#include "hadal/render/camera_presets.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "render_test_support.h"

namespace hadal::render {
namespace {

LensSpec calibration(std::string_view id) { return config::find_preset(camera_presets(), id)->figures; }

TEST(CameraPresetsTest, EveryPresetMakesALensWithItsPublishedCalibration) {
  std::set<std::string> ids;
  for (const config::Preset<LensSpec>& preset : camera_presets()) {
    SCOPED_TRACE(std::string(preset.id));
    ids.insert(std::string(preset.id));
    const Lens lens = make_lens(preset.figures);
    EXPECT_LT(lens.max_reprojection_error_px(), 1e-3);
    EXPECT_EQ(lens.K()[0], preset.figures.fx);
    EXPECT_EQ(lens.K()[2], preset.figures.cx);
    EXPECT_EQ(lens.K()[4], preset.figures.fy);
    EXPECT_EQ(lens.K()[5], preset.figures.cy);
    EXPECT_EQ(lens.D()[0], preset.figures.distortion[0]);
  }
  EXPECT_EQ(ids.size(), camera_presets().size());  // unique ids
  // Spot checks against the sources (camera_presets.cc).
  EXPECT_EQ(calibration("svin2_stereo_rig_v2_left").distortion[0], -0.17473019446863114);
  EXPECT_EQ(calibration("subpipe_gopro_hero10").width_px, 2704);
  EXPECT_EQ(config::find_preset(camera_presets(), "no_such_camera"), nullptr);
}

// Downscaling by s: a point seen at pixel p by the full-size calibration (cv::projectPoints) is seen
// at (p + 0.5) / s - 0.5 by the downscaled one; within 1e-9 px.
TEST(CameraPresetsTest, DownscaledCalibrationProjectsAsTheScaledImage) {
  for (const char* name : {"svin2_stereo_rig_v2_left", "subpipe_gopro_hero10"}) {
    SCOPED_TRACE(name);
    const LensSpec full = calibration(name);
    const double s = std::string(name) == "svin2_stereo_rig_v2_left" ? 2.5 : 2.0;
    const LensSpec small = downscaled(full, s);
    EXPECT_EQ(small.width_px * s, full.width_px);
    EXPECT_EQ(small.height_px * s, full.height_px);
    std::vector<cv::Point3d> points;
    for (double x : {-0.6, 0.0, 0.4}) {
      for (double y : {-0.3, 0.2}) points.emplace_back(x, y, 1.0);
    }
    const std::vector<cv::Point2d> a = testing::opencv_project(full, points);
    const std::vector<cv::Point2d> b = testing::opencv_project(small, points);
    for (std::size_t i = 0; i < points.size(); ++i) {
      EXPECT_NEAR(b[i].x, (a[i].x + 0.5) / s - 0.5, 1e-9);
      EXPECT_NEAR(b[i].y, (a[i].y + 0.5) / s - 0.5, 1e-9);
    }
  }
  EXPECT_THROW(downscaled(calibration("subpipe_gopro_hero10"), 3.0), std::invalid_argument);  // 2704 / 3
  EXPECT_THROW(downscaled(calibration("subpipe_gopro_hero10"), 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace hadal::render
