// The profiler kind alone (no Bullet): its rays from a capture's snapshot, traced by the ray-cast
// service over a view of a real Embree world, closed forms over a plane, the REP 117 window, noise
// and its message.
#include "hadal/sensors/profiler_sensor.h"

#include <gtest/gtest.h>
#include <sensor_msgs.h>

#include <cfloat>
#include <cmath>
#include <limits>

#include "hadal/geometry/raycast_service.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::rpy;
using testing::SensorTestWorld;

constexpr double kSeabedZ = -100.0;

// Looking straight down with the fan across the track: x_S down, y_S to port, z_S forward.
const Eigen::Isometry3d kX_BS = pose(Eigen::Vector3d(0.0, 0.0, -0.2), rpy(0.0, EIGEN_PI / 2.0, 0.0));

ProfilerSensor::Spec exact(int beams = 64, int rays = 5) {
  ProfilerSensor::Spec spec;
  spec.beams = beams;
  spec.rays_per_beam = rays;
  spec.fov = 90.0 * kDegToRad;
  spec.beam_width = 1.0 * kDegToRad;
  spec.noise_stddev = 0.0;
  spec.resolution = 0.0;
  spec.max_range = 100.0;
  return spec;
}

// A capture of the vehicle's profiler at its state, traced by a ray-cast service over the world.
geometry::RayHits cast(SensorTestWorld& world, const ProfilerSensor::Spec& spec) {
  std::vector<Eigen::Isometry3d> X_WB;
  for (const VehicleState& vehicle : world.state.vehicles) X_WB.push_back(vehicle.body.X_WB);
  const CaptureContext context{world.state.time, world.state.step_count, X_WB, 0, kX_BS};
  geometry::RaycastService service(world.rays->scene().view(), {1});
  return service.submit(ProfilerSensor::capture_rays(context, spec)).get();
}

// The rays: beams x rays_per_beam from S's origin, in S's x-y plane at the documented angles, passing
// through their own vehicle, stopping 1 % past max_range; the batch carries the snapshot.
TEST(ProfilerSensorTest, RaysSpanEachBeamInTheFanPlane) {
  const ProfilerSensor::Spec spec = exact(4, 3);
  const std::vector<Eigen::Isometry3d> X_WB = {pose(Eigen::Vector3d(1, 2, -30), rpy(0, 0, 0.3))};
  const CaptureContext context{1.5, 750, X_WB, 0, kX_BS};
  const geometry::RayBatch batch = ProfilerSensor::capture_rays(context, spec);
  ASSERT_EQ(batch.size(), 12u);
  EXPECT_EQ(batch.sim_time, 1.5);
  EXPECT_EQ(batch.step_count, 750u);
  EXPECT_EQ(batch.X_WB.size(), 1u);
  const Eigen::Isometry3d X_WS = X_WB[0] * kX_BS;
  for (int k = 0; k < 4; ++k) {
    for (int j = 0; j < 3; ++j) {
      const std::size_t i = static_cast<std::size_t>(3 * k + j);
      const Eigen::Vector3d d_S = X_WS.linear().transpose() *
                                  Eigen::Vector3d(batch.d_W_x[i], batch.d_W_y[i], batch.d_W_z[i]).cast<double>();
      const double phi = -45.0 * kDegToRad + (k + 0.5) * 22.5 * kDegToRad + 1.0 * kDegToRad * ((j + 0.5) / 3 - 0.5);
      EXPECT_NEAR(std::atan2(d_S.y(), d_S.x()), phi, 1e-6) << i;
      EXPECT_NEAR(d_S.z(), 0.0, 1e-6) << i;
      EXPECT_EQ(batch.ignore_body[i], 0);
      EXPECT_EQ(batch.t_far[i], 101.0f);
      EXPECT_NEAR(batch.p_WO_z[i], X_WS.translation().z(), 1e-5);
    }
  }
  EXPECT_NEAR(ProfilerSensor::beam_angle(spec, 3), 33.75 * kDegToRad, 1e-15);
}

// Over a plane h below S, a level profiler looking down measures each beam as the nearest of its rays:
// h / cos(phi) at the ray closest to the vertical (Embree is float: 4 ulp of 100 m).
TEST(ProfilerSensorTest, NearestRayOfEachBeamOverAPlane) {
  SensorTestWorld world(testing::one_vehicle_world(Eigen::Vector3d(0, 0, kSeabedZ + 40.2), kSeabedZ), true);
  const ProfilerSensor::Spec spec = exact();
  ProfilerSensor::State state = world.initial_state<ProfilerSensor>(spec, 10.0);
  const geometry::RayHits hits = cast(world, spec);
  const SampleContext context{0.0, 0.1, 0.002, world.model.world, world.ocean, world.environment, world.state, 0,
                              kX_BS, world.p_BBcm, world.v_WBcm_step_start, world.w_WB_step_start, nullptr};
  ProfilerSensor::deliver(context, spec, state, hits);
  ASSERT_EQ(state.ranges.size(), 64u);
  for (int k = 0; k < spec.beams; ++k) {
    double nearest_angle = 1e9;
    for (int j = 0; j < spec.rays_per_beam; ++j) {
      const double phi = ProfilerSensor::beam_angle(spec, k) + spec.beam_width * ((j + 0.5) / spec.rays_per_beam - 0.5);
      nearest_angle = std::min(nearest_angle, std::abs(phi));
    }
    EXPECT_NEAR(state.ranges[static_cast<std::size_t>(k)], 40.0 / std::cos(nearest_angle), 4 * FLT_EPSILON * 100.0) << k;
  }
}

