// The side-scan kind alone (no Bullet): both channels over a plane seabed against the geometry, a target's
// echo and shadow on its side only, and the RawSonarImage messages.
#include "hadal/sensors/sidescan_sensor.h"

#include <gtest/gtest.h>
#include <marine_acoustic_msgs.h>

#include <cmath>
#include <cstring>

#include "hadal/core/units.h"
#include "hadal/physics/ocean.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::SensorTestWorld;

constexpr double kAltitude = 8.0;
const Eigen::Isometry3d kX_BS = Eigen::Isometry3d::Identity();  // S = B: x forward, y port, z up

SidescanSensor::Spec quiet_spec() {
  SidescanSensor::Spec spec;
  spec.depression = 20.0 * kDegToRad;
  spec.vertical_beam_width = 40.0 * kDegToRad;
  spec.acoustics.max_range = 60.0;
  spec.acoustics.bins = 1200;  // 5 cm from 0 m
  spec.acoustics.speckle = false;
  spec.acoustics.receiver_noise = false;
  spec.encoding.float32 = true;
  SidescanSensor::make_ping(spec);
  return spec;
}

float sample(const std::vector<std::uint8_t>& side, std::size_t i) { return testing::float32_sample(side, i); }

int first_echo(const std::vector<std::uint8_t>& side) {
  for (std::size_t i = 0; i < side.size() / 4; ++i) {
    if (sample(side, i) > 0.0f) return static_cast<int>(i);
  }
  return -1;
}

// Each channel's first echo is the first bottom return of a real side-scan: from straight below, at the
// altitude (8 m; the water column before it is empty), within a bin (the steepest ray lies within a ray cell,
// 0.06 deg, of nadir: 4 um of range, and its patch spreads less than a bin there), and the two sides of a level
// vehicle over a plane see the same. It is weak (the pattern 70 deg off the axis): the echo where the beam's
// axis meets the seabed, 8 / sin(20 deg) = 23.4 m, is stronger even after the TVG's 30 log10(23.4 / 8) = 14 dB.
TEST(SidescanSensorTest, FirstReturnIsTheAltitude) {
  SensorTestWorld world(testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -100.0 + kAltitude)), true);
  const SidescanSensor::Spec spec = quiet_spec();
  const SidescanSensor::State state = world.initial_state<SidescanSensor>(spec, 5.0, "sss");
  const SidescanSensor::Capture ping = testing::capture<SidescanSensor>(world, spec, state, kX_BS);
  ASSERT_EQ(ping.port.size(), 4u * 1200u);
  EXPECT_NEAR(first_echo(ping.port), spec.ping->bin_of(kAltitude), 1);
  EXPECT_NEAR(first_echo(ping.starboard), spec.ping->bin_of(kAltitude), 1);
  const auto axis_bin = static_cast<std::size_t>(spec.ping->bin_of(kAltitude / std::sin(20.0 * kDegToRad)));
  const auto nadir_bin = static_cast<std::size_t>(spec.ping->bin_of(kAltitude) + 2);
  EXPECT_GT(sample(ping.port, axis_bin), sample(ping.port, nadir_bin));
  // And the echo goes on to where the shallowest ray meets the seabed: 8 / sin(0) is beyond the window.
  EXPECT_GT(sample(ping.port, static_cast<std::size_t>(spec.ping->bin_of(55.0))), 0.0f);
}

