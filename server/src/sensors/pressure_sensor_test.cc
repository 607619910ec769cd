// The pressure sensor kind alone (no Bullet): ideal value from the ocean at the sensor's position,
// noise, quantisation, range, air, and its message.
#include "hadal/sensors/pressure_sensor.h"

#include <gtest/gtest.h>
#include <sensor_msgs.h>

#include <algorithm>
#include <cmath>

#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::one_vehicle_world;
using testing::pose;
using testing::SensorTestWorld;

// B at `depth` in a pycnocline-ramp ocean; the sensor 0.5 m above and 0.3 m ahead of B's origin.
SensorTestWorld world_at(double depth) {
  Model model = one_vehicle_world(Eigen::Vector3d(0, 0, -depth), -5000.0);
  model.world.water.density_model = DensityModel::kRamp;
  model.world.seed = 1;
  return SensorTestWorld(model);
}
const Eigen::Isometry3d kX_BS = pose(Eigen::Vector3d(0.3, 0.0, 0.5));

// Without noise the sensor reads the ocean's absolute pressure at its own depth, 0.5 m shallower than
// B, exactly; tilting the vehicle moves the sensor and the reading with it.
TEST(PressureSensorTest, ReadsTheOceanAtItsPosition) {
  SensorTestWorld world = world_at(1500.0);
  const PressureSensor::Spec spec;
  PressureSensor::State state = world.initial_state<PressureSensor>(spec, 10.0);
  world.sample<PressureSensor>(spec, state, kX_BS, 10.0);
  EXPECT_EQ(state.pressure, world.ocean.pressure(1500.0 - 0.5));
  // Pitched 90 deg nose up (B's x up): the sensor is 0.3 m above B's origin.
  world.body().X_WB = pose(Eigen::Vector3d(0, 0, -1500.0), testing::rpy(0.0, -EIGEN_PI / 2.0, 0.0));
  world.sample<PressureSensor>(spec, state, kX_BS, 10.0);
  EXPECT_NEAR(state.pressure, world.ocean.pressure(1500.0 - 0.3), 1e-6);
}

// Under regular waves (1 m, 8 s, deep water) 4.5 m down, the sensor reads the hydrostatic pressure of the mean level
// plus the wave's dynamic pressure rho g a exp(k z') cos(theta) (Wheeler: z' = z - eta), through a period (1e-6 Pa
// relative to rho g a: what the two additions round).
TEST(PressureSensorTest, UnderWavesItFeelsTheirDynamicPressure) {
  Model model = one_vehicle_world(Eigen::Vector3d(0, 0, -5.0), -5000.0);
  model.world.waves.spectrum = physics::WaveSpectrum::kRegular;
  model.world.waves.regular = {{1.0, 8.0, 0.0, 0.0}};
  model.world.waves.ramp_time = 0.0;  // the full sea from t = 0
  SensorTestWorld world(model);
  const PressureSensor::Spec spec;
  PressureSensor::State state = world.initial_state<PressureSensor>(spec, 10.0);
  const double rho = model.world.water.density, g = 9.80665, omega = 2.0 * EIGEN_PI / 8.0, k = omega * omega / g;
  double lo = 1e12, hi = 0.0;
  for (int i = 0; i < 80; ++i) {
    world.state.time = 0.1 * i;
    world.sample<PressureSensor>(spec, state, kX_BS, 10.0);
    const double theta = k * 0.3 - omega * world.state.time, eta = std::cos(theta), z = -4.5;
    const double expected = world.ocean.pressure(4.5) + rho * g * std::exp(k * (z - eta)) * std::cos(theta);
    EXPECT_NEAR(state.pressure, expected, 1e-6 * rho * g) << world.state.time;
    lo = std::min(lo, state.pressure);
    hi = std::max(hi, state.pressure);
  }
  // A swing of about 2 rho g a e^(k z) = 15 kPa at 4.5 m under 8 s waves.
  EXPECT_GT(hi - lo, 10000.0);
}

// White noise of 100 Pa: over 20 000 samples the mean is within 4 sigma / sqrt(n) = 2.8 Pa of the
// ideal value and the standard deviation within 4 sigma / sqrt(2 n) = 2 % of 100 Pa (fixed seed).
TEST(PressureSensorTest, NoiseHasTheConfiguredSpread) {
  SensorTestWorld world = world_at(100.0);
  PressureSensor::Spec spec;
  spec.noise_stddev = 100.0;
  PressureSensor::State state = world.initial_state<PressureSensor>(spec, 1000.0);
  const double ideal = world.ocean.pressure(99.5);
  double sum = 0.0, sum2 = 0.0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    world.sample<PressureSensor>(spec, state, kX_BS, 1000.0);
    const double e = state.pressure - ideal;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n, stddev = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4.0 * 100.0 / std::sqrt(n));
  EXPECT_NEAR(stddev, 100.0, 4.0 * 100.0 / std::sqrt(2.0 * n));
}

