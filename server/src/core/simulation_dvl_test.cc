// Ray-casting sensors inside the simulation: the DVL and the altimeter cast their beams into the
// world's Embree scene at the state of each sample, on the stepping thread. Bottom lock lost and
// regained as a moving vehicle crosses the altitude window; determinism and restore. The kinds' closed
// forms are in sensors/dvl_sensor_test.cc and sensors/altimeter_sensor_test.cc.
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
  d.X_LS = testing::at(Eigen::Vector3d(0.3, 0.0, -0.2), rpy(EIGEN_PI, 0.0, 0.0));
  d.rate_hz = rate_hz;
  d.frame_id = "auv/dvl";
  d.kind = sensors::DvlSensor::Spec{dvl};
  SensorSpec a;
  a.name = "altimeter";
  a.X_LS = testing::at(Eigen::Vector3d(-0.3, 0.0, -0.1), rpy(0.0, EIGEN_PI / 2.0, 0.0));
  a.rate_hz = 10.0;
  a.frame_id = "auv/altimeter";
  sensors::AltimeterSensor::Spec altimeter;
  altimeter.noise_stddev = 0.0;
  altimeter.resolution = 0.0;
  a.kind = altimeter;
  vehicle.sensors = {d, a};
  Model model = testing::water_model({vehicle});
  model.world.gravity_W.setZero();
  model.world.seabed.z = kSeabedZ;
  model.world.physics_rate_hz = 500.0;
  model.world.seed = seed;
  return model;
}

const sensors::DvlPing& ping_of(const Simulation& sim) {
  return state_of<sensors::DvlSensor>(sim.state().vehicles[0].sensors[0]).ping;
}

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
    std::get<sensors::AltimeterSensor::Spec>(model.vehicles[0].sensors[1].kind).noise_stddev = 0.02;
    return model;
  };
  auto record = [](Simulation& sim, int steps) {
    std::vector<double> out;
    for (int k = 0; k < steps; ++k) {
      sim.step();
      const auto& sensors = sim.state().vehicles[0].sensors;
      if (k % 100 != 99) continue;  // every 5th step is a DVL ping, every 50th an altimeter sample
      const sensors::DvlPing& ping = state_of<sensors::DvlSensor>(sensors[0]).ping;
      for (int c = 0; c < 3; ++c) out.push_back(ping.velocity[c]);
      for (int b = 0; b < sensors::kDvlBeams; ++b) {
        out.push_back(ping.range[b]);
        out.push_back(ping.beam_velocity[b]);
      }
      out.push_back(static_cast<double>(ping.num_good_beams));
      out.push_back(state_of<sensors::AltimeterSensor>(sensors[1]).range);
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
