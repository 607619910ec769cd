// The DVL kind alone (no Bullet): its four beams ray-cast into a world scene from the sensor's pose,
// closed forms over a plane seabed, the bottom-lock window, water track, the sound-speed scale, and its
// message. The DVL library itself (beam solution, bias, noise) is tested in dvl_test.cc.
#include "hadal/sensors/dvl_sensor.h"

#include <gtest/gtest.h>
#include <marine_acoustic_msgs.h>

#include <cfloat>
#include <cmath>

#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::rpy;
using testing::SensorTestWorld;

constexpr double kSeabedZ = -100.0;

// A DVL without noise or bias, window 0.5-90 m.
DvlSensor::Spec ideal_dvl() {
  DvlSensor::Spec spec;
  spec.params.min_altitude = 0.5;
  spec.params.max_altitude = 90.0;
  return spec;
}

// A 1 x 0.4 x 0.4 m box vehicle at p_W with attitude R_WB and velocity v_W over a plane seabed; the DVL
// under its hull 0.3 m ahead of B (S: z down, x forward), inside the box: its own hull is transparent.
SensorTestWorld dvl_world(const Eigen::Vector3d& p_W, const Eigen::Matrix3d& R_WB, const Eigen::Vector3d& v_W) {
  Model model = testing::one_vehicle_world(p_W, kSeabedZ);
  CollisionShape box;
  box.type = CollisionShapeType::kBox;
  box.box_size = Eigen::Vector3d(1.0, 0.4, 0.4);
  model.vehicles[0].links[0].collisions = {box};
  model.vehicles[0].X_WB_initial.linear() = R_WB;
  model.vehicles[0].v_WB_initial = v_W;
  return SensorTestWorld(model, true);
}
const Eigen::Isometry3d kX_BS = pose(Eigen::Vector3d(0.3, 0.0, -0.19), rpy(EIGEN_PI, 0.0, 0.0));

DvlSensor::State ping(SensorTestWorld& world, const DvlSensor::Spec& spec) {
  DvlSensor::State state = world.initial_state<DvlSensor>(spec, 5.0, "dvl");
  world.sample<DvlSensor>(spec, state, kX_BS, 5.0);
  return state;
}

// Over a plane seabed, with no noise and no bias, a pitched, rolled and yawed DVL on a turning vehicle
// measures its own velocity (lever arm included) in S, each beam reads d_i . v, and each beam's range is
// the plane's distance along the beam, h / (-d_W . z). Tolerances: velocities 1e-12 m/s (double
// rounding of the 4-beam least squares); ranges 4 float ulp of the 100 m coordinates (Embree is float).
TEST(DvlSensorTest, IdealDvlOverAPlaneMeasuresItsVelocityAndTheBeamRanges) {
  const Eigen::Vector3d v_W(0.8, -0.3, 0.05);
  SensorTestWorld world = dvl_world(Eigen::Vector3d(5.0, 2.0, -60.0), rpy(0.05, -0.08, 0.6), v_W);
  world.body().w_WB = Eigen::Vector3d(0.0, 0.0, 0.1);  // yawing at 0.1 rad/s
  const DvlSensor::State state = ping(world, ideal_dvl());
  const DvlPing& p = state.ping;
  const RigidBodyState& body = world.body();
  const Eigen::Isometry3d X_WS = body.X_WB * kX_BS;
  const Eigen::Vector3d v_WS_S =
      X_WS.linear().transpose() * (body.v_WB + body.w_WB.cross(X_WS.translation() - body.X_WB.translation()));
  ASSERT_EQ(p.mode, DvlMode::kBottomTrack);
  EXPECT_EQ(p.num_good_beams, 4);
  EXPECT_TRUE(p.beam_ranges_valid);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.velocity[c], v_WS_S[c], 1e-12) << c;
  const double h = X_WS.translation().z() - kSeabedZ;
  double altitude = 0.0;
  for (int b = 0; b < kDvlBeams; ++b) {
    const Eigen::Vector3d& d_S = p.beam_unit_vec[b];
    EXPECT_NEAR(p.beam_velocity[b], d_S.dot(v_WS_S), 1e-12) << b;
    EXPECT_NEAR(p.range[b], h / -(X_WS.linear() * d_S).z(), 4 * FLT_EPSILON * 100.0) << b;
    altitude += p.range[b] * std::cos(ideal_dvl().params.beam_tilt) / 4.0;
  }
  EXPECT_DOUBLE_EQ(p.altitude, altitude);
  EXPECT_NEAR(p.speed_gnd, std::hypot(v_WS_S.x(), v_WS_S.y()), 1e-12);
}