// Closer than min_range: -inf; no hit within max_range: +inf; noise of 2 cm per beam gives the
// configured spread over many beams (n = 64 x 200 scans: 4 sigma / sqrt(2 n) = 2.5 %), on the
// resolution grid.
TEST(ProfilerSensorTest, WindowAndNoise) {
  SensorTestWorld near(testing::one_vehicle_world(Eigen::Vector3d(0, 0, kSeabedZ + 0.4), kSeabedZ), true);
  ProfilerSensor::Spec spec = exact();
  ProfilerSensor::State state = near.initial_state<ProfilerSensor>(spec, 10.0);
  const SampleContext near_context{0.0, 0.1, 0.002, near.model.world, near.ocean, near.environment, near.state, 0,
                                   kX_BS, near.p_BBcm, near.v_WBcm_step_start, near.w_WB_step_start, nullptr};
  ProfilerSensor::deliver(near_context, spec, state, cast(near, spec));
  EXPECT_EQ(state.ranges[32], -std::numeric_limits<double>::infinity());  // 0.2 m < min_range 0.5 m

  SensorTestWorld far(testing::one_vehicle_world(Eigen::Vector3d(0, 0, kSeabedZ + 150.0), kSeabedZ), true);
  const SampleContext far_context{0.0, 0.1, 0.002, far.model.world, far.ocean, far.environment, far.state, 0,
                                  kX_BS, far.p_BBcm, far.v_WBcm_step_start, far.w_WB_step_start, nullptr};
  ProfilerSensor::deliver(far_context, spec, state, cast(far, spec));
  for (double range : state.ranges) EXPECT_EQ(range, std::numeric_limits<double>::infinity());

  SensorTestWorld world(testing::one_vehicle_world(Eigen::Vector3d(0, 0, kSeabedZ + 30.2), kSeabedZ), true);
  spec.noise_stddev = 0.02;
  spec.resolution = 0.001;
  const geometry::RayHits hits = cast(world, spec);
  ProfilerSensor::State ideal = world.initial_state<ProfilerSensor>(exact(), 10.0);
  ProfilerSensor::State noisy = world.initial_state<ProfilerSensor>(spec, 10.0);
  const SampleContext context{0.0, 0.1, 0.002, world.model.world, world.ocean, world.environment, world.state, 0,
                              kX_BS, world.p_BBcm, world.v_WBcm_step_start, world.w_WB_step_start, nullptr};
  ProfilerSensor::deliver(context, exact(), ideal, hits);
  double sum2 = 0.0;
  int n = 0;
  for (int scan = 0; scan < 200; ++scan) {
    ProfilerSensor::deliver(context, spec, noisy, hits);
    for (std::size_t k = 0; k < noisy.ranges.size(); ++k) {
      EXPECT_NEAR(std::remainder(noisy.ranges[k], 0.001), 0.0, 1e-9);
      const double e = noisy.ranges[k] - ideal.ranges[k];
      sum2 += e * e;
      ++n;
    }
  }
  const double sigma = std::sqrt(0.02 * 0.02 + 0.001 * 0.001 / 12.0);
  EXPECT_NEAR(std::sqrt(sum2 / n), sigma, 4.0 * sigma / std::sqrt(2.0 * n));
}

// sensor_msgs/LaserScan: the fan's angles, all beams at once, the scan period, the window and the
// ranges (infinities kept), no intensities.
TEST(ProfilerSensorTest, Message) {
  const ProfilerSensor::Spec spec = exact(4, 1);
  ProfilerSensor::State state;
  state.ranges = {10.5, -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), 3.25};
  sensor_msgs::msg::LaserScan msg;
  const std::string frame = "auv/profiler";
  ProfilerSensor::fill_message(spec, state, MessageHeader{2.5, frame, 10.0}, msg);
  EXPECT_EQ(msg.header().frame_id(), "auv/profiler");
  EXPECT_EQ(msg.header().stamp().sec(), 2);
  EXPECT_FLOAT_EQ(msg.angle_min(), static_cast<float>(-33.75 * kDegToRad));
  EXPECT_FLOAT_EQ(msg.angle_max(), static_cast<float>(33.75 * kDegToRad));
  EXPECT_FLOAT_EQ(msg.angle_increment(), static_cast<float>(22.5 * kDegToRad));
  EXPECT_EQ(msg.time_increment(), 0.0f);
  EXPECT_FLOAT_EQ(msg.scan_time(), 0.1f);
  EXPECT_EQ(msg.range_min(), 0.5f);
  EXPECT_EQ(msg.range_max(), 100.0f);
  ASSERT_EQ(msg.ranges().size(), 4u);
  EXPECT_EQ(msg.ranges()[0], 10.5f);
  EXPECT_EQ(msg.ranges()[1], -std::numeric_limits<float>::infinity());
  EXPECT_EQ(msg.ranges()[2], std::numeric_limits<float>::infinity());
  EXPECT_TRUE(msg.intensities().empty());
}

}  // namespace
}  // namespace hadal::sensors
