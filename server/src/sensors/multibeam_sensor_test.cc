// The multibeam kind alone (no Bullet): its swath over a plane seabed against the geometry through its
// message, beams that find nothing, and its YAML-independent pieces.
#include "hadal/sensors/multibeam_sensor.h"

#include <gtest/gtest.h>
#include <marine_acoustic_msgs.h>

#include <cmath>
#include <cstring>

#include "hadal/core/units.h"
#include "hadal/physics/ocean.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::rpy;
using testing::SensorTestWorld;

constexpr double kAltitude = 20.0;
// x_S down, y_S to port (then z_S forward): pitch +90 deg.
const Eigen::Isometry3d kX_BS = pose(Eigen::Vector3d::Zero(), rpy(0.0, kPi / 2.0, 0.0));

MultibeamSensor::Spec quiet_spec() {
  MultibeamSensor::Spec spec;
  spec.beams = 101;
  spec.swath = 100.0 * kDegToRad;  // rolled 20 deg the outer beam is 70 deg off nadir: 58 m, in the window
  spec.across_beam_width = 1.0 * kDegToRad;
  spec.along_beam_width = 2.0 * kDegToRad;
  spec.rays_across = 96;  // enough that the oblique beams' long footprints fill their bins
  spec.rays_along = 4;
  spec.acoustics.max_range = 100.0;
  spec.acoustics.bins = 3980;  // 2.5 cm
  spec.acoustics.speckle = false;
  spec.acoustics.receiver_noise = false;
  MultibeamSensor::make_ping(spec);
  return spec;
}

// One ping of the world's vehicle's multibeam (mounted at kX_BS) as its message.
marine_acoustic_msgs::msg::SonarDetections ping_message(SensorTestWorld& world, const MultibeamSensor::Spec& spec) {
  MultibeamSensor::State state = world.initial_state<MultibeamSensor>(spec, 2.0, "mbes");
  MultibeamSensor::Capture ping = testing::capture<MultibeamSensor>(world, spec, state, kX_BS);
  state.last = std::move(ping.detections);
  state.sound_speed_m_per_s = ping.water.sound_speed_m_per_s;
  marine_acoustic_msgs::msg::SonarDetections msg;
  const std::string frame = "auv/mbes";
  MultibeamSensor::fill_message(spec, state, MessageHeader{1.0, frame, 2.0}, msg);
  return msg;
}

// The vehicle 20 m above the plane, rolled: each beam's two-way travel time times c / 2 is the range at which
// its axis meets the plane, altitude / cos(angle off nadir), within one range bin.
TEST(MultibeamSensorTest, SwathOverAPlaneMatchesTheGeometry) {
  for (double roll_deg : {0.0, 12.0, -20.0}) {
    SCOPED_TRACE(roll_deg);
    Model model = testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -100.0 + kAltitude));
    model.vehicles[0].X_WB_initial.linear() = rpy(roll_deg * kDegToRad, 0.0, 0.0);
    SensorTestWorld world(model, true);
    const MultibeamSensor::Spec spec = quiet_spec();
    const marine_acoustic_msgs::msg::SonarDetections msg = ping_message(world, spec);
    ASSERT_EQ(msg.flags().size(), 101u);
    const Eigen::Matrix3d R_WS = world.body().X_WB.linear() * kX_BS.linear();
    const double c = msg.ping_info().sound_speed();
    for (int k = 0; k < spec.beams; ++k) {
      const double down = -(R_WS * spec.ping->beams[static_cast<std::size_t>(k)].axis_S).z();
      const double expected = kAltitude / down;
      ASSERT_EQ(msg.flags()[k].flag(), marine_acoustic_msgs::msg::DetectionFlag_Constants::DETECT_OK) << k;
      EXPECT_NEAR(0.5 * c * msg.two_way_travel_times()[k], expected, spec.ping->bin_size_m()) << "beam " << k;
      EXPECT_FLOAT_EQ(msg.rx_angles()[k], static_cast<float>(-MultibeamSensor::beam_angle(spec, k)));
      EXPECT_GT(msg.intensities()[k], 0.0f);
    }
    // Beam 0 looks to starboard (-y_S is starboard when y_S is port): + rx_angle.
    EXPECT_GT(msg.rx_angles()[0], 0.0f);
    EXPECT_EQ(msg.tx_angles()[0], 0.0f);
    EXPECT_FLOAT_EQ(msg.ping_info().sound_speed(), static_cast<float>(world.ocean.sound_speed(100.0 - kAltitude)));
    EXPECT_FLOAT_EQ(msg.ping_info().tx_beamwidths()[0], static_cast<float>(2.0 * kDegToRad));
    EXPECT_FLOAT_EQ(msg.ping_info().rx_beamwidths()[0], static_cast<float>(1.0 * kDegToRad));
  }
}

