// The sensor accessors of libhadal_client end to end: a real hadald, real Fast DDS, the default AUV's
// sensors (configs/vehicles/torpedo_auv.yaml). Each test reserves its own DDS domain (DomainLease).
//
// Two scenarios: the default one (the AUV at 50 m depth, its survey schedule running) and a "still" one
// written by the test: the AUV alone, level, heading east, with no command, over a plane seabed, so the
// sensors' ideal values are closed forms. Under water it is only ~1 N buoyant: at rest it rises ~1 cm
// and pitches < 3e-4 rad in the first second. Above the water the test turns gravity off so the AUV
// stays where it is put. (Not under water: with world.gravity zero the ocean's hydrostatics fall back
// to g = 9.80665 m/s^2 (server/src/physics/ocean.cc), so a weightless AUV would be pushed up by its
// full buoyancy.)

#include "hadal_client/client.h"
#include "lockstep_server.h"
#include "server_process.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>

namespace hadal::test {
namespace {

constexpr double kStepSize = 0.002;  // physics_rate_hz 500 in both scenarios [s]

// A scenario file for the life of the object: the default AUV alone at (0, 0, z), level, yaw 0 (body x
// east), moving east at v_x, no command; gravity g_z (m/s^2, along W z); a plane seabed at z = -100 m,
// world origin 43 N 5 E on the WGS84 ellipsoid, date 2026-06-01 (as the default scenario).
class StillScenario {
 public:
  StillScenario(double z, double v_x = 0.0, double g_z = -9.80665, double v_y = 0.0)
      : path_("/tmp/hadal-sensor-client-test-" + std::to_string(::getpid()) + "-" + std::to_string(++count_) +
              ".yaml") {
    std::ofstream f(path_);
    f << "world:\n"
         "  physics_rate_hz: 500\n"
         "  seed: 11\n"
         "  gravity: [0.0, 0.0, "
      << g_z
      << "]\n"
         "  date: \"2026-06-01\"\n"
         "  water: {surface_z: 0.0, density: 1025.0}\n"
         "  seabed: {type: plane, z: -100.0}\n"
         "  origin: {latitude_deg: 43.0, longitude_deg: 5.0, altitude: 0.0}\n"
         "vehicles:\n"
         "  - name: auv\n"
         "    include: "
      << source_path("configs/vehicles/torpedo_auv.yaml")
      << "\n"
         "    initial_pose: {position: [0.0, 0.0, "
      << z
      << "], rpy_deg: [0.0, 0.0, 0.0]}\n"
         "    initial_velocity: ["
      << v_x << ", " << v_y << ", 0.0]\n";
  }
  ~StillScenario() { std::remove(path_.c_str()); }
  StillScenario(const StillScenario&) = delete;
  StillScenario& operator=(const StillScenario&) = delete;
  const std::string& path() const { return path_; }