// Level, water track off: bottom lock up to the window's 90 m, none beyond (mode none, NaN velocity).
TEST(DvlSensorTest, BottomLockEndsAtMaxAltitude) {
  DvlSensor::Spec spec = ideal_dvl();
  spec.params.water_track = false;
  const double dvl_height = 0.19;  // B above the transducer
  for (const double h : {89.9, 90.1}) {
    SensorTestWorld world = dvl_world(Eigen::Vector3d(0, 0, kSeabedZ + h + dvl_height), Eigen::Matrix3d::Identity(),
                                      Eigen::Vector3d(0.5, 0, 0));
    const DvlPing p = ping(world, spec).ping;
    if (h < 90.0) {
      EXPECT_EQ(p.mode, DvlMode::kBottomTrack);
      EXPECT_NEAR(p.altitude, h, 1e-4);
    } else {
      EXPECT_EQ(p.mode, DvlMode::kNone);
      EXPECT_TRUE(std::isnan(p.velocity.x()));
      EXPECT_EQ(p.num_good_beams, 0);
      EXPECT_FALSE(p.beam_ranges_valid);
    }
  }
}

// Out of bottom range (150 m up) in a uniform current, water track measures the vehicle's velocity
// through the water, v_vehicle - v_water, in S (ideal DVL: to rounding).
TEST(DvlSensorTest, WaterTrackMeasuresTheVelocityRelativeToTheCurrent) {
  const Eigen::Vector3d v_W(1.0, 0.2, 0.0), u_W(0.3, -0.25, 0.02);
  Model model = dvl_world(Eigen::Vector3d(0.0, 0.0, kSeabedZ + 150.0), rpy(0.0, 0.0, 0.4), v_W).model;
  model.world.water.current.uniform_W = u_W;
  SensorTestWorld world(model, true);
  const DvlPing p = ping(world, ideal_dvl()).ping;
  ASSERT_EQ(p.mode, DvlMode::kWaterTrack);
  EXPECT_EQ(p.num_good_beams, 4);
  EXPECT_FALSE(p.beam_ranges_valid);
  const Eigen::Vector3d expected = (world.body().X_WB.linear() * kX_BS.linear()).transpose() * (v_W - u_W);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.velocity[c], expected[c], 1e-12) << c;
}

