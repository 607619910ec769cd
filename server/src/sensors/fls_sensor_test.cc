// The forward-looking sonar kind alone (no Bullet): a ping of a real Embree world on the ray-cast service's
// workers against the geometry, its determinism and its message (the Oculus driver's convention).
#include "hadal/sensors/fls_sensor.h"

#include <gtest/gtest.h>
#include <marine_acoustic_msgs.h>
#include <sensor_msgs.h>

#include <algorithm>
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

// Above the plane seabed [m]: the fan's edges then meet it mid-bin (14.375 m and 27.016 m, bins 140.5 and
// 268.5), so that jitter within a ray cell and the patches' spread cannot move them to a neighbouring bin.
constexpr double kAltitude = 9.24;
constexpr double kTilt = 30.0 * kDegToRad;  // the fan's centre below the horizontal
const Eigen::Isometry3d kX_BS = pose(Eigen::Vector3d::Zero(), rpy(0.0, kTilt, 0.0));

Model world_model() { return testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -100.0 + kAltitude)); }

FlsSensor::Spec quiet_spec(bool float32 = false) {
  FlsSensor::Spec spec;
  spec.beams = 64;
  spec.fov = 60.0 * kDegToRad;
  spec.beam_width = 1.0 * kDegToRad;
  spec.vertical_aperture = 20.0 * kDegToRad;
  spec.acoustics.max_range = 40.0;
  spec.acoustics.bins = 400;  // 9.875 cm
  spec.acoustics.speckle = false;
  spec.acoustics.receiver_noise = false;
  spec.encoding.float32 = float32;
  FlsSensor::make_ping(spec);
  return spec;
}

// The centre beams see the seabed between the ranges where the aperture's edges meet it: altitude /
// sin(tilt + aperture / 2) = 14.37 m and altitude / sin(tilt - aperture / 2) = 27.02 m (the outermost rays
// lie within 0.02 deg of the edges: 6 mm of range), nothing before or after; the image is range-major.
TEST(FlsSensorTest, TheFanMeetsTheSeabedWhereTheGeometrySays) {
  SensorTestWorld world(world_model(), true);
  const FlsSensor::Spec spec = quiet_spec(true);
  const FlsSensor::State state = world.initial_state<FlsSensor>(spec, 5.0, "fls");
  const FlsSensor::Capture ping = testing::capture<FlsSensor>(world, spec, state, kX_BS);
  const std::size_t beams = 64, bins = 400;
  ASSERT_EQ(ping.image.size(), 4 * beams * bins);
  const double near = kAltitude / std::sin(kTilt + 10.0 * kDegToRad), far = kAltitude / std::sin(kTilt - 10.0 * kDegToRad);
  for (std::size_t k : {31u, 32u}) {
    int first = -1, last = -1;
    for (std::size_t b = 0; b < bins; ++b) {
      if (testing::float32_sample(ping.image, b * beams + k) > 0.0f) {
        if (first < 0) first = static_cast<int>(b);
        last = static_cast<int>(b);
      }
    }
    EXPECT_EQ(first, spec.ping->bin_of(near)) << k;
    EXPECT_EQ(last, spec.ping->bin_of(far)) << k;
  }
  // The water at the sonar (90.76 m deep, the default constant-density water).
  const double depth = 100.0 - kAltitude;
  EXPECT_DOUBLE_EQ(ping.water.sound_speed_m_per_s, world.ocean.sound_speed(depth));
  EXPECT_DOUBLE_EQ(ping.water.absorption_db_per_m, world.ocean.sound_absorption_db_per_m(depth, 400e3));
}

