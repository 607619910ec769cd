// The LBL kind alone (no Bullet): a vehicle's transceiver ranging to seabed beacons through the acoustic
// channel, stepped as the simulation steps it, against closed forms: ranges and stamps at rest, the mean of
// the two legs for a moving vehicle, no range from a hidden beacon, range noise with the configured sigma,
// and the message.
#include "hadal/sensors/lbl_sensor.h"

#include <gtest/gtest.h>
#include <hadal_msgs.h>

#include <cmath>
#include <vector>

#include "hadal/physics/ocean.h"
#include "hadal/sensors/acoustic_channel.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::rpy;
using testing::SensorTestWorld;

// The transceiver 0.3 m under the AUV's B, the AUV pitched and yawed at 1500 m; three beacons 10 m above a
// plane seabed at 3000 m, with different turnarounds.
const Eigen::Isometry3d kX_BS = pose(Eigen::Vector3d(0.2, 0.0, -0.3));

Model field() {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(100.0, 200.0, -1500.0), -3000.0);
  model.vehicles[0].X_WB_initial.linear() = rpy(0.0, 0.05, 0.7);
  model.world.acoustics.beacons = {{"north", Eigen::Vector3d(0.0, 1500.0, -2990.0), 185.0, 10.0, 0.05},
                                   {"east", Eigen::Vector3d(1300.0, -700.0, -2990.0), 185.0, 10.0, 0.1},
                                   {"west", Eigen::Vector3d(-1300.0, -700.0, -2990.0), 185.0, 10.0, 0.0}};
  return model;
}

LblSpec exact() {
  LblSpec spec;
  spec.range_stddev = 0.0;
  return spec;
}

std::vector<LblRange> run(SensorTestWorld& world, const LblSpec& spec, LblSensor::State& state, double until,
                          double dt = 0.01, int every = 1000, const std::function<void(double)>& move = {}) {
  std::vector<LblRange> ranges;
  testing::step_events<LblSensor>(world, spec, state, kX_BS, until, dt, every, move, [&](const LblSensor::State& s) {
    ranges.insert(ranges.end(), s.ranges.begin(), s.ranges.end());
  });
  return ranges;
}

// At rest: each beacon's range is its distance to 1e-6 m, its reply arrives at two travel times plus its
// turnaround (1e-9 s), nearest first.
TEST(LblSensorTest, RangesAtRestAreTheDistancesToEachBeacon) {
  SensorTestWorld world(field());
  LblSensor::State state = world.initial_state<LblSensor>(exact(), 0.1, "lbl");
  const std::vector<LblRange> ranges = run(world, exact(), state, 5.0);
  ASSERT_EQ(ranges.size(), 3u);
  const Eigen::Vector3d p_WS = world.body().X_WB * kX_BS.translation();
  const AcousticChannel channel(world.ocean, world.model.world.acoustics);
  for (const LblRange& range : ranges) {
    const BeaconSpec& beacon = world.model.world.acoustics.beacons[static_cast<std::size_t>(range.beacon)];
    EXPECT_EQ(range.beacon_name, beacon.name);
    EXPECT_NEAR(range.range, (beacon.p_W - p_WS).norm(), 1e-6) << beacon.name;
    EXPECT_NEAR(range.stamp, 2.0 * channel.travel_time(p_WS, beacon.p_W) + beacon.turnaround_s, 1e-9) << beacon.name;
    EXPECT_EQ(range.p_Wbeacon, beacon.p_W);
    EXPECT_EQ(range.range_variance, 0.0);
    EXPECT_EQ(range.interrogation, 0u);
  }
  EXPECT_LT(ranges[0].stamp, ranges[1].stamp);
  EXPECT_LT(ranges[1].stamp, ranges[2].stamp);
}

// The vehicle moving at v straight at a beacon at its own depth (one sound speed c), D0 away at the
// interrogation t_i = 0: the beacon hears it at D0 / c, replies T later, and the reply meets the vehicle at
// t_f = (c t_r + D0) / (c + v); the range is c (t_f - T) / 2, the mean of the two legs.
TEST(LblSensorTest, AMovingVehicleRangesTheMeanOfTheTwoLegs) {
  Model model = field();
  model.world.acoustics.beacons = {{"ahead", Eigen::Vector3d(0.0, 0.0, -1500.0), 185.0, 10.0, 0.2}};
  SensorTestWorld world(model);
  const double d0 = 1200.0, v = 2.0;
  const auto move = [&](double t) {
    world.body().X_WB = pose(Eigen::Vector3d(-0.2 - d0 + v * t, 0.0, -1500.0 + 0.3));
  };
  LblSensor::State state = world.initial_state<LblSensor>(exact(), 0.1, "lbl");
  const std::vector<LblRange> ranges = run(world, exact(), state, 2.5, 0.01, 1000, move);
  ASSERT_EQ(ranges.size(), 1u);
  const double c = world.ocean.sound_speed(1500.0);
  const double t_r = d0 / c + 0.2;
  const double t_f = (c * t_r + d0) / (c + v);
  EXPECT_NEAR(ranges[0].stamp, t_f, 1e-9);
  EXPECT_NEAR(ranges[0].range, c * (t_f - 0.2) / 2.0, 1e-6);
  EXPECT_NEAR(ranges[0].range, (d0 + (d0 - v * t_f)) / 2.0, 1e-6);
}