// Looking up from under the sea surface (mounted on top, S's axis up), the DVL locks on the surface: over a flat
// surface 20 m above each beam's range is 20 / cos(tilt) (double precision: the surface is no Embree mesh, 1e-9);
// under regular waves (1 m, 8 s, deep water, no build-up) at a crest its tangent plane is level, 21 m up; a quarter
// period later the surface over the DVL is at the mean level with the slope a k, and each beam meets that tilted
// plane at (0 - z) / (d_z - s_x d_x).
TEST(DvlSensorTest, LookingUpItLocksOnTheSeaSurface) {
  const Eigen::Isometry3d X_BS_up = pose(Eigen::Vector3d(0.3, 0.0, 0.19), rpy(0.0, 0.0, 0.0));
  DvlSensor::Spec spec = ideal_dvl();
  spec.params.water_track = false;
  const double cos_tilt = std::cos(spec.params.beam_tilt);
  for (const bool waves : {false, true}) {
    Model model = dvl_world(Eigen::Vector3d(-0.3, 0.0, -20.0 - 0.19), Eigen::Matrix3d::Identity(),
                            Eigen::Vector3d::Zero()).model;
    model.world.seabed.z = -1000.0;
    if (waves) {
      model.world.waves.spectrum = physics::WaveSpectrum::kRegular;
      model.world.waves.regular = {{1.0, 8.0, 0.0, 0.0}};
      model.world.waves.ramp_time = 0.0;
    }
    SensorTestWorld world(model, true);
    for (const double t : {0.0, 2.0}) {
      world.state.time = t;
      DvlSensor::State state = world.initial_state<DvlSensor>(spec, 5.0, "dvl");
      world.sample<DvlSensor>(spec, state, X_BS_up, 5.0);
      const DvlPing& p = state.ping;
      ASSERT_EQ(p.mode, DvlMode::kBottomTrack) << waves << " " << t;
      const double k = std::pow(2.0 * EIGEN_PI / 8.0, 2) / 9.80665;
      const double eta = waves ? std::cos(-2.0 * EIGEN_PI / 8.0 * t) : 0.0;
      const double slope_x = waves ? -k * std::sin(-2.0 * EIGEN_PI / 8.0 * t) : 0.0;  // d/dx of cos(k x - w t)
      for (int b = 0; b < kDvlBeams; ++b) {
        const Eigen::Vector3d d_W = p.beam_unit_vec[b];  // S's axes are W's
        EXPECT_NEAR(p.range[b], (eta + 20.0) / (d_W.z() - slope_x * d_W.x()), 1e-9) << waves << " " << t << " " << b;
        if (!waves || t == 0.0) {
          EXPECT_NEAR(p.range[b], (eta + 20.0) / cos_tilt, 1e-9);
        }
      }
    }
  }
}

// Under waves, water track measures the velocity through the water's orbital motion too: each beam's reading is
// d . (v - u_b) with u_b the mean of the current plus the waves' velocity over that beam's layer points (a DVL
// 10 m under 1 m, 8 s waves, out of bottom range; to rounding).
TEST(DvlSensorTest, WaterTrackSeesTheWavesOrbitalVelocity) {
  const Eigen::Vector3d v_W(1.0, 0.2, 0.0);
  Model model = dvl_world(Eigen::Vector3d(0.0, 0.0, -10.0), rpy(0.0, 0.0, 0.4), v_W).model;
  model.world.seabed.z = -1000.0;
  model.world.waves.spectrum = physics::WaveSpectrum::kRegular;
  model.world.waves.regular = {{1.0, 8.0, 0.0, 0.0}};
  model.world.waves.ramp_time = 0.0;
  SensorTestWorld world(model, true);
  world.state.time = 1.3;
  const DvlSensor::Spec spec = ideal_dvl();
  const DvlPing p = ping(world, spec).ping;
  ASSERT_EQ(p.mode, DvlMode::kWaterTrack);
  const Eigen::Isometry3d X_WS = world.body().X_WB * kX_BS;
  const Eigen::Matrix3d R_SW = X_WS.linear().transpose();
  const Eigen::Vector3d v_S = R_SW * v_W;
  const auto beams_S = dvl_beam_unit_vectors(spec.params);
  double largest = 0.0;
  for (int b = 0; b < kDvlBeams; ++b) {
    Eigen::Vector3d u_W = Eigen::Vector3d::Zero();
    const int n = spec.water_track_layer_samples;
    for (int j = 0; j < n; ++j) {
      u_W += world.ocean.waves().velocity_W(X_WS * water_track_layer_point(spec.params, beams_S[b], j, n), 1.3) / n;
    }
    largest = std::max(largest, u_W.norm());
    EXPECT_NEAR(p.beam_velocity[b], beams_S[b].dot(v_S - R_SW * u_W), 1e-12) << b;
  }
  EXPECT_GT(largest, 0.1);  // the orbital velocity is there: a omega e^(k z) ~ 0.3 m/s at 10 m
}

