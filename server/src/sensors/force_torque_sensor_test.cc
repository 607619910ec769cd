// The force/torque kind alone (no Bullet): the joint's wrench moved to the sensor's frame and origin, its
// direction, its noise, and its message. The joint's wrench itself is checked in the simulation
// (simulation_articulated_test.cc) against closed forms.
#include "hadal/sensors/force_torque_sensor.h"

#include <geometry_msgs.h>
#include <gtest/gtest.h>

#include <cmath>

#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A wrench with every component different, at a sensor 0.2 m along L's y and turned 90 degrees about z:
// F_S = R_SL F_L and N_S = R_SL (N_L - p_LS x F_L), worked by hand; parent_to_child gives the parent's
// side, child_to_parent (the default) its opposite.
TEST(ForceTorqueSensorTest, TheJointsWrenchMovesToTheSensorsFrameAndOrigin) {
  Eigen::Isometry3d X_LS = Eigen::Isometry3d::Identity();
  X_LS.translation() = Eigen::Vector3d(0.0, 0.2, 0.0);
  X_LS.linear() = Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Eigen::Matrix<double, 6, 1> wrench_L;
  wrench_L << 1.0, 2.0, 3.0, 0.4, 0.5, 0.6;
  // p_LS x F_L = (0.2 * 3 - 0, 0 - 0, 0 - 0.2 * 1) = (0.6, 0, -0.2); N_L - that = (-0.2, 0.5, 0.8).
  // R_SL turns L's x to S's -y and L's y to S's x: (a, b, c)_L = (b, -a, c)_S.
  ForceTorqueSpec spec;
  spec.parent_to_child = true;
  Eigen::Vector3d force_S, torque_S;
  ForceTorqueSensor::ideal(spec, X_LS, wrench_L, force_S, torque_S);
  EXPECT_TRUE(force_S.isApprox(Eigen::Vector3d(2.0, -1.0, 3.0), 1e-12)) << force_S.transpose();
  EXPECT_TRUE(torque_S.isApprox(Eigen::Vector3d(0.5, 0.2, 0.8), 1e-12)) << torque_S.transpose();
  spec.parent_to_child = false;
  ForceTorqueSensor::ideal(spec, X_LS, wrench_L, force_S, torque_S);
  EXPECT_TRUE(force_S.isApprox(Eigen::Vector3d(-2.0, 1.0, -3.0), 1e-12)) << force_S.transpose();
  EXPECT_TRUE(torque_S.isApprox(Eigen::Vector3d(-0.5, -0.2, -0.8), 1e-12)) << torque_S.transpose();
}

// Noise: a zero offset of 5 N drawn once per run (the same every sample) and 2 N of white noise per
// sample. Over 4000 samples the spread is 2 N within 4 sigma / sqrt(2 n) = 4.5 % and the mean is the
// offset within 4 sigma / sqrt(n) = 0.13 N. The same seed gives the same bits; another sensor name
// other draws. The message carries the reading.
TEST(ForceTorqueSensorTest, SeededOffsetAndWhiteNoiseAndTheMessage) {
  testing::SensorTestWorld world(testing::one_vehicle_world(Eigen::Vector3d(0, 0, -10)));
  SensorSpec mount;
  mount.link_index = 1;
  world.sensor_spec = &mount;
  world.state.vehicles[0].joint_wrenches_L.assign(2, Eigen::Matrix<double, 6, 1>::Zero());
  world.state.vehicles[0].joint_wrenches_L[1] << 0.0, 0.0, -40.0, 0.0, 3.0, 0.0;
  ForceTorqueSpec spec;
  spec.parent_to_child = true;
  spec.force_noise_stddev = 2.0;
  spec.force_offset_stddev = 5.0;
  ForceTorqueSensor::State state = world.initial_state<ForceTorqueSensor>(spec, 100.0, "ft");
  ForceTorqueSensor::State again = world.initial_state<ForceTorqueSensor>(spec, 100.0, "ft");
  ForceTorqueSensor::State other = world.initial_state<ForceTorqueSensor>(spec, 100.0, "ft2");
  const int n = 4000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    world.sample<ForceTorqueSensor>(spec, state, Eigen::Isometry3d::Identity(), 100.0);
    world.sample<ForceTorqueSensor>(spec, again, Eigen::Isometry3d::Identity(), 100.0);
    ASSERT_EQ(state.force_S, again.force_S);
    sum += state.force_S.z();
    sum2 += state.force_S.z() * state.force_S.z();
    EXPECT_EQ(state.torque_S, Eigen::Vector3d(0.0, 3.0, 0.0));  // no torque noise
  }
  world.sample<ForceTorqueSensor>(spec, other, Eigen::Isometry3d::Identity(), 100.0);
  EXPECT_NE(other.force_S, state.force_S);
  const double mean = sum / n, spread = std::sqrt(sum2 / n - mean * mean);
  const double offset = state.force_noise.axes[2].turn_on_bias;
  EXPECT_NE(offset, 0.0);
  EXPECT_NEAR(mean, -40.0 + offset, 4.0 * 2.0 / std::sqrt(n));
  EXPECT_NEAR(spread / 2.0, 1.0, 4.0 / std::sqrt(2.0 * n));

  geometry_msgs::msg::WrenchStamped msg;
  const std::string frame = "rov/ft";
  ForceTorqueSensor::fill_message(spec, state, MessageHeader{12.5, frame, 100.0}, msg);
  EXPECT_EQ(msg.header().frame_id(), "rov/ft");
  EXPECT_EQ(msg.header().stamp().sec(), 12);
  EXPECT_EQ(msg.wrench().force().z(), state.force_S.z());
  EXPECT_EQ(msg.wrench().torque().y(), 3.0);
}

}  // namespace
}  // namespace hadal::sensors