// A box on the seabed 20 m to port, 1.5 m high: a bright echo and behind it a shadow on the port channel
// only; the starboard channel sees plain seabed at those ranges.
TEST(SidescanSensorTest, TargetAndShadowOnItsSideOnly) {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -100.0 + kAltitude));
  VehicleSpec rock;
  rock.name = "rock";
  LinkSpec body;
  body.name = "body";
  body.mass = 1.0;
  CollisionShape box;
  box.type = CollisionShapeType::kBox;
  box.box_size = Eigen::Vector3d(2.0, 1.0, 1.5);
  body.collisions = {box};
  rock.links = {body};
  rock.X_WB_initial.translation() = Eigen::Vector3d(0.0, 20.0, -100.0 + 0.75);
  model.vehicles.push_back(rock);
  SensorTestWorld world(model, true);
  const SidescanSensor::Spec spec = quiet_spec();
  const SidescanSensor::State state = world.initial_state<SidescanSensor>(spec, 5.0, "sss");
  const SidescanSensor::Capture ping = testing::capture<SidescanSensor>(world, spec, state, kX_BS);
  // Shadow: rays over the box's top edge (y = 20.5, 1.5 m up: 6.5 m below the sonar) meet the seabed at
  // y = 20.5 * 8 / 6.5 = 25.2 m; the seabed from the box's far foot (y = 20.5) to there is hidden: ranges
  // 21.98 to 26.47 m.
  for (double r = 22.3; r < 26.2; r += 0.05) {
    EXPECT_EQ(sample(ping.port, static_cast<std::size_t>(spec.ping->bin_of(r))), 0.0f) << r;
    EXPECT_GT(sample(ping.starboard, static_cast<std::size_t>(spec.ping->bin_of(r))), 0.0f) << r;
  }
  // The box's face towards the sonar returns more than the seabed beside it on the other side.
  float box_echo = 0.0f, seabed_echo = 0.0f;
  for (double r = 20.2; r < 21.4; r += 0.05) {
    box_echo = std::max(box_echo, sample(ping.port, static_cast<std::size_t>(spec.ping->bin_of(r))));
    seabed_echo = std::max(seabed_echo, sample(ping.starboard, static_cast<std::size_t>(spec.ping->bin_of(r))));
  }
  EXPECT_GT(box_echo, 10.0f * seabed_echo);
}

// RawSonarImage per side: sample rate c / (2 bin), bins per beam, sample0 = min_range / bin (0: the window
// starts at the transducer), the across-track steering angle of each side (+ to starboard), one beam of samples.
TEST(SidescanSensorTest, Messages) {
  SensorTestWorld world(testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -100.0 + kAltitude)), true);
  const SidescanSensor::Spec spec = quiet_spec();
  SidescanSensor::State state = world.initial_state<SidescanSensor>(spec, 5.0, "sss");
  SidescanSensor::Capture ping = testing::capture<SidescanSensor>(world, spec, state, kX_BS);
  state.port = ping.port;
  state.starboard = ping.starboard;
  state.sound_speed_m_per_s = ping.water.sound_speed_m_per_s;
  marine_acoustic_msgs::msg::RawSonarImage port, starboard;
  const std::string frame = "auv/sss";
  SidescanSensor::PortTopic::fill(spec, state, MessageHeader{2.0, frame, 5.0}, port);
  SidescanSensor::StarboardTopic::fill(spec, state, MessageHeader{2.0, frame, 5.0}, starboard);
  const double bin = 60.0 / 1200.0;
  EXPECT_FLOAT_EQ(port.sample_rate(), static_cast<float>(state.sound_speed_m_per_s / (2.0 * bin)));
  EXPECT_EQ(port.samples_per_beam(), 1200u);
  EXPECT_EQ(port.sample0(), 0u);
  ASSERT_EQ(port.rx_angles().size(), 1u);
  EXPECT_FLOAT_EQ(port.rx_angles()[0], static_cast<float>(-70.0 * kDegToRad));
  EXPECT_FLOAT_EQ(starboard.rx_angles()[0], static_cast<float>(70.0 * kDegToRad));
  EXPECT_EQ(port.image().beam_count(), 1u);
  EXPECT_EQ(port.image().dtype(), marine_acoustic_msgs::msg::SonarImageData_Constants::DTYPE_FLOAT32);
  EXPECT_EQ(port.image().data(), ping.port);
  EXPECT_EQ(starboard.image().data(), ping.starboard);
  ASSERT_EQ(port.ping_info().tx_beamwidths().size(), 1u);
  EXPECT_FLOAT_EQ(port.ping_info().tx_beamwidths()[0], static_cast<float>(40.0 * kDegToRad));
  EXPECT_FLOAT_EQ(port.ping_info().rx_beamwidths()[0], static_cast<float>(0.5 * kDegToRad));
}

}  // namespace
}  // namespace hadal::sensors