// A box between the vehicle and the east beacon hides it; a beacon out of max_range gives no range; too weak a
// beacon none either.
TEST(LblSensorTest, NoRangeFromAHiddenFarOrWeakBeacon) {
  Model model = field();
  VehicleSpec block = model.vehicles[0];
  block.name = "block";
  CollisionShape shape;
  shape.type = CollisionShapeType::kBox;
  shape.box_size = Eigen::Vector3d(40.0, 40.0, 40.0);
  block.links[0].collisions = {shape};
  const Eigen::Vector3d p_WS(100.0, 200.0, -1500.0);
  block.X_WB_initial = pose(0.5 * (p_WS + model.world.acoustics.beacons[1].p_W));
  model.vehicles.push_back(block);
  model.world.acoustics.beacons[2].source_level_db = 120.0;
  SensorTestWorld world(model, true);
  LblSpec spec = exact();
  LblSensor::State state = world.initial_state<LblSensor>(spec, 0.1, "lbl");
  std::vector<std::string> names;
  for (const LblRange& range : run(world, spec, state, 5.0)) names.push_back(range.beacon_name);
  EXPECT_EQ(names, std::vector<std::string>{"north"});
  spec.max_range = 1000.0;
  LblSensor::State near = world.initial_state<LblSensor>(spec, 0.1, "lbl");
  world.state.time = 0.0;
  EXPECT_TRUE(run(world, spec, near, 5.0).empty());
}

// 300 ranges to one beacon at high SNR: mean error 0 within 3 sigma / sqrt(n), sigma within 15 % (the chi
// distribution's 3-sigma band for n = 300 is +-12 %).
TEST(LblSensorTest, RangeNoiseIsUnbiasedWithTheConfiguredSigma) {
  Model model = field();
  model.world.acoustics.beacons.resize(1);
  SensorTestWorld world(model);
  LblSpec spec;
  spec.range_stddev = 0.3;
  spec.reference_snr_db = 0.0;
  LblSensor::State state = world.initial_state<LblSensor>(spec, 1.0, "lbl");
  const std::vector<LblRange> ranges = run(world, spec, state, 304.0, 0.02, 50);
  ASSERT_GE(ranges.size(), 300u);
  const double r = (model.world.acoustics.beacons[0].p_W - world.body().X_WB * kX_BS.translation()).norm();
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < 300; ++i) {
    sum += ranges[i].range - r;
    sum2 += (ranges[i].range - r) * (ranges[i].range - r);
    EXPECT_DOUBLE_EQ(ranges[i].range_variance, 0.09);
  }
  EXPECT_NEAR(sum / 300, 0.0, 3.0 * 0.3 / std::sqrt(300.0));
  EXPECT_NEAR(std::sqrt(sum2 / 300), 0.3, 0.15 * 0.3);
}

TEST(LblSensorTest, MessageCarriesTheStepsRanges) {
  SensorTestWorld world(field());
  LblSensor::State state = world.initial_state<LblSensor>(exact(), 0.1, "lbl");
  const std::vector<LblRange> ranges = run(world, exact(), state, 5.0);
  ASSERT_EQ(state.ranges.size(), 1u);  // the last step's: the west beacon's
  const std::string frame = "auv/lbl";
  hadal_msgs::msg::LblRanges msg;
  LblSensor::fill_message(exact(), state, MessageHeader{state.ranges[0].stamp, frame, 0.1}, msg);
  ASSERT_EQ(msg.ranges().size(), 1u);
  EXPECT_EQ(msg.header().frame_id(), frame);
  EXPECT_EQ(msg.ranges()[0].beacon(), "west");
  EXPECT_EQ(msg.ranges()[0].range(), ranges.back().range);
  EXPECT_EQ(msg.ranges()[0].beacon_position().x(), -1300.0);
}

}  // namespace
}  // namespace hadal::sensors