// Beams whose echoes fall outside the window (the outer beams with a 30 m max_range at 20 m altitude: their
// axes meet the plane beyond 30 m) have no detection: DETECT_BAD_SONAR and a zero travel time; those within
// are found.
TEST(MultibeamSensorTest, BeamsThatFindNothingAreFlagged) {
  SensorTestWorld world(testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -100.0 + kAltitude)), true);
  MultibeamSensor::Spec spec = quiet_spec();
  spec.swath = 120.0 * kDegToRad;  // 101 beams 1.19 deg apart: 9 per side beyond 49.2 deg (near edge > 30 m)
  spec.acoustics.max_range = 30.0;
  spec.acoustics.bins = 1180;
  MultibeamSensor::make_ping(spec);
  const marine_acoustic_msgs::msg::SonarDetections msg = ping_message(world, spec);
  namespace flag = marine_acoustic_msgs::msg::DetectionFlag_Constants;
  int found = 0, missed = 0;
  for (int k = 0; k < spec.beams; ++k) {
    const double off_nadir = std::abs(MultibeamSensor::beam_angle(spec, k));
    const double expected = kAltitude / std::cos(off_nadir);
    // Beams whose footprint straddles the window's end (within a beam width of it) may go either way.
    const double near_edge = kAltitude / std::cos(off_nadir - 1.0 * kDegToRad), far_edge = kAltitude / std::cos(off_nadir + 1.0 * kDegToRad);
    if (far_edge < 29.0) {
      EXPECT_EQ(msg.flags()[k].flag(), flag::DETECT_OK) << k;
      ++found;
    } else if (near_edge > 30.0) {
      EXPECT_EQ(msg.flags()[k].flag(), flag::DETECT_BAD_SONAR) << k << " " << expected;
      EXPECT_EQ(msg.two_way_travel_times()[k], 0.0f);
      ++missed;
    }
  }
  EXPECT_GT(found, 70);
  EXPECT_EQ(missed, 18);
}

// With speckle and receiver noise the detections scatter but stay near the geometry (a few bins), and the
// same ping step gives the same detections.
TEST(MultibeamSensorTest, NoisyDetectionsAreSeededAndStayNearTheSeabed) {
  SensorTestWorld world(testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -100.0 + kAltitude)), true);
  MultibeamSensor::Spec spec = quiet_spec();
  spec.acoustics.speckle = true;
  spec.acoustics.receiver_noise = true;
  MultibeamSensor::make_ping(spec);
  const MultibeamSensor::State state = world.initial_state<MultibeamSensor>(spec, 2.0, "mbes");
  const MultibeamSensor::Capture a = testing::capture<MultibeamSensor>(world, spec, state, kX_BS, 3);
  const MultibeamSensor::Capture b = testing::capture<MultibeamSensor>(world, spec, state, kX_BS, 3);
  const MultibeamSensor::Capture c = testing::capture<MultibeamSensor>(world, spec, state, kX_BS, 4);
  // Bit for bit (beams without a detection hold NaN, which == would call unequal to itself).
  const auto same = [](const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
  };
  EXPECT_TRUE(same(a.detections.range_m, b.detections.range_m));
  EXPECT_FALSE(same(a.detections.range_m, c.detections.range_m));
  int valid = 0;
  for (int k = 0; k < spec.beams; ++k) {
    const double range = a.detections.range_m[static_cast<std::size_t>(k)];
    if (!std::isfinite(range)) continue;
    ++valid;
    const double expected = kAltitude / std::cos(MultibeamSensor::beam_angle(spec, k));
    EXPECT_NEAR(range, expected, 0.01 * expected + 0.1) << k;
  }
  EXPECT_GT(valid, 90);
}

}  // namespace
}  // namespace hadal::sensors