// A DVL that assumes 1450 m/s where the water's sound speed is c (UNESCO at the transducer's depth)
// scales every velocity by k = 1450 / c, and the ranges with it.
TEST(DvlSensorTest, AWrongAssumedSoundSpeedScalesTheVelocity) {
  DvlSensor::Spec spec = ideal_dvl();
  spec.params.assumed_sound_speed = 1450.0;
  SensorTestWorld world = dvl_world(Eigen::Vector3d(0.0, 0.0, -40.0), Eigen::Matrix3d::Identity(),
                                    Eigen::Vector3d(1.0, 0.0, 0.0));
  const DvlPing p = ping(world, spec).ping;
  const Eigen::Isometry3d X_WS = world.body().X_WB * kX_BS;
  const double scale = 1450.0 / world.ocean.sound_speed(-X_WS.translation().z());
  EXPECT_GT(std::abs(scale - 1.0), 0.01);  // the test means something
  const Eigen::Vector3d v_S = X_WS.linear().transpose() * Eigen::Vector3d(1.0, 0.0, 0.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.velocity[c], scale * v_S[c], 1e-12);
  EXPECT_NEAR(p.altitude, scale * (X_WS.translation().z() - kSeabedZ), 1e-4);
  EXPECT_EQ(p.sound_speed, 1450.0);
}

// marine_acoustic_msgs/Dvl: modes, NaN / -1 for what a ping lacks, row-major covariance.
TEST(DvlSensorTest, Message) {
  DvlSensor::State state;
  DvlPing& p = state.ping;
  p.mode = DvlMode::kWaterTrack;
  p.velocity = Eigen::Vector3d(0.5, -0.1, 0.02);
  p.velocity_covariance = Eigen::Matrix3d::Identity() * 1e-4;
  p.velocity_covariance(0, 1) = 2e-5;
  p.num_good_beams = 3;
  p.sound_speed = 1490.5;
  p.beam_velocities_valid = true;
  p.beam_unit_vec = dvl_beam_unit_vectors(kPi / 6.0, kPi / 4.0);
  p.range = {10.0, std::nan(""), 10.5, 11.0};
  p.beam_velocity = {0.25, std::nan(""), 0.3, 0.35};
  p.beam_velocity_covar = {1e-4, -1.0, 1e-4, 1e-4};
  marine_acoustic_msgs::msg::Dvl msg;
  const std::string frame = "auv/dvl";
  DvlSensor::fill_message(DvlSensor::Spec{}, state, MessageHeader{12.25, frame, 5.0}, msg);
  EXPECT_EQ(msg.header().frame_id(), "auv/dvl");
  EXPECT_EQ(msg.header().stamp().sec(), 12);
  EXPECT_EQ(msg.header().stamp().nanosec(), 250000000u);
  EXPECT_EQ(msg.velocity_mode(), marine_acoustic_msgs::msg::Dvl_Constants::DVL_MODE_WATER);
  EXPECT_EQ(msg.velocity().x(), 0.5);
  EXPECT_EQ(msg.velocity_covar()[1], 2e-5);  // row-major
  EXPECT_EQ(msg.velocity_covar()[3], 0.0);
  EXPECT_EQ(msg.num_good_beams(), 3);
  EXPECT_EQ(msg.sound_speed(), 1490.5f);
  EXPECT_TRUE(msg.beam_velocities_valid());
  EXPECT_FALSE(msg.beam_ranges_valid());
  EXPECT_EQ(msg.beam_unit_vec()[2].z(), p.beam_unit_vec[2].z());
  EXPECT_EQ(msg.range()[3], 11.0);
  EXPECT_TRUE(std::isnan(msg.range()[1]));
  EXPECT_EQ(msg.beam_velocity()[2], 0.3f);
  EXPECT_EQ(msg.beam_velocity_covar()[1], -1.0f);
  p.mode = DvlMode::kNone;
  DvlSensor::fill_message(DvlSensor::Spec{}, state, MessageHeader{12.25, frame, 5.0}, msg);
  EXPECT_EQ(msg.velocity_mode(), 0);
}

}  // namespace
}  // namespace hadal::sensors
