// The run summary's wording (app::RunSummary::format) and the start-up warnings of a mode (app::mode_warnings).
#include "server_loop.h"

#include "hadal/sensors/sensor_kinds.h"

#include <gtest/gtest.h>

#include <string>

namespace hadal::app {
namespace {

// A static vehicle never moves: the summary says "static" instead of distances (which would only be
// Bullet's round-off); a moving one keeps its distances.
TEST(RunSummaryTest, AStaticVehicleIsSaidStaticWithoutDistances) {
  RunSummary summary;
  summary.vehicles.push_back({"auv", 48.113, 48.112, 9.413, false});
  summary.vehicles.push_back({"rocks", 0.0, 0.0, 0.7, true});
  const std::string text = summary.format();
  EXPECT_NE(text.find("  auv: distance travelled 48.113 m (net displacement 48.112 m), altitude 9.413 m\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("  rocks: static, altitude 0.700 m\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("rocks: distance"), std::string::npos) << text;
}

// In real time, a captured sensor whose latency rounds to 0 physics steps publishes nothing: said once per
// sensor; not in the other modes, and not for a latency of one step.
TEST(ModeWarningsTest, AZeroLatencyCapturedSensorIsWarnedAboutInRealTimeOnly) {
  Model model;
  model.world.physics_rate_hz = 500.0;
  VehicleSpec& auv = model.vehicles.emplace_back();
  auv.name = "auv";
  SensorSpec camera;
  camera.name = "camera";
  camera.rate_hz = 10.0;
  camera.kind = sensors::CameraSensor::Spec{};
  camera.latency_s = 0.0;
  auv.sensors.push_back(camera);
  SensorSpec imu;
  imu.name = "imu";
  imu.kind = sensors::ImuSensor::Spec{};
  auv.sensors.push_back(imu);  // not captured: never a latency warning
  const std::vector<std::string> warnings = mode_warnings(model, RunMode::kRealtime);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("auv/camera: latency_s 0 s is less than one physics step", 0), 0u) << warnings[0];
  EXPECT_NE(warnings[0].find("leave latency_s out for one sample period, 0.1 s"), std::string::npos) << warnings[0];
  EXPECT_TRUE(mode_warnings(model, RunMode::kLockstep).empty());
  EXPECT_TRUE(mode_warnings(model, RunMode::kFast).empty());
  model.vehicles[0].sensors[0].latency_s = 0.002;  // one step at 500 Hz
  EXPECT_TRUE(mode_warnings(model, RunMode::kRealtime).empty());
}

// A real-time run at 10 status periods per second that stalls for one period and catches up in the next:
// that period alone reads RTF 2, the reported window of 1 s reads the schedule's 1.00 (hadal-viewer showed
// 1.93 while hadald's line said 1.00). A fast run at 3x reads 3; a reset forgets the samples.
TEST(RtfWindowTest, TheReportedRealTimeFactorIsOverTheLastSecond) {
  RtfWindow window;
  EXPECT_EQ(window.rtf(), 0.0);
  double sim = 0.0;
  for (int k = 0; k <= 20; ++k) {
    if (k == 15) {
      // stalled: sim time did not advance in this period
    } else if (k == 16) {
      sim += 0.2;  // caught up
    } else if (k > 0) {
      sim += 0.1;
    }
    window.add(0.1 * k, sim);
    if (k == 16) {
      EXPECT_NEAR(window.rtf(), 1.0, 1e-12);  // (1.6 - 0.6) / (1.6 - 0.6): the last second
    }
  }
  EXPECT_NEAR(window.rtf(), 1.0, 1e-12);
  window.clear();
  for (int k = 0; k <= 30; ++k) window.add(0.1 * k, 0.3 * k);
  EXPECT_NEAR(window.rtf(), 3.0, 1e-12);
}

}  // namespace
}  // namespace hadal::app