 private:
  static inline int count_ = 0;
  std::string path_;
};

std::string default_scenario() { return source_path("configs/scenarios/default.yaml"); }

// True when `stamp` is a whole number of periods of `rate_hz` (stamps are sim times, multiples of
// the 2 ms step: 1e-6 of a period is far below one step and far above rounding).
bool on_schedule(double stamp, double rate_hz) {
  return std::abs(stamp * rate_hz - std::round(stamp * rate_hz)) < 1e-6;
}

double norm(const std::array<double, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// ---- magnetometer (sensor_msgs/MagneticField) ----------------------------------------------------

// Default scenario, 1 s of lockstep: 20 Hz samples in frame auv/magnetometer whose magnitude is Earth's
// field at 43 N 5 E (WMM2025: F = 46.7 uT; 40..52 uT leaves room for any attitude, the 5.8 nT motor
// dipole and 5 nT of noise), with the configured covariance: diagonal (5 nT)^2 + (1 nT)^2 / 12
// (white noise plus quantisation of the 1 nT resolution), 1e-9 relative for rounding.
TEST(SensorClientTest, MagnetometerReadsTheEarthFieldInItsFrame) {
  LockstepServer s(default_scenario());
  SampleLog<MagneticField> magnetometer;
  s.client().on_magnetic_field("auv", "magnetometer", [&](const MagneticField& m) { magnetometer.add(m); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  const double t = s.client().step(500);
  ASSERT_TRUE(wait_until([&] { return magnetometer.has(t); }, kWait));
  const std::map<double, MagneticField> samples = magnetometer.all();
  ASSERT_GE(samples.size(), 20u);  // 0.05 .. 1.00 s (+ t = 0 if it arrived after the match)
  const double variance = 5e-9 * 5e-9 + 1e-9 * 1e-9 / 12.0;
  for (const auto& [stamp, m] : samples) {
    EXPECT_TRUE(on_schedule(stamp, 20.0)) << stamp;
    EXPECT_EQ(m.frame_id, "auv/magnetometer");
    const double field = norm(m.magnetic_field);
    EXPECT_GT(field, 40e-6) << stamp;
    EXPECT_LT(field, 52e-6) << stamp;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        if (r == c) {
          EXPECT_NEAR(m.magnetic_field_covariance[3 * r + c], variance, 1e-9 * variance);
        } else {
          EXPECT_EQ(m.magnetic_field_covariance[3 * r + c], 0.0);
        }
      }
    }
  }
}

// Still AUV 50 m deep, level, heading east (yaw 0: sensor x = east, y = north, z = up): the reading is
// WMM2025 at 43 N 5 E, -0.05 km, 2026.41 (`hadal-geomag 43 5 -0.05 2026.41`, which reproduces NOAA's
// test values: north X = 24140.0, east Y = 1136.8, down Z = 39982.9 nT), so B_S = (Y, X, -Z), plus the
// motor's hard-iron dipole, 5.8 nT along +x at the sensor. Tolerance 40 nT: 5 sigma of the 5 nT noise
// (25 nT), 1 nT resolution, < 12 nT from the < 3e-4 rad of pitch the resting AUV picks up in 1 s, < 1 nT
// for the ~1 cm rise and the date rounding (secular change ~50 nT/yr).
TEST(SensorClientTest, MagnetometerMatchesTheWorldMagneticModelAxisByAxis) {
  StillScenario scenario(-50.0);
  LockstepServer s(scenario.path());
  SampleLog<MagneticField> magnetometer;
  s.client().on_magnetic_field("auv", "magnetometer", [&](const MagneticField& m) { magnetometer.add(m); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  const double t = s.client().step(500);
  ASSERT_TRUE(wait_until([&] { return magnetometer.has(t); }, kWait));
  const std::array<double, 3> expected = {(1136.8 + 5.8) * 1e-9, 24140.0e-9, -39982.9e-9};
  for (const auto& [stamp, m] : magnetometer.all()) {
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(m.magnetic_field[a], expected[a], 40e-9) << "axis " << a << " t " << stamp;
  }
}

// ---- GPS (sensor_msgs/NavSatFix) -----------------------------------------------------------------

// Default scenario, 2 s of lockstep: the antenna is ~50 m under water, so every 1 Hz sample is
// STATUS_NO_FIX with NaN position, still stamped, framed and carrying the configured covariance
// (1.5 m horizontal, 3 m vertical: diagonal 2.25, 2.25, 9 m^2, exact).
TEST(SensorClientTest, GpsUnderWaterReportsNoFix) {
  LockstepServer s(default_scenario());
  SampleLog<NavSatFix> gps;
  s.client().on_nav_sat_fix("auv", "gps", [&](const NavSatFix& m) { gps.add(m); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  const double t = s.client().step(1000);
  ASSERT_NEAR(t, 1000 * kStepSize, 1e-12);
  ASSERT_TRUE(wait_until([&] { return gps.has(t); }, kWait));
  const std::map<double, NavSatFix> samples = gps.all();
  ASSERT_TRUE(gps.has(1.0));
  for (const auto& [stamp, m] : samples) {
    EXPECT_TRUE(on_schedule(stamp, 1.0)) << stamp;
    EXPECT_EQ(m.frame_id, "auv/gps");
    EXPECT_EQ(m.status, NavSatFix::kStatusNoFix);
    EXPECT_EQ(m.status, -1);
    EXPECT_FALSE(m.has_fix());
    EXPECT_EQ(m.service, NavSatFix::kServiceGps);
    EXPECT_TRUE(std::isnan(m.latitude));
    EXPECT_TRUE(std::isnan(m.longitude));
    EXPECT_TRUE(std::isnan(m.altitude));
    EXPECT_EQ(m.position_covariance, (std::array<double, 9>{2.25, 0, 0, 0, 2.25, 0, 0, 0, 9.0}));
    EXPECT_EQ(m.position_covariance_type, NavSatFix::kCovarianceTypeDiagonalKnown);
  }
}

// AUV held 1 m above the surface (gravity off, nothing else acts on it in air): the antenna at
// (-0.3, 0, 1.12) m in W has a fix at the origin 43 N 5 E. Tolerances: 5 sigma of the configured noise, 7.5 m
// horizontally (converted with the WGS84 radii of curvature at 43 N, M = 6.3636e6 m, N = 6.3882e6 m;
// the 0.3 m offset is inside that bound) and 15 m vertically.
TEST(SensorClientTest, GpsAboveTheWaterFixesAtTheOrigin) {
  StillScenario scenario(1.0, 0.0, 0.0);
  LockstepServer s(scenario.path());
  SampleLog<NavSatFix> gps;
  s.client().on_nav_sat_fix("auv", "gps", [&](const NavSatFix& m) { gps.add(m); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  const double t = s.client().step(1000);
  ASSERT_TRUE(wait_until([&] { return gps.has(t); }, kWait));
  ASSERT_TRUE(gps.has(1.0));
  const double deg = M_PI / 180.0;
  for (const auto& [stamp, m] : gps.all()) {
    EXPECT_EQ(m.frame_id, "auv/gps");
    EXPECT_TRUE(m.has_fix()) << stamp;
    EXPECT_EQ(m.status, NavSatFix::kStatusFix);
    const double north = (m.latitude - 43.0) * deg * 6.3636e6;
    const double east = (m.longitude - 5.0) * deg * 6.3882e6 * std::cos(43.0 * deg);
    EXPECT_LT(std::hypot(north, east), 7.5) << "north " << north << " east " << east;
    EXPECT_NEAR(m.altitude, 1.12, 15.0);
  }
}

// ---- DVL (marine_acoustic_msgs/Dvl): enable once the server's `dvl` sensor is on main --------------

// AUV 20 m above the plane seabed (z = -80), coasting from 0.5 m/s east and 0.4 m/s north (so forward and sideways
// along B's x and y, told apart; the hull's side drag damps the sideways part to ~0.16 m/s at the first ping and to
// millimetres per second within 2 s) and slowed only by drag, 2 s of lockstep. The 5 Hz pings in frame auv/dvl
// bottom-track on all 4 beams; the altitude is 20 m within 0.5 m (transducer mounted within the hull radius, 0.08
// m, of the centre; range noise of a DVL at 20 m is ~1 % per beam, averaged over 4); each beam's slant range times
// the cosine of its angle to the (vertical) DVL axis gives the same altitude; the velocity matches the ground truth
// at the same sim time within 0.05 m/s (single-ping noise of a few mm/s to ~1 cm/s; the vehicle barely rotates, so
// the lever arm adds < 1 mm/s; its ~1 cm/s rise shows in z), in the DVL's frame: mounted rolled 180 deg
// (torpedo_auv.yaml): its x along B's x, its y and z against B's, so a sideways drift to B's +y reads negative.
TEST(SensorClientTest, DvlBottomTracksACoastingVehicleOverAPlaneSeabed) {
  StillScenario scenario(-80.0, 0.5, -9.80665, 0.4);
  LockstepServer s(scenario.path());
  SampleLog<Dvl> dvl;
  SampleLog<Odometry> odometry;
  s.client().on_dvl("auv", "dvl", [&](const Dvl& m) { dvl.add(m); });
  s.client().on_odometry("auv", [&](const Odometry& o) { odometry.add(o); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  const double t = s.client().step(1000);
  ASSERT_TRUE(wait_until([&] { return dvl.has(t) && odometry.has(t); }, kWait));
  const std::map<double, Dvl> samples = dvl.all();
  ASSERT_GE(samples.size(), 10u);  // 0.2 .. 2.0 s
  ASSERT_TRUE(odometry.has(samples.begin()->first));
  // At the first ping the drift sideways is well above the tolerance: a y read with the wrong sign misses.
  EXPECT_GT(odometry.at(samples.begin()->first).v_WB_B[1], 0.12);
  for (const auto& [stamp, m] : samples) {
    SCOPED_TRACE("t = " + std::to_string(stamp));
    EXPECT_TRUE(on_schedule(stamp, 5.0));
    EXPECT_EQ(m.frame_id, "auv/dvl");
    EXPECT_EQ(m.velocity_mode, Dvl::kVelocityModeBottomTrack);
    EXPECT_TRUE(m.dvl_type == Dvl::kDvlTypePiston || m.dvl_type == Dvl::kDvlTypePhasedArray);
    EXPECT_EQ(m.num_good_beams, 4);
    EXPECT_TRUE(m.beam_ranges_valid);
    EXPECT_TRUE(m.beam_velocities_valid);
    EXPECT_GT(m.sound_speed, 1400.0);  // seawater: 1400..1600 m/s
    EXPECT_LT(m.sound_speed, 1600.0);
    EXPECT_NEAR(m.altitude, 20.0, 0.5);
    for (int b = 0; b < 4; ++b) {
      EXPECT_NEAR(norm(m.beam_unit_vec[b]), 1.0, 1e-6) << "beam " << b;
      EXPECT_NEAR(m.ranges[b] * std::abs(m.beam_unit_vec[b][2]), 20.0, 0.5) << "beam " << b;
      EXPECT_GE(m.range_covariance[b], 0.0);
      EXPECT_GE(m.beam_velocity_covariance[b], 0.0);
    }
    EXPECT_NEAR(m.speed_gnd, std::hypot(m.velocity[0], m.velocity[1]), 1e-9);
    EXPECT_NEAR(m.course_gnd, std::atan2(m.velocity[1], m.velocity[0]), 1e-9);
    ASSERT_TRUE(odometry.has(stamp));
    const Odometry truth = odometry.at(stamp);
    EXPECT_GT(truth.v_WB_B[0], 0.3);  // still coasting: the comparison is not between zeros
    EXPECT_NEAR(m.velocity[0], truth.v_WB_B[0], 0.05);
    EXPECT_NEAR(m.velocity[1], -truth.v_WB_B[1], 0.05);
    EXPECT_NEAR(m.velocity[2], -truth.v_WB_B[2], 0.05);
  }
}

// Default scenario, 2 s: the AUV's DVL pings at 5 Hz in frame auv/dvl with bottom lock ~4 m above
// the generated seabed (the plain around the start lies at -100 m, tilted 1 deg; the AUV starts at
// -96 m and the DVL sits 0.08 m below its axis: 3..5 m).
TEST(SensorClientTest, DvlStreamOfTheDefaultAuv) {
  LockstepServer s(default_scenario());
  SampleLog<Dvl> dvl;
  s.client().on_dvl("auv", "dvl", [&](const Dvl& m) { dvl.add(m); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  const double t = s.client().step(1000);
  ASSERT_TRUE(wait_until([&] { return dvl.has(t); }, kWait));
  const std::map<double, Dvl> samples = dvl.all();
  ASSERT_GE(samples.size(), 10u);
  for (const auto& [stamp, m] : samples) {
    EXPECT_TRUE(on_schedule(stamp, 5.0)) << stamp;
    EXPECT_EQ(m.frame_id, "auv/dvl");
    EXPECT_EQ(m.velocity_mode, Dvl::kVelocityModeBottomTrack) << stamp;
    EXPECT_GE(m.num_good_beams, 3) << stamp;
    EXPECT_GT(m.altitude, 3.0) << stamp;
    EXPECT_LT(m.altitude, 5.0) << stamp;
  }
}

// ---- altimeter (sensor_msgs/Range) ------------------------------------------------------------------

// AUV at rest 20 m above the plane seabed: 10 Hz samples in frame auv/altimeter, an acoustic beam
// (ULTRASOUND, the closest ROS radiation type) with a cone in (0, pi), and range = 20 m within 0.5 m
// (mounted within the hull radius of the centre, looking straight down; the AUV rises ~2 cm in 2 s;
// altimeter noise ~0.1-1 % of range), inside [min_range, max_range].
TEST(SensorClientTest, RangeOfTheAltimeterIsTheHeightAboveAPlaneSeabed) {
  StillScenario scenario(-80.0);
  LockstepServer s(scenario.path());
  SampleLog<Range> altimeter;
  s.client().on_range("auv", "altimeter", [&](const Range& m) { altimeter.add(m); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  const double t = s.client().step(1000);
  ASSERT_TRUE(wait_until([&] { return altimeter.has(t); }, kWait));
  const std::map<double, Range> samples = altimeter.all();
  ASSERT_GE(samples.size(), 20u);  // 0.1 .. 2.0 s
  for (const auto& [stamp, m] : samples) {
    EXPECT_TRUE(on_schedule(stamp, 10.0)) << stamp;
    EXPECT_EQ(m.frame_id, "auv/altimeter");
    EXPECT_EQ(m.radiation_type, Range::kUltrasound);
    EXPECT_GT(m.field_of_view, 0.0);
    EXPECT_LT(m.field_of_view, M_PI);
    EXPECT_GE(m.range, m.min_range) << stamp;
    EXPECT_LE(m.range, m.max_range) << stamp;
    EXPECT_NEAR(m.range, 20.0, 0.5) << stamp;
  }
}

// ---- profiler (sensor_msgs/LaserScan, captured asynchronously) ------------------------------------

// tests/integration/scenarios/profiler.yaml: scans taken at 0.1 s and 0.2 s are published 0.05 s later,
// within the lockstep request that covers that time, stamped with the scan's time; the beams nearest the
// vertical read the 40 m to the plane (float message, Embree float: 1e-4 m).
TEST(SensorClientTest, ProfilerScansArriveTheirLatencyAfterTheScanStampedWithIt) {
  LockstepServer s("tests/integration/scenarios/profiler.yaml");
  SampleLog<LaserScan> scans;
  s.client().on_laser_scan("auv", "profiler", [&](const LaserScan& m) { scans.add(m); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  EXPECT_NEAR(s.client().step(100), 0.2, 1e-12);  // scans taken at 0.1 s (out at 0.15 s) and 0.2 s
  ASSERT_TRUE(wait_until([&] { return scans.has(0.1); }, kWait));
  EXPECT_NEAR(s.client().step(24), 0.248, 1e-12);
  EXPECT_FALSE(scans.has(0.2));  // due at 0.25 s: the server has not published it (no timing involved)
  EXPECT_NEAR(s.client().step(1), 0.25, 1e-12);
  ASSERT_TRUE(wait_until([&] { return scans.has(0.2); }, kWait));
  EXPECT_EQ(scans.all().size(), 2u);
  const LaserScan m = scans.at(0.2);
  EXPECT_EQ(m.frame_id, "auv/profiler");
  ASSERT_EQ(m.ranges.size(), 64u);
  EXPECT_NEAR(m.angle_min, -0.5 * M_PI / 2.0 + 0.5 * (M_PI / 2.0) / 64.0, 1e-6);
  EXPECT_NEAR(m.angle_increment, (M_PI / 2.0) / 64.0, 1e-6);
  EXPECT_NEAR(m.scan_time, 0.1, 1e-7);
  EXPECT_NEAR(m.ranges[31], 40.0, 1e-3);
  EXPECT_NEAR(m.ranges[32], 40.0, 1e-3);
  // Beam 0's ray nearest the vertical is 0.4 deg inside its centre at -45 + 0.70 deg.
  EXPECT_NEAR(m.ranges[0], 40.0 / std::cos(M_PI / 4.0 - 0.5 * (M_PI / 2.0) / 64.0 - 0.4 * M_PI / 180.0), 2e-3);
  EXPECT_TRUE(m.intensities.empty());
}

// ---- camera (sensor_msgs/Image, CameraInfo; rendered on the ray-cast workers) -------------------

// tests/integration/scenarios/camera.yaml: frames taken at 0.1 s and 0.2 s are published 0.05 s later on
// image_raw, depth and camera_info, stamped with the frame's time, in the optical frame. Looking straight
// down 10 m at the plane through water that only absorbs, with the light at the camera and the sensor's
// noise off, the centre pixel's counts are the Lambertian closed form
//   round(gain sensitivity exposure albedo / pi I / d^2 exp(-2 c d)) = 117, 140, 128 (R, G, B),
// its depth is 10 m (float rays: 1e-4 m), and its own hull (around the camera and the light) is
// transparent to camera and shadow rays.
TEST(SensorClientTest, CameraFramesArriveOnThreeTopicsWithTheClosedFormCounts) {
  LockstepServer s("tests/integration/scenarios/camera.yaml");
  SampleLog<Image> images, depths;
  SampleLog<CameraInfo> infos;
  s.client().on_image("auv", "camera", [&](const Image& m) { images.add(m); });
  s.client().on_depth_image("auv", "camera", [&](const Image& m) { depths.add(m); });
  s.client().on_camera_info("auv", "camera", [&](const CameraInfo& m) { infos.add(m); });
  ASSERT_NO_FATAL_FAILURE(s.connect());
  EXPECT_NEAR(s.client().step(124), 0.248, 1e-12);
  ASSERT_TRUE(wait_until([&] { return images.has(0.1) && depths.has(0.1) && infos.has(0.1); }, kWait));
  EXPECT_FALSE(images.has(0.2));  // due at 0.25 s
  EXPECT_NEAR(s.client().step(1), 0.25, 1e-12);
  ASSERT_TRUE(wait_until([&] { return images.has(0.2) && depths.has(0.2); }, kWait));

  const Image image = images.at(0.2);
  EXPECT_EQ(image.frame_id, "auv/camera_optical");
  EXPECT_EQ(image.encoding, "rgb8");
  ASSERT_EQ(image.width, 160u);
  ASSERT_EQ(image.height, 120u);
  ASSERT_EQ(image.step, 480u);
  ASSERT_EQ(image.data.size(), 480u * 120u);
  // The centre of the image (cx = 79.5, cy = 59.5) lies between four pixels; all four see 10 m.
  const double albedo[3] = {0.5, 0.4, 0.3}, c[3] = {0.05, 0.03, 0.02};
  for (int ch = 0; ch < 3; ++ch) {
    const double L = albedo[ch] / M_PI * 2000.0 / 100.0 * std::exp(-2.0 * c[ch] * 10.0);
    // The pixel's ray is 0.71 px (0.29 deg) off the axis: cos^3 and the longer path change L by ~1e-4,
    // far from a count.
    EXPECT_EQ(image.data[59 * 480 + 79 * 3 + ch], static_cast<std::uint8_t>(std::round(100.0 * L))) << ch;
  }
  const Image depth = depths.at(0.2);
  EXPECT_EQ(depth.encoding, "32FC1");
  EXPECT_EQ(depth.frame_id, "auv/camera_optical");
  EXPECT_NEAR(depth.depth_m(79, 59), 10.0, 1e-4);
  EXPECT_NEAR(depth.depth_m(0, 0), 10.0, 1e-4);  // a plane perpendicular to the axis: one depth
  const CameraInfo info = infos.at(0.1);
  EXPECT_EQ(info.frame_id, "auv/camera_optical");
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  EXPECT_EQ(info.d, std::vector<double>(5, 0.0));
  EXPECT_NEAR(info.k[0], 80.0 / std::tan(30.0 * M_PI / 180.0), 1e-9);
  EXPECT_EQ(info.k[2], 79.5);
  EXPECT_EQ(info.k[5], 59.5);
  EXPECT_EQ(info.p[3], 0.0);
}

// A topic already subscribed with one message type refuses another (its samples would be misread):
// a clear error at subscription, no server needed.
TEST(SensorClientTest, SubscribingATopicWithAnotherTypeIsRefused) {
  DomainLease domain;
  Client client(ClientOptions{domain.id(), "sensor_client_test"});
  client.on_magnetic_field("auv", "magnetometer", [](const MagneticField&) {});
  try {
    client.on_imu("auv", "magnetometer", [](const Imu&) {});
    ADD_FAILURE() << "on_imu on a MagneticField topic was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rt/auv/magnetometer has type sensor_msgs::msg::dds_::MagneticField_, not "
                                         "sensor_msgs::msg::dds_::Imu_"),
              std::string::npos)
        << e.what();
  }
  client.on_magnetic_field("auv", "magnetometer", [](const MagneticField&) {});  // same type: fine
}

// ---- determinism over DDS -------------------------------------------------------------------------

// Every field of a sample as bit patterns (NaN equals NaN), in a fixed order.
struct Bits {
  std::vector<std::uint64_t> words;
  void put(double x) {
    std::uint64_t w;
    std::memcpy(&w, &x, sizeof w);
    words.push_back(w);
  }
  template <std::size_t N>
  void put(const std::array<double, N>& a) {
    for (double x : a) put(x);
  }
};

// Each sensor stream of the default AUV as one record per sample, for 2 s of lockstep with a thruster
// command (the AUV moves and turns, so the ideal values change from sample to sample).
std::map<std::string, std::map<double, std::vector<std::uint64_t>>> all_sensor_streams(std::uint64_t seed) {
  LockstepServer s(kClientScenario, {"--seed", std::to_string(seed)});
  std::mutex mutex;
  std::map<std::string, std::map<double, std::vector<std::uint64_t>>> streams;
  auto record = [&](const std::string& sensor, double stamp, Bits bits) {
    std::lock_guard<std::mutex> lock(mutex);
    streams[sensor][stamp] = std::move(bits.words);
  };
  Client& c = s.client();
  c.on_fluid_pressure("auv", "depth", [&](const FluidPressure& m) {
    Bits b;
    b.put(m.pressure);
    record("depth", m.stamp, b);
  });
  c.on_imu("auv", "imu", [&](const Imu& m) {
    Bits b;
    b.put(m.angular_velocity);
    b.put(m.linear_acceleration);
    record("imu", m.stamp, b);
  });
  c.on_magnetic_field("auv", "magnetometer", [&](const MagneticField& m) {
    Bits b;
    b.put(m.magnetic_field);
    record("magnetometer", m.stamp, b);
  });
  c.on_nav_sat_fix("auv", "gps", [&](const NavSatFix& m) {
    Bits b;
    b.put(static_cast<double>(m.status));
    b.put(m.latitude);
    b.put(m.longitude);
    b.put(m.altitude);
    record("gps", m.stamp, b);
  });
  c.on_dvl("auv", "dvl", [&](const Dvl& m) {
    Bits b;
    b.put(static_cast<double>(m.velocity_mode));
    b.put(m.velocity);
    b.put(m.altitude);
    b.put(static_cast<double>(m.num_good_beams));
    b.put(m.ranges);
    b.put(m.beam_velocity);
    record("dvl", m.stamp, b);
  });
  c.on_range("auv", "altimeter", [&](const Range& m) {
    Bits b;
    b.put(m.range);
    record("altimeter", m.stamp, b);
  });
  s.connect();
  double t = 0.0;
  for (int k = 0; k < 4; ++k) {  // 2 s: forward and sway thrust, refreshed before the 1 s watchdog
    c.set_commands("auv", {0.8, 0.0, 0.3});
    t = c.step(250);
  }
  EXPECT_TRUE(wait_until(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        if (streams.size() < 6) return false;
        for (const auto& [name, samples] : streams) {
          if (samples.empty() || std::abs(samples.rbegin()->first - t) > 1e-9) return false;
        }
        return true;
      },
      kWait));
  std::lock_guard<std::mutex> lock(mutex);
  return streams;
}

// Determinism: the same seed and the same lockstep commands give bit-identical streams of all six
// sensors over real DDS (every sample of 2 s: 20 depth, 200 IMU, 40 magnetometer, 2 GPS, 10 DVL, 20
// altimeter); another seed changes every noisy stream (the GPS under water reports no fix, so its
// stream carries no noise to differ).
TEST(SensorClientTest, AllSensorStreamsAreBitIdenticalInLockstep) {
  const auto a = all_sensor_streams(99), b = all_sensor_streams(99), c = all_sensor_streams(100);
  const std::map<std::string, std::size_t> expected = {{"depth", 20},    {"imu", 200}, {"magnetometer", 40},
                                                       {"gps", 2},       {"dvl", 10},  {"altimeter", 20}};
  for (const auto& [name, count] : expected) {
    SCOPED_TRACE(name);
    ASSERT_EQ(a.count(name), 1u);
    ASSERT_EQ(b.count(name), 1u);
    ASSERT_EQ(c.count(name), 1u);
    EXPECT_EQ(a.at(name).size(), count);
    EXPECT_EQ(a.at(name), b.at(name));
    if (name != "gps") {
      EXPECT_NE(a.at(name), c.at(name));
    }
  }
}

}  // namespace
}  // namespace hadal::test
