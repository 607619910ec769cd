// The altimeter kind alone (no Bullet): its single beam ray-cast from the sensor's pose into a world
// scene (a plane seabed, its own hull, another vehicle), the REP 117 window, noise, and its message.
#include "hadal/sensors/altimeter_sensor.h"

#include <gtest/gtest.h>
#include <sensor_msgs.h>

#include <cfloat>
#include <cmath>
#include <limits>

#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::rpy;
using testing::SensorTestWorld;

constexpr double kSeabedZ = -100.0;
const Eigen::Isometry3d kX_BS = pose(Eigen::Vector3d(-0.3, 0.0, -0.1), rpy(0.0, EIGEN_PI / 2.0, 0.0));  // x down

AltimeterSensor::Spec exact() {
  AltimeterSensor::Spec spec;
  spec.noise_stddev = 0.0;
  spec.resolution = 0.0;
  return spec;
}

CollisionShape box(const Eigen::Vector3d& size) {
  CollisionShape shape;
  shape.type = CollisionShapeType::kBox;
  shape.box_size = size;
  return shape;
}

// The AUV (a 1 x 0.4 x 0.4 m box around the sensor) pitched at 0.2 rad 30 m over the plane, and a 2 x 2 x
// 1 m lander on the seabed 50 m east.
Model two_vehicles() {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, kSeabedZ + 30.0), kSeabedZ);
  model.vehicles[0].links[0].collisions = {box(Eigen::Vector3d(1.0, 0.4, 0.4))};
  model.vehicles[0].X_WB_initial.linear() = rpy(0.0, 0.2, 0.0);
  VehicleSpec lander = model.vehicles[0];
  lander.name = "lander";
  lander.links[0].collisions = {box(Eigen::Vector3d(2.0, 2.0, 1.0))};
  lander.X_WB_initial = pose(Eigen::Vector3d(50.0, 0.0, kSeabedZ + 10.0));  // top at 10.5 m
  model.vehicles.push_back(lander);
  return model;
}

// The beam (x of S, pointing down) reads the distance to the plane through its own hull, to 4 float ulp
// of 100 m (Embree is float); over the lander, the lander's top; closer than min_range -inf, beyond
// max_range +inf (REP 117).
TEST(AltimeterSensorTest, RangesThePlaneAndOtherVehiclesNotItsOwnHull) {
  SensorTestWorld world(two_vehicles(), true);
  const AltimeterSensor::Spec spec = exact();
  AltimeterSensor::State state = world.initial_state<AltimeterSensor>(spec, 10.0);
  auto expected_range = [&](double surface_z) {
    const Eigen::Isometry3d X_WS = world.body().X_WB * kX_BS;
    return (X_WS.translation().z() - surface_z) / -X_WS.linear().col(0).z();
  };
  world.sample<AltimeterSensor>(spec, state, kX_BS, 10.0);
  EXPECT_NEAR(state.range, expected_range(kSeabedZ), 4 * FLT_EPSILON * 100.0);

  // Level, with the altimeter right over the lander's top (B 0.3 m ahead of the sensor).
  world.body().X_WB = pose(Eigen::Vector3d(50.3, 0.0, kSeabedZ + 30.0));
  world.state.step_count = 1;  // a new state: the scene's bodies move
  world.sample<AltimeterSensor>(spec, state, kX_BS, 10.0);
  EXPECT_NEAR(state.range, 30.0 - 0.1 - 10.5, 4 * FLT_EPSILON * 100.0);

  // 0.2 m over the seabed (min_range 0.3 m): -inf; 150 m up (max_range 100 m): +inf.
  world.body().X_WB = pose(Eigen::Vector3d(-50.0, 0.0, kSeabedZ + 0.2 + 0.1));
  world.state.step_count = 2;
  world.sample<AltimeterSensor>(spec, state, kX_BS, 10.0);
  EXPECT_EQ(state.range, -std::numeric_limits<double>::infinity());
  world.body().X_WB = pose(Eigen::Vector3d(-50.0, 0.0, kSeabedZ + 150.0));
  world.state.step_count = 3;
  world.sample<AltimeterSensor>(spec, state, kX_BS, 10.0);
  EXPECT_EQ(state.range, std::numeric_limits<double>::infinity());
}

// White noise of 5 cm per sample on a 30 m range: stddev within 4 sigma / sqrt(2 n) (n = 5000, fixed
// seed), readings on the 1 cm resolution grid.
TEST(AltimeterSensorTest, NoiseAndResolution) {
  SensorTestWorld world(testing::one_vehicle_world(Eigen::Vector3d(0, 0, kSeabedZ + 30.0), kSeabedZ), true);
  AltimeterSensor::Spec spec;
  spec.noise_stddev = 0.05;
  spec.resolution = 0.01;
  AltimeterSensor::State state = world.initial_state<AltimeterSensor>(spec, 10.0);
  const int n = 5000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    world.sample<AltimeterSensor>(spec, state, kX_BS, 10.0);
    EXPECT_NEAR(std::remainder(state.range, 0.01), 0.0, 1e-12);
    const double e = state.range - 29.9;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n, stddev = std::sqrt(sum2 / n - mean * mean);
  // Quantising to 1 cm adds 0.01^2 / 12 of variance.
  const double sigma = std::sqrt(0.05 * 0.05 + 0.01 * 0.01 / 12.0);
  EXPECT_NEAR(stddev, sigma, 4.0 * sigma / std::sqrt(2.0 * n));
  EXPECT_NEAR(mean, 0.0, 4.0 * sigma / std::sqrt(n));
}

// sensor_msgs/Range (ULTRASOUND): range, window and beam width as configured, infinities kept.
TEST(AltimeterSensorTest, Message) {
  const AltimeterSensor::Spec spec;
  AltimeterSensor::State state;
  state.range = 42.125;
  sensor_msgs::msg::Range msg;
  const std::string frame = "auv/altimeter";
  AltimeterSensor::fill_message(spec, state, MessageHeader{1.0, frame, 10.0}, msg);
  EXPECT_EQ(msg.range(), 42.125f);
  EXPECT_EQ(msg.min_range(), 0.3f);
  EXPECT_EQ(msg.max_range(), 100.0f);
  EXPECT_EQ(msg.radiation_type(), sensor_msgs::msg::Range_Constants::ULTRASOUND);
  EXPECT_FLOAT_EQ(msg.field_of_view(), static_cast<float>(6.0 * kPi / 180.0));
  state.range = -std::numeric_limits<double>::infinity();
  AltimeterSensor::fill_message(spec, state, MessageHeader{1.1, frame, 10.0}, msg);
  EXPECT_EQ(msg.range(), -std::numeric_limits<float>::infinity());
}

}  // namespace
}  // namespace hadal::sensors