// Quantisation to the resolution and clipping to [0, range_pa]; above the water the sensor reads the
// atmosphere.
TEST(PressureSensorTest, ResolutionRangeAndAir) {
  SensorTestWorld world = world_at(50.0);
  PressureSensor::Spec spec;
  spec.resolution = 1000.0;
  spec.noise_stddev = 300.0;
  PressureSensor::State state = world.initial_state<PressureSensor>(spec, 100.0);
  for (int k = 0; k < 100; ++k) {
    world.sample<PressureSensor>(spec, state, kX_BS, 100.0);
    EXPECT_EQ(std::fmod(state.pressure, 1000.0), 0.0) << state.pressure;
  }
  SensorTestWorld deep = world_at(1000.0);
  PressureSensor::Spec small_range;
  small_range.range_pa = 2.0e5;
  PressureSensor::State clipped = deep.initial_state<PressureSensor>(small_range, 100.0);
  deep.sample<PressureSensor>(small_range, clipped, kX_BS, 100.0);
  EXPECT_EQ(clipped.pressure, 2.0e5);
  SensorTestWorld dry = world_at(-10.0);
  PressureSensor::State air = dry.initial_state<PressureSensor>(PressureSensor::Spec{}, 100.0);
  dry.sample<PressureSensor>(PressureSensor::Spec{}, air, kX_BS, 100.0);
  EXPECT_EQ(air.pressure, dry.ocean.atmospheric_pressure());
}

// A zero offset is added to every reading, before clipping: exactly, without noise; in air a negative
// offset larger than the atmosphere reads 0.
TEST(PressureSensorTest, OffsetIsAddedBeforeClipping) {
  SensorTestWorld world = world_at(300.0);
  PressureSensor::Spec spec;
  spec.offset = 250.0;
  PressureSensor::State state = world.initial_state<PressureSensor>(spec, 10.0);
  world.sample<PressureSensor>(spec, state, kX_BS, 10.0);
  EXPECT_EQ(state.pressure, world.ocean.pressure(300.0 - 0.5) + 250.0);
  SensorTestWorld dry = world_at(-10.0);
  spec.offset = -2.0e5;
  PressureSensor::State air = dry.initial_state<PressureSensor>(spec, 10.0);
  dry.sample<PressureSensor>(spec, air, kX_BS, 10.0);
  EXPECT_EQ(air.pressure, 0.0);
}

// Same seed and names: the same stream; another sensor name: another stream.
TEST(PressureSensorTest, StreamsAreKeyedBySeedVehicleAndSensor) {
  SensorTestWorld world = world_at(200.0);
  PressureSensor::Spec spec;
  spec.noise_stddev = 50.0;
  auto stream = [&](const std::string& name) {
    PressureSensor::State state = world.initial_state<PressureSensor>(spec, 10.0, name);
    std::vector<double> values;
    for (int k = 0; k < 50; ++k) {
      world.sample<PressureSensor>(spec, state, kX_BS, 10.0);
      values.push_back(state.pressure);
    }
    return values;
  };
  EXPECT_EQ(stream("depth"), stream("depth"));
  EXPECT_NE(stream("depth"), stream("depth2"));
}

// sensor_msgs/FluidPressure: the last sample, its stamp and frame, variance sigma^2 + lsb^2 / 12.
TEST(PressureSensorTest, Message) {
  PressureSensor::Spec spec;
  spec.noise_stddev = 20.0;
  spec.resolution = 6.0;
  PressureSensor::State state;
  state.pressure = 1.5e6;
  sensor_msgs::msg::FluidPressure msg;
  const std::string frame = "auv/depth";
  PressureSensor::fill_message(spec, state, MessageHeader{3.5, frame, 10.0}, msg);
  EXPECT_EQ(msg.fluid_pressure(), 1.5e6);
  EXPECT_EQ(msg.variance(), 400.0 + 3.0);
  EXPECT_EQ(msg.header().frame_id(), "auv/depth");
  EXPECT_EQ(msg.header().stamp().sec(), 3);
  EXPECT_EQ(msg.header().stamp().nanosec(), 500000000u);
}

}  // namespace
}  // namespace hadal::sensors
