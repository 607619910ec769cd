// The GPS kind alone (no Bullet): a fix only above the water at the geodetic position of the antenna,
// NO_FIX below it, its noise and its message.
#include "hadal/sensors/gps_sensor.h"

#include <gtest/gtest.h>
#include <sensor_msgs.h>

#include <cmath>

#include "hadal/sensors/magnetometer.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::SensorTestWorld;

SensorTestWorld world_with_vehicle_at(double z) {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(120.0, -40.0, z));
  model.world.origin.latitude_rad = 43.0 * kDegToRad;
  model.world.origin.longitude_rad = 5.0 * kDegToRad;
  return SensorTestWorld(model);
}

GpsSensor::Spec exact() {
  GpsSensor::Spec spec;
  spec.horizontal_stddev = 0.0;
  spec.vertical_stddev = 0.0;
  return spec;
}

// With the antenna above the water (on a 0.5 m mast, the vehicle's origin 0.6 m under the surface) a fix
// at the geodetic position of the antenna (W = the local ENU frame at world.origin), agreeing with the
// magnetometer's own exact ECEF geodesy to 1e-12 deg; under water NO_FIX with NaN.
TEST(GpsSensorTest, FixesOnlyAboveTheWater) {
  SensorTestWorld world = world_with_vehicle_at(-0.4);
  GpsSensor::State state = world.initial_state<GpsSensor>(exact(), 10.0);
  world.sample<GpsSensor>(exact(), state, pose(Eigen::Vector3d(0, 0, 1.4)), 10.0);
  ASSERT_TRUE(state.fix);
  const LocalEnuFrame frame({43.0 * kDegToRad, 5.0 * kDegToRad, 0.0});
  const GeodeticPosition expected = frame.to_geodetic(Eigen::Vector3d(120.0, -40.0, 1.0));
  EXPECT_NEAR(state.latitude_deg, expected.latitude_rad / kDegToRad, 1e-12);
  EXPECT_NEAR(state.longitude_deg, expected.longitude_rad / kDegToRad, 1e-12);
  EXPECT_NEAR(state.height_m, expected.height_m, 1e-6);

  world.sample<GpsSensor>(exact(), state, pose(Eigen::Vector3d(0, 0, 0.3)), 10.0);  // antenna 0.1 m under
  EXPECT_FALSE(state.fix);
  EXPECT_TRUE(std::isnan(state.latitude_deg));
}

// In regular waves (0.5 m, 6 s) an antenna 0.2 m above the mean surface is awash under every crest: it has a fix
// exactly when it is above the instantaneous surface there, loses it under a crest and gets it back in the trough.
TEST(GpsSensorTest, AwashUnderACrestItLosesItsFixAndGetsItBack) {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(120.0, -40.0, -0.3));
  model.world.waves.spectrum = physics::WaveSpectrum::kRegular;
  model.world.waves.regular = {{0.5, 6.0, 0.3, 0.0}};
  model.world.waves.ramp_time = 0.0;  // the full sea from t = 0
  SensorTestWorld world(model);
  GpsSensor::State state = world.initial_state<GpsSensor>(exact(), 10.0);
  int fixes = 0, lost = 0, regained = 0;
  bool before = true;
  for (int k = 0; k < 120; ++k) {  // 12 s, two periods
    world.state.time = 0.1 * k;
    world.sample<GpsSensor>(exact(), state, pose(Eigen::Vector3d(0, 0, 0.5)), 10.0);
    const double eta = world.ocean.surface_height(120.0, -40.0, world.state.time);
    EXPECT_EQ(state.fix, 0.2 > eta) << "t = " << world.state.time << " s, surface at " << eta << " m";
    fixes += state.fix;
    lost += before && !state.fix;
    regained += !before && state.fix;
    before = state.fix;
  }
  EXPECT_GT(fixes, 40);
  EXPECT_LT(fixes, 100);
  EXPECT_GE(lost, 2);  // once under each crest (and at the start when it begins under one)
  EXPECT_GE(regained, 2);
}