// Same seed and ping step: the same image; another step draws other speckle. uint8 samples map the level
// linearly onto the display window.
TEST(FlsSensorTest, SpeckleIsSeededPerPing) {
  SensorTestWorld world(world_model(), true);
  FlsSensor::Spec spec = quiet_spec();
  spec.acoustics.speckle = true;
  spec.acoustics.receiver_noise = true;
  FlsSensor::make_ping(spec);
  const FlsSensor::State state = world.initial_state<FlsSensor>(spec, 5.0, "fls");
  const FlsSensor::Capture a = testing::capture<FlsSensor>(world, spec, state, kX_BS, 7);
  EXPECT_EQ(a.image, testing::capture<FlsSensor>(world, spec, state, kX_BS, 7).image);
  EXPECT_NE(a.image, testing::capture<FlsSensor>(world, spec, state, kX_BS, 8).image);
  SonarImageEncoding encoding;
  std::uint8_t v = 0;
  encoding.encode(static_cast<float>(std::pow(10.0, 13.5)), &v);  // 135 dB: halfway through [100, 170]
  EXPECT_EQ(v, 128);
  encoding.encode(1e30f, &v);
  EXPECT_EQ(v, 255);
  encoding.encode(0.0f, &v);
  EXPECT_EQ(v, 0);
}

// ProjectedSonarImage as the UW-APL Oculus driver fills it: beam k's direction (0, -sin phi, cos phi),
// ranges at the bin centres, range-major samples, per-beam widths, the sound speed at the sonar.
TEST(FlsSensorTest, MessageFollowsTheOculusDriversConvention) {
  SensorTestWorld world(world_model(), true);
  const FlsSensor::Spec spec = quiet_spec();
  FlsSensor::State state = world.initial_state<FlsSensor>(spec, 5.0, "fls");
  FlsSensor::Capture ping = testing::capture<FlsSensor>(world, spec, state, kX_BS);
  const std::vector<std::uint8_t> image = ping.image;
  state.image = std::move(ping.image);
  state.sound_speed_m_per_s = ping.water.sound_speed_m_per_s;
  marine_acoustic_msgs::msg::ProjectedSonarImage msg;
  const std::string frame = "auv/fls";
  FlsSensor::ImageTopic::fill(spec, state, MessageHeader{12.5, frame, 5.0}, msg);
  EXPECT_EQ(msg.header().frame_id(), frame);
  EXPECT_EQ(msg.header().stamp().sec(), 12);
  EXPECT_EQ(msg.header().stamp().nanosec(), 500000000u);
  EXPECT_FLOAT_EQ(msg.ping_info().frequency(), 400e3f);
  EXPECT_FLOAT_EQ(msg.ping_info().sound_speed(), static_cast<float>(world.ocean.sound_speed(100.0 - kAltitude)));
  ASSERT_EQ(msg.ping_info().rx_beamwidths().size(), 64u);
  EXPECT_FLOAT_EQ(msg.ping_info().rx_beamwidths()[3], static_cast<float>(1.0 * kDegToRad));
  EXPECT_FLOAT_EQ(msg.ping_info().tx_beamwidths()[3], static_cast<float>(20.0 * kDegToRad));
  ASSERT_EQ(msg.beam_directions().size(), 64u);
  for (int k : {0, 20, 63}) {
    const double phi = FlsSensor::beam_azimuth(spec, k);
    EXPECT_DOUBLE_EQ(msg.beam_directions()[k].x(), 0.0);
    EXPECT_DOUBLE_EQ(msg.beam_directions()[k].y(), -std::sin(phi));
    EXPECT_DOUBLE_EQ(msg.beam_directions()[k].z(), std::cos(phi));
  }
  EXPECT_NEAR(FlsSensor::beam_azimuth(spec, 0), -30.0 * kDegToRad + 0.5 * kDegToRad * 60.0 / 64.0, 1e-15);
  ASSERT_EQ(msg.ranges().size(), 400u);
  EXPECT_FLOAT_EQ(msg.ranges()[0], static_cast<float>(0.5 + 0.5 * 39.5 / 400.0));
  EXPECT_FLOAT_EQ(msg.ranges()[399], static_cast<float>(40.0 - 0.5 * 39.5 / 400.0));
  EXPECT_FALSE(msg.image().is_bigendian());
  EXPECT_EQ(msg.image().dtype(), marine_acoustic_msgs::msg::SonarImageData_Constants::DTYPE_UINT8);
  EXPECT_EQ(msg.image().beam_count(), 64u);
  EXPECT_EQ(msg.image().data(), image);
}

