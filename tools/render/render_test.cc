// Integration test of hadal-render as users run it: a scenario in, PNG files and a JSON line per camera
// out (read back here and checked against the closed form of tests/integration/scenarios/camera.yaml),
// or the documented exit codes.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_test_support.h"

namespace {

using hadal::test::Json;
using hadal::test::RunResult;

class RenderCliTest : public hadal::test::CliTest {
 protected:
  RunResult render(const std::string& args) const { return run(std::string(HADAL_RENDER) + " " + args); }
  static std::string scenario() { return std::string(HADAL_SOURCE_DIR) + "/tests/integration/scenarios/camera.yaml"; }
};

// The camera 10 m above the seabed looking down with the light at the camera, noise off: the pixels
// next to the image centre hold round(100 albedo / pi 2000 / 10^2 exp(-2 c 10)) = 117, 140, 128 (R, G,
// B; the PNG stores B, G, R), the depth PNG 10 000 mm everywhere.
TEST_F(RenderCliTest, WritesTheImageAndDepthOfEveryCamera) {
  const RunResult r = render(scenario() + " --time 0.1 --out " + dir_ + "/out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json line = parse(r.out);
  EXPECT_EQ(line["vehicle"].string, "auv");
  EXPECT_EQ(line["camera"].string, "camera");
  EXPECT_DOUBLE_EQ(line["time"].number, 0.1);
  EXPECT_EQ(line["width"].number, 160.0);
  EXPECT_EQ(line["encoding"].string, "rgb8");
  EXPECT_EQ(line["hit_fraction"].number, 1.0);
  const cv::Mat image = cv::imread(dir_ + "/out/auv_camera.png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(image.type(), CV_8UC3);
  ASSERT_EQ(image.cols, 160);
  ASSERT_EQ(image.rows, 120);
  const cv::Vec3b bgr = image.at<cv::Vec3b>(59, 79);
  const double albedo[3] = {0.5, 0.4, 0.3}, c[3] = {0.05, 0.03, 0.02};
  for (int ch = 0; ch < 3; ++ch) {
    const double L = albedo[ch] / M_PI * 2000.0 / 100.0 * std::exp(-2.0 * c[ch] * 10.0);
    EXPECT_EQ(bgr[2 - ch], static_cast<std::uint8_t>(std::round(100.0 * L))) << ch;
  }
  const cv::Mat depth = cv::imread(dir_ + "/out/auv_camera_depth.png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth.type(), CV_16UC1);
  EXPECT_EQ(depth.at<std::uint16_t>(59, 79), 10000);
  EXPECT_EQ(depth.at<std::uint16_t>(0, 0), 10000);
}

// An articulated vehicle's camera on a moving link (the work-class ROV's wrist camera): rendered where the
// arm holds it, in the world with the arm's bodies in it (the tool once passed the vehicles' poses only, which
// the ray-cast world, one body per moving part, refused).
TEST_F(RenderCliTest, RendersACameraOnAnArticulatedVehiclesArm) {
  const RunResult r = render(std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/rov_intervention.yaml --camera "
                             "wrist_camera --out " + dir_ + "/rov");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json line = parse(r.out);
  EXPECT_EQ(line["camera"].string, "wrist_camera");
  EXPECT_EQ(line["hit_fraction"].number, 1.0);
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/rov/rov_wrist_camera.png"));
}

TEST_F(RenderCliTest, ErrorsHaveTheDocumentedExitCodes) {
  // A camera that does not exist: 1, naming the cameras there are.
  RunResult r = render(scenario() + " --camera mast --out " + dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no camera named 'mast' (cameras: auv/camera)"), std::string::npos) << r.err;
  // A malformed scenario: 1 with file:line:col.
  const std::string bad = dir_ + "/bad.yaml";
  std::ofstream(bad) << "world: {physics_rate_hz: fast}\nvehicles: []\n";
  r = render(bad);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(bad + ":1:26: error: world.physics_rate_hz: expected a number (got 'fast')"), std::string::npos) << r.err;
  // Sonars only: 1, and the command that draws them (hadal-validate-sonar), naming them.
  const std::string sonars = std::string(HADAL_SOURCE_DIR) + "/tests/integration/scenarios/sonar.yaml";
  r = render(sonars + " --out " + dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("hadal-render: sonars auv/fls (fls), auv/multibeam (multibeam), auv/sidescan (sidescan) are "
                       "drawn by hadal-validate-sonar --scenario " + sonars + " --out DIR"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("the scenario has no camera"), std::string::npos) << r.err;
  // Usage: 2.
  EXPECT_EQ(render("").exit_code, 2);
  EXPECT_EQ(render(scenario() + " --time -1").exit_code, 2);
  EXPECT_EQ(render(scenario() + " --threads 1.5").exit_code, 2);
  EXPECT_TRUE(r.out.empty());
}

}  // namespace
