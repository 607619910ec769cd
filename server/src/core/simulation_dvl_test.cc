// Ray-casting sensors inside the simulation: the DVL (sensors/dvl.h) and the altimeter, with their
// beams cast into the world's Embree scene each sample. Closed forms over a plane seabed; bottom lock
// against the altitude window; water track against a uniform current; determinism and restore.
#include "hadal/core/simulation.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "hadal/physics/ocean.h"
#include "hadal/physics/test_models.h"
#include "hadal/sensors/dvl.h"

namespace hadal {
namespace {

namespace testing = physics::testing;

constexpr double kSeabedZ = -100.0;

Eigen::Matrix3d rpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// A DVL without noise or bias: every channel off, the ideal instrument.
sensors::DvlParams ideal_dvl() {
  sensors::DvlParams p;
  p.min_altitude = 0.5;
  p.max_altitude = 90.0;
  return p;
}

// A box vehicle (1 x 0.4 x 0.4 m) that keeps its initial velocity: no gravity, no buoyancy volume, no
// damping, no added mass. A DVL under the hull 0.3 m ahead of B (S: z down, x forward), an altimeter
// 0.3 m aft looking down (x down), both inside or on the box: its own hull is transparent to them.
Model dvl_vehicle(const Eigen::Vector3d& p_W, const Eigen::Matrix3d& R_WB, const Eigen::Vector3d& v_W,
                  const sensors::DvlParams& dvl, double rate_hz = 5.0, std::uint64_t seed = 1) {
  VehicleSpec vehicle;
  vehicle.name = "auv";
  vehicle.links = {testing::box_link("hull", 20.0, Eigen::Vector3d(1.0, 0.4, 0.4), 0.0)};
  vehicle.fluid.model = FluidModelType::kLumped;
  vehicle.fluid.added_mass.model = AddedMassModel::kNone;
  vehicle.X_WB_initial = testing::at(p_W, R_WB);
  vehicle.v_WB_initial = v_W;
  SensorSpec d;
  d.name = "dvl";
  d.type = SensorType::kDvl;
  d.X_LS = testing::at(Eigen::Vector3d(0.3, 0.0, -0.2), rpy(EIGEN_PI, 0.0, 0.0));
  d.rate_hz = rate_hz;
  d.frame_id = "auv/dvl";
  d.dvl.params = dvl;
  SensorSpec a;
  a.name = "altimeter";
  a.type = SensorType::kAltimeter;
  a.X_LS = testing::at(Eigen::Vector3d(-0.3, 0.0, -0.1), rpy(0.0, EIGEN_PI / 2.0, 0.0));
  a.rate_hz = 10.0;
  a.frame_id = "auv/altimeter";
  a.altimeter.noise_stddev = 0.0;
  a.altimeter.resolution = 0.0;
  vehicle.sensors = {d, a};
  Model model = testing::water_model({vehicle});
  model.world.gravity_W.setZero();
  model.world.seabed.z = kSeabedZ;
  model.world.physics_rate_hz = 500.0;
  model.world.seed = seed;
  return model;
}

const sensors::DvlPing& ping_of(const Simulation& sim) { return *sim.state().vehicles[0].sensors[0].dvl_ping; }

// The DVL's pose and velocity in the current state: R_WS, p_WS, v_WS_S.
struct DvlKinematics {
  Eigen::Matrix3d R_WS;
  Eigen::Vector3d p_WS, v_WS_S;
};
DvlKinematics dvl_kinematics(const Simulation& sim) {
  const RigidBodyState& body = sim.state().vehicles[0].body;
  const SensorSpec& spec = sim.model().vehicles[0].sensors[0];
  const Eigen::Isometry3d X_WS = body.X_WB * sim.model().vehicles[0].links[0].X_BL * spec.X_LS;
  DvlKinematics k;
  k.R_WS = X_WS.linear();
  k.p_WS = X_WS.translation();
  k.v_WS_S = k.R_WS.transpose() * (body.v_WB + body.w_WB.cross(k.p_WS - body.X_WB.translation()));
  return k;
}

// Over a plane seabed, with no noise and no bias, a pitched, rolled and yawed DVL on a turning vehicle
// measures its own velocity (lever arm included) in S, each beam reads d_i . v, and each beam's range is
// the plane's distance along the beam, h / (-d_W . z). Tolerances: velocities 1e-12 m/s (double
// rounding of the 4-beam least squares); ranges 4 float ulp of the 100 m coordinates (Embree is float).
TEST(SimulationDvlTest, IdealDvlOverAPlaneMeasuresItsVelocityAndTheBeamRanges) {
  const Eigen::Vector3d v_W(0.8, -0.3, 0.05);
  Simulation sim(dvl_vehicle(Eigen::Vector3d(5.0, 2.0, -60.0), rpy(0.05, -0.08, 0.6), v_W, ideal_dvl()));
  SimState turning = sim.state();
  turning.vehicles[0].body.w_WB = Eigen::Vector3d(0.0, 0.0, 0.1);  // yawing at 0.1 rad/s
  sim.set_state(turning);
  int pings = 0;
  std::uint64_t last = 0;
  for (int k = 0; k < 1000; ++k) {  // 2 s at 500 Hz: 10 pings at 5 Hz
    sim.step();
    const SensorState& s = sim.state().vehicles[0].sensors[0];
    if (s.samples == last) continue;
    last = s.samples;
    ++pings;
    const sensors::DvlPing& ping = ping_of(sim);
    const DvlKinematics kin = dvl_kinematics(sim);
    ASSERT_EQ(ping.mode, sensors::DvlMode::kBottomTrack);
    EXPECT_EQ(ping.num_good_beams, 4);
    EXPECT_TRUE(ping.beam_ranges_valid);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ping.velocity[c], kin.v_WS_S[c], 1e-12) << c;
    const double h = kin.p_WS.z() - kSeabedZ;
    double altitude = 0.0;
    for (int b = 0; b < sensors::kDvlBeams; ++b) {
      const Eigen::Vector3d& d_S = ping.beam_unit_vec[b];
      EXPECT_NEAR(ping.beam_velocity[b], d_S.dot(ping.velocity), 1e-12) << b;
      EXPECT_NEAR(ping.beam_velocity[b], d_S.dot(kin.v_WS_S), 1e-12) << b;
      const double slant = h / -(kin.R_WS * d_S).z();
      EXPECT_NEAR(ping.range[b], slant, 4 * FLT_EPSILON * 100.0) << b;
      altitude += ping.range[b] * std::cos(ideal_dvl().beam_tilt) / 4.0;
    }
    EXPECT_DOUBLE_EQ(ping.altitude, altitude);
    EXPECT_NEAR(ping.speed_gnd, std::hypot(kin.v_WS_S.x(), kin.v_WS_S.y()), 1e-12);
    EXPECT_EQ(s.stamp, sim.time());
  }
  EXPECT_EQ(pings, 10);
}

// Rising at 1 m/s from 80 m above the plane, the DVL (window 0.5-90 m, water track off) keeps bottom
// lock up to 90 m and loses it beyond (mode none, NaN velocity); sinking back it regains lock below
// 90 m. Level vehicle: every beam's altitude is the DVL's height h, so lock changes within one ping
// (0.2 m at 5 Hz) of h = 90 m.
TEST(SimulationDvlTest, BottomLockIsLostAboveMaxAltitudeAndRegainedBelow) {
  sensors::DvlParams dvl = ideal_dvl();
  dvl.water_track = false;
  Simulation sim(dvl_vehicle(Eigen::Vector3d(0.0, 0.0, kSeabedZ + 80.2), Eigen::Matrix3d::Identity(),
                             Eigen::Vector3d(0.0, 0.0, 1.0), dvl));
  std::uint64_t last = 0;
  int locked = 0, unlocked = 0;
  auto run = [&](int steps) {
    for (int k = 0; k < steps; ++k) {
      sim.step();
      const SensorState& s = sim.state().vehicles[0].sensors[0];
      if (s.samples == last) continue;
      last = s.samples;
      const double h = dvl_kinematics(sim).p_WS.z() - kSeabedZ;
      const sensors::DvlPing& ping = ping_of(sim);
      if (h < 90.0 - 1e-6) {
        EXPECT_EQ(ping.mode, sensors::DvlMode::kBottomTrack) << "h = " << h;
        EXPECT_NEAR(ping.altitude, h, 1e-4);
        ++locked;
      } else if (h > 90.0 + 1e-6) {
        EXPECT_EQ(ping.mode, sensors::DvlMode::kNone) << "h = " << h;
        EXPECT_TRUE(std::isnan(ping.velocity.x()));
        EXPECT_EQ(ping.num_good_beams, 0);
        EXPECT_FALSE(ping.beam_ranges_valid);
        ++unlocked;
      }
    }
  };
  run(10000);  // 20 s up: h from 80 to 100 m
  EXPECT_EQ(locked, 49);
  EXPECT_EQ(unlocked, 50);
  SimState sinking = sim.state();
  sinking.vehicles[0].body.v_WB = Eigen::Vector3d(0.0, 0.0, -1.0);
  sim.set_state(sinking);
  run(10000);  // 20 s down: h from 100 to 80 m
  EXPECT_EQ(locked, 49 + 50);
  EXPECT_EQ(unlocked, 50 + 49);
}

// Out of bottom range (150 m up) in a uniform current, water track measures the vehicle's velocity
// through the water, v_vehicle - v_water, in S (ideal DVL: to rounding).
TEST(SimulationDvlTest, WaterTrackMeasuresTheVelocityRelativeToTheCurrent) {
  const Eigen::Vector3d v_W(1.0, 0.2, 0.0), u_W(0.3, -0.25, 0.02);
  Model model = dvl_vehicle(Eigen::Vector3d(0.0, 0.0, kSeabedZ + 150.0), rpy(0.0, 0.0, 0.4), v_W, ideal_dvl());
  model.world.water.current.uniform_W = u_W;
  Simulation sim(std::move(model));
  for (int k = 0; k < 500; ++k) sim.step();
  const sensors::DvlPing& ping = ping_of(sim);
  ASSERT_EQ(ping.mode, sensors::DvlMode::kWaterTrack);
  EXPECT_EQ(ping.num_good_beams, 4);
  EXPECT_FALSE(ping.beam_ranges_valid);
  const Eigen::Vector3d expected = dvl_kinematics(sim).R_WS.transpose() * (v_W - u_W);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(ping.velocity[c], expected[c], 1e-12) << c;
}

// A DVL that assumes 1450 m/s where the water's sound speed is c (UNESCO at 40 m depth, 4 degC, 35)
// scales every velocity by k = 1450 / c, and the ranges with it.
TEST(SimulationDvlTest, AWrongAssumedSoundSpeedScalesTheVelocity) {
  sensors::DvlParams dvl = ideal_dvl();
  dvl.assumed_sound_speed = 1450.0;
  const Eigen::Vector3d v_W(1.0, 0.0, 0.0);
  Simulation sim(dvl_vehicle(Eigen::Vector3d(0.0, 0.0, -40.0), Eigen::Matrix3d::Identity(), v_W, dvl));
  for (int k = 0; k < 100; ++k) sim.step();
  const DvlKinematics kin = dvl_kinematics(sim);
  const double c = sim.ocean().sound_speed(-kin.p_WS.z());
  const double scale = 1450.0 / c;
  EXPECT_GT(std::abs(scale - 1.0), 0.01);  // the test means something
  const sensors::DvlPing& ping = ping_of(sim);
  for (int c3 = 0; c3 < 3; ++c3) EXPECT_NEAR(ping.velocity[c3], scale * kin.v_WS_S[c3], 1e-12);
  EXPECT_NEAR(ping.altitude, scale * (kin.p_WS.z() - kSeabedZ), 1e-4);
  EXPECT_EQ(ping.sound_speed, 1450.0);
}

// The altimeter's single beam (x of S, pointing down) reads the distance to the plane through its own
// hull; closer than min_range it reports -inf, beyond max_range +inf (REP 117); a vehicle passing
// under it is seen.
TEST(SimulationDvlTest, AltimeterRangesThePlaneAndOtherVehiclesNotItsOwnHull) {
  Model model = dvl_vehicle(Eigen::Vector3d(0.0, 0.0, kSeabedZ + 30.0), rpy(0.0, 0.2, 0.0),
                            Eigen::Vector3d::Zero(), ideal_dvl());
  VehicleSpec lander;
  lander.name = "lander";
  lander.links = {testing::box_link("frame", 50.0, Eigen::Vector3d(2.0, 2.0, 1.0), 0.0)};
  lander.fluid.model = FluidModelType::kLumped;
  lander.fluid.added_mass.model = AddedMassModel::kNone;
  lander.X_WB_initial = testing::at(Eigen::Vector3d(50.0, 0.0, kSeabedZ + 10.0));  // top at 10.5 m
  model.vehicles.push_back(lander);
  Simulation sim(std::move(model));
  for (int k = 0; k < 50; ++k) sim.step();  // one altimeter sample at 10 Hz
  const SensorSpec& spec = sim.model().vehicles[0].sensors[1];
  auto sensor_pose = [&]() {
    return sim.state().vehicles[0].body.X_WB * spec.X_LS;  // link frame = B
  };
  auto expected_range = [&](double surface_z) {
    const Eigen::Isometry3d X_WS = sensor_pose();
    return (X_WS.translation().z() - surface_z) / -X_WS.linear().col(0).z();
  };
  ASSERT_EQ(sim.state().vehicles[0].sensors[1].samples, 1u);
  EXPECT_NEAR(sim.state().vehicles[0].sensors[1].value[0], expected_range(kSeabedZ), 4 * FLT_EPSILON * 100.0);

  // Level, with the altimeter right over the lander's top (B 0.3 m ahead of the sensor): the lander, not
  // the seabed.
  SimState over = sim.state();
  over.vehicles[0].body.X_WB = testing::at(Eigen::Vector3d(50.3, 0.0, kSeabedZ + 30.0));
  sim.set_state(over);
  for (int k = 0; k < 50; ++k) sim.step();
  EXPECT_NEAR(sim.state().vehicles[0].sensors[1].value[0], expected_range(kSeabedZ + 10.5), 4 * FLT_EPSILON * 100.0);
  EXPECT_NEAR(expected_range(kSeabedZ + 10.5), 30.0 - 0.1 - 10.5, 1e-9);

  // 0.2 m over the seabed (min_range 0.3 m): -inf; 150 m up (max_range 100 m): +inf.
  SimState low = sim.state();
  low.vehicles[0].body.X_WB = testing::at(Eigen::Vector3d(-50.0, 0.0, kSeabedZ + 0.2 + 0.1));
  sim.set_state(low);
  for (int k = 0; k < 50; ++k) sim.step();
  EXPECT_EQ(sim.state().vehicles[0].sensors[1].value[0], -std::numeric_limits<double>::infinity());
  SimState high = sim.state();
  high.vehicles[0].body.X_WB = testing::at(Eigen::Vector3d(-50.0, 0.0, kSeabedZ + 150.0));
  sim.set_state(high);
  for (int k = 0; k < 50; ++k) sim.step();
  EXPECT_EQ(sim.state().vehicles[0].sensors[1].value[0], std::numeric_limits<double>::infinity());
}

// A noisy DVL (per-beam noise, dropouts, the paper's bias with drawn turn-on, drift rate and walk) and
// a noisy altimeter: the same seed gives bit-identical streams, another seed differs, and a restored
// state continues bit-identically.
TEST(SimulationDvlTest, NoisyStreamsAreDeterministicAndRestorable) {
  sensors::DvlParams dvl = ideal_dvl();
  dvl.dropout_probability = 0.2;
  dvl.beam_velocity_noise.noise.white_noise_density = 0.01 * std::sqrt(0.2);
  dvl.range_noise.noise.white_noise_density = 0.05 * std::sqrt(0.2);
  dvl.bias.initial_sigma = 0.002;
  dvl.bias.drift_rate_sigma = 1e-6;
  dvl.bias.random_walk_density = 1e-4;
  auto make = [&](std::uint64_t seed) {
    Model model = dvl_vehicle(Eigen::Vector3d(0.0, 0.0, -60.0), rpy(0.0, 0.0, 0.3), Eigen::Vector3d(0.5, 0.0, 0.0),
                              dvl, 5.0, seed);
    model.vehicles[0].sensors[1].altimeter.noise_stddev = 0.02;
    return model;
  };
  auto record = [](Simulation& sim, int steps) {
    std::vector<double> out;
    for (int k = 0; k < steps; ++k) {
      sim.step();
      const auto& sensors = sim.state().vehicles[0].sensors;
      if (k % 100 != 99) continue;  // every 5th step is a DVL ping, every 50th an altimeter sample
      const sensors::DvlPing& ping = *sensors[0].dvl_ping;
      for (int c = 0; c < 3; ++c) out.push_back(ping.velocity[c]);
      for (int b = 0; b < sensors::kDvlBeams; ++b) {
        out.push_back(ping.range[b]);
        out.push_back(ping.beam_velocity[b]);
      }
      out.push_back(static_cast<double>(ping.num_good_beams));
      out.push_back(sensors[1].value[0]);
    }
    return out;
  };
  // NaN (a dropped beam) never equals itself: compare bit patterns.
  auto bits = [](const std::vector<double>& v) {
    std::vector<std::uint64_t> b(v.size());
    std::memcpy(b.data(), v.data(), v.size() * sizeof(double));
    return b;
  };
  Simulation a(make(7)), b(make(7)), c(make(8));
  const std::vector<double> ra = record(a, 5000), rb = record(b, 5000), rc = record(c, 5000);
  EXPECT_EQ(bits(ra), bits(rb));
  EXPECT_NE(bits(ra), bits(rc));
  int dropped = 0;
  for (double x : ra) dropped += std::isnan(x) ? 1 : 0;
  EXPECT_GT(dropped, 0);  // dropouts happened: the comparison covers them

  const SimState saved = a.state();
  const std::vector<double> first = record(a, 3000);
  a.set_state(saved);
  EXPECT_EQ(bits(record(a, 3000)), bits(first));
}

}  // namespace
}  // namespace hadal