// The fan seen from above (the preview, hadal-validate-sonar): 4 beams over 60 deg, 10 bins of 1 m from 0 m,
// 20 px per m (220 rows, 10 px margins); sample (bin b, beam k) = 10 k + b + 1. A pixel's centre at azimuth
// +20 deg (port, the image's left) and 7.5 m lies in beam floor((20 + 30) / 60 x 4) = 3 and bin 7; outside
// the fan and beyond the window the fan is black; a float32 sample is its level over the display window;
// the preview message carries the fan as mono8.
TEST(FlsSensorTest, FanImagePutsEachSampleAtItsBearingAndRange) {
  FlsSensor::Spec spec;
  spec.beams = 4;
  spec.fov = 60.0 * kDegToRad;
  spec.acoustics.min_range = 0.0;
  spec.acoustics.max_range = 10.0;
  spec.acoustics.bins = 10;
  FlsSensor::make_ping(spec);
  std::vector<std::uint8_t> samples(40);
  for (int b = 0; b < 10; ++b) {
    for (int k = 0; k < 4; ++k) samples[static_cast<std::size_t>(b * 4 + k)] = static_cast<std::uint8_t>(10 * k + b + 1);
  }
  const FlsSensor::FanImage fan = FlsSensor::fan_image(spec, samples, 220);
  ASSERT_EQ(fan.height, 220);
  EXPECT_DOUBLE_EQ(fan.px_per_m, 20.0);
  EXPECT_EQ(fan.width, 2 * 10 + static_cast<int>(std::ceil(2.0 * 10.0 * std::sin(30.0 * kDegToRad) * 20.0)));
  ASSERT_EQ(fan.grey.size(), static_cast<std::size_t>(fan.width * fan.height));
  const auto at = [&](double azimuth_deg, double range_m) {
    const double x = -range_m * std::sin(azimuth_deg * kDegToRad), y = range_m * std::cos(azimuth_deg * kDegToRad);
    const int u = static_cast<int>(std::floor(fan.apex_u + x * fan.px_per_m));
    const int v = static_cast<int>(std::floor(fan.apex_v - y * fan.px_per_m));
    return fan.grey[static_cast<std::size_t>(v * fan.width + u)];
  };
  EXPECT_EQ(at(20.0, 7.5), 10 * 3 + 7 + 1);
  EXPECT_EQ(at(-20.0, 2.5), 10 * 0 + 2 + 1);
  EXPECT_EQ(at(-5.0, 9.5), 10 * 1 + 9 + 1);
  EXPECT_EQ(at(40.0, 5.0), 0);   // outside the fan
  EXPECT_EQ(at(0.0, 10.3), 0);   // beyond the window
  // float32: 10^13.5 uPa^2 is 135 dB, half-way up the 100-170 dB window.
  spec.encoding.float32 = true;
  std::vector<std::uint8_t> levels(40 * 4);
  const float intensity = std::pow(10.0f, 13.5f);
  for (std::size_t i = 0; i < 40; ++i) std::memcpy(&levels[4 * i], &intensity, 4);
  EXPECT_EQ(FlsSensor::fan_image(spec, levels, 220).grey[static_cast<std::size_t>(fan.apex_v - 100) * fan.width + fan.apex_u], 128);
  // Samples of the wrong size: black.
  const FlsSensor::FanImage black = FlsSensor::fan_image(spec, samples, 220);
  EXPECT_TRUE(std::all_of(black.grey.begin(), black.grey.end(), [](std::uint8_t g) { return g == 0; }));
  FlsSensor::State state;
  state.image = levels;
  sensor_msgs::msg::Image preview;
  FlsSensor::ImageTopic::fill_preview(spec, state, MessageHeader{1.5, "auv/fls", 5.0}, preview);
  EXPECT_EQ(preview.encoding(), "mono8");
  EXPECT_EQ(static_cast<int>(preview.height()), FlsSensor::kPreviewHeight);
  EXPECT_EQ(preview.step(), preview.width());
  EXPECT_EQ(preview.data().size(), static_cast<std::size_t>(preview.width() * preview.height()));
  EXPECT_EQ(preview.header().frame_id(), "auv/fls");
  EXPECT_EQ(preview.header().stamp().sec(), 1);
}

}  // namespace
}  // namespace hadal::sensors