// Horizontal noise of 2 m per axis: sample stddev of the east offset over 4000 fixes within
// 4 sigma / sqrt(2 n) = 4.5 % (plus 0.5 % for the rough metres-per-degree scale); the streams advance
// under water too, so fixes after a dive are those of a run that never dived.
TEST(GpsSensorTest, NoiseSpreadAndStreamsThatAdvanceUnderWater) {
  SensorTestWorld world = world_with_vehicle_at(1.0);
  GpsSensor::Spec spec = exact();
  spec.horizontal_stddev = 2.0;
  GpsSensor::State state = world.initial_state<GpsSensor>(spec, 1.0);
  GpsSensor::State reference = world.initial_state<GpsSensor>(exact(), 1.0);
  world.sample<GpsSensor>(exact(), reference, Eigen::Isometry3d::Identity(), 1.0);
  const int n = 4000;
  const double metres_per_deg_lon = 111319.49 * std::cos(43.0 * kDegToRad);
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    world.sample<GpsSensor>(spec, state, Eigen::Isometry3d::Identity(), 1.0);
    const double east = (state.longitude_deg - reference.longitude_deg) * metres_per_deg_lon;
    sum += east;
    sum2 += east * east;
  }
  const double stddev = std::sqrt(sum2 / n - (sum / n) * (sum / n));
  EXPECT_NEAR(stddev, 2.0, 4.0 * 2.0 / std::sqrt(2.0 * n) + 0.01);

  GpsSensor::State surfaced = world.initial_state<GpsSensor>(spec, 1.0);
  GpsSensor::State dived = world.initial_state<GpsSensor>(spec, 1.0);
  SensorTestWorld under = world_with_vehicle_at(-5.0);
  for (int k = 0; k < 3; ++k) {
    world.sample<GpsSensor>(spec, surfaced, Eigen::Isometry3d::Identity(), 1.0);
    under.sample<GpsSensor>(spec, dived, Eigen::Isometry3d::Identity(), 1.0);
  }
  world.sample<GpsSensor>(spec, surfaced, Eigen::Isometry3d::Identity(), 1.0);
  world.sample<GpsSensor>(spec, dived, Eigen::Isometry3d::Identity(), 1.0);
  EXPECT_EQ(dived.latitude_deg, surfaced.latitude_deg);
  EXPECT_EQ(dived.longitude_deg, surfaced.longitude_deg);
}

// sensor_msgs/NavSatFix: STATUS_FIX with the position, or STATUS_NO_FIX with NaN; diagonal ENU
// covariance of the configured noise, DIAGONAL_KNOWN.
TEST(GpsSensorTest, Message) {
  GpsSensor::Spec spec;
  GpsSensor::State state;
  state.fix = true;
  state.latitude_deg = 43.001;
  state.longitude_deg = 5.002;
  state.height_m = 48.5;
  sensor_msgs::msg::NavSatFix msg;
  const std::string frame = "auv/gps";
  GpsSensor::fill_message(spec, state, MessageHeader{7.0, frame, 1.0}, msg);
  EXPECT_EQ(msg.status().status(), sensor_msgs::msg::NavSatStatus_Constants::STATUS_FIX);
  EXPECT_EQ(msg.latitude(), 43.001);
  EXPECT_EQ(msg.position_covariance()[0], 1.5 * 1.5);
  EXPECT_EQ(msg.position_covariance()[8], 9.0);
  EXPECT_EQ(msg.position_covariance_type(), sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_DIAGONAL_KNOWN);
  state.fix = false;
  GpsSensor::fill_message(spec, state, MessageHeader{8.0, frame, 1.0}, msg);
  EXPECT_EQ(msg.status().status(), sensor_msgs::msg::NavSatStatus_Constants::STATUS_NO_FIX);
  EXPECT_TRUE(std::isnan(msg.longitude()));
}

}  // namespace
}  // namespace hadal::sensors
