// End-to-end tests of the vehicle zoo's signature behaviours (issue 12): each zoo scenario under a real
// lockstep hadald over DDS, commanded through libhadal_client as a user would.
#include "hadal_client/client.h"
#include "lockstep_server.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace hadal::test {
namespace {

// Attitude from a ROS quaternion (x, y, z, w): nose-up pitch and yaw (heading from x, to the left) [rad].
double nose_up_pitch(const Odometry& o) {
  const double x = o.q_WB[0], y = o.q_WB[1], z = o.q_WB[2], w = o.q_WB[3];
  return -std::asin(std::clamp(2.0 * (w * y - z * x), -1.0, 1.0));
}
double yaw(const Odometry& o) {
  const double x = o.q_WB[0], y = o.q_WB[1], z = o.q_WB[2], w = o.q_WB[3];
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

// configs/scenarios/crawler.yaml: the tracked crawler settles into the deep-sea ooze and, commanded to
// 0.6 of full belt speed, drives the distance its belts cover, at the sinkage Bekker predicts for half
// its weight in water under each track.
TEST(ZooTest, CrawlerDrivesItsCommandedDistanceWithThePredictedSinkage) {
  LockstepServer s("configs/scenarios/crawler.yaml");
  SampleLog<Odometry> odometry;
  SampleLog<TrackStates> tracks;
  s.client().on_odometry("crawler", [&](const Odometry& o) { odometry.add(o); });
  s.client().on_track_state("crawler", [&](const TrackStates& t) { tracks.add(t); });
  s.connect();

  // 2 s at rest (200 Hz physics; the schedule holds the tracks at 0 until a client commands).
  double t = s.client().step(400);
  ASSERT_TRUE(wait_until([&] { return odometry.has(t); }, kWait));
  const Odometry start = odometry.at(t);
  // Closed form (configs/vehicles/tracked_crawler.yaml): 1400 kg less 1.018 m^3 of 1025 kg/m^3 water,
  // half on each 1.8 m x 0.3 m track; the ooze's n = 0.8, k_c = 4 kN/m^1.8, k_phi = 30 kN/m^2.8.
  const double W = 0.5 * (1400.0 - 1025.0 * 1.018) * 9.80665, A = 1.8 * 0.3, b = 0.3;
  const double sinkage = std::pow(W / (A * (4.0e3 / b + 30.0e3)), 1.0 / 0.8);
  const double seabed_z = -100.0;
  EXPECT_NEAR(seabed_z - start.p_WB[2], sinkage, 0.03 * sinkage);

  // 10 s at setpoint 0.6, commands refreshed every 0.5 s (watchdog 1 s): belts at 0.6 x 32 rpm x 0.15 m.
  for (int i = 0; i < 20; ++i) {
    s.client().set_commands("crawler", {0.6, 0.6});
    t = s.client().step(100);
  }
  ASSERT_TRUE(wait_until([&] { return odometry.has(t); }, kWait));
  const Odometry end = odometry.at(t);
  const double V = 0.6 * 32.0 * 2.0 * M_PI / 60.0 * 0.15;
  const double commanded = V * (10.0 - 0.3);  // less the 0.3 s speed loop's lag
  EXPECT_NEAR(end.p_WB[0] - start.p_WB[0], commanded, 0.02 * commanded);
  EXPECT_NEAR(end.p_WB[1] - start.p_WB[1], 0.0, 0.01);
  EXPECT_NEAR(end.v_WB_B[0], V, 0.01 * V);
  EXPECT_NEAR(seabed_z - end.p_WB[2], sinkage, 0.03 * sinkage);
  // The tracks' state (20 Hz): both belts at V, commanded by the client, each pulling its share of the
  // water's drag (~15 N) at a motor current of torque / 8 N m/A.
  ASSERT_TRUE(wait_until([&] { return tracks.has(t); }, kWait));
  const TrackStates state = tracks.at(t);
  ASSERT_EQ(state.names, (std::vector<std::string>{"track_port", "track_starboard"}));
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(state.setpoint[k], 0.6);
    EXPECT_NEAR(state.belt_speed[k], V, 1e-3 * V);
    EXPECT_NEAR(state.sprocket_speed[k], state.belt_speed[k] / 0.15, 1e-9);
    EXPECT_GT(state.load[k], 5.0);
    EXPECT_LT(state.load[k], 50.0);
    EXPECT_NEAR(state.current[k], state.motor_torque[k] / 8.0, 1e-9);
  }
  EXPECT_EQ(state.command_source, 2);
}

// configs/scenarios/lander.yaml: the free-fall lander sinks at a steady speed on its two weights, lets
// the descent weight go at its 4 m altitude trigger, lands on its legs, and on the client's release
// command drops the ascent weight and rises.
TEST(ZooTest, LanderDescendsDropsItsWeightsAndAscends) {
  LockstepServer s("configs/scenarios/lander.yaml");
  SampleLog<Odometry> odometry;
  SampleLog<DropWeightStates> weights;
  s.client().on_odometry("lander", [&](const Odometry& o) { odometry.add(o); });
  s.client().on_drop_weight_state("lander", [&](const DropWeightStates& w) { weights.add(w); });
  s.connect();

  // A drop weight's command is 0 or 1: anything else is refused with the reason, and nothing moves.
  for (const auto& [bad, reason] : std::vector<std::pair<std::vector<double>, std::string>>{
           {{0.0, 0.5}, "setpoint[1] = 0.5 is not 0 (hold) or 1 (release)"},
           {{std::nan(""), 0.0}, "setpoint[0] is NaN, not 0 (hold) or 1 (release)"},
           {{1.0}, "expected 2 setpoints (descent_weight, ascent_weight), got 1"}}) {
    s.client().set_commands("lander", bad);
    try {
      s.client().step(100);
      ADD_FAILURE() << "accepted: " << reason;
    } catch (const ClientError& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  }

  // Sink for 95 s (100 Hz physics), one second per request.
  double t = 0.0;
  for (int i = 0; i < 95; ++i) t = s.client().step(100);
  ASSERT_TRUE(wait_until([&] { return odometry.has(t) && weights.has(t); }, kWait));
  const std::map<double, Odometry> descent = odometry.all();
  // A steady descent between 20 s and 60 s (terminal speed, both weights on): one speed within 0.5 %.
  const double v20 = descent.lower_bound(20.0 - 1e-9)->second.v_WB_B[2];
  const double v60 = descent.lower_bound(60.0 - 1e-9)->second.v_WB_B[2];
  EXPECT_LT(v20, -0.3);
  EXPECT_NEAR(v60, v20, 0.005 * std::abs(v20));
  // The descent weight went by its altitude trigger, 4 m above the plain (z = -100 m): at the step its
  // centre crossed -96 m, so the release came within one step of that depth (0.61 m/s x 0.01 s).
  const DropWeightStates landed = weights.at(t);
  ASSERT_EQ(landed.names, (std::vector<std::string>{"descent_weight", "ascent_weight"}));
  EXPECT_FALSE(landed.attached[0]);
  EXPECT_EQ(landed.reason[0], DropWeightStates::kReleasedAtAltitude);
  EXPECT_TRUE(landed.attached[1]);
  EXPECT_LT(landed.force[1], -500.0);  // 70 kg of steel: (1025 x 70 / 7850 - 70) g = -597 N
  const double released_at = landed.release_time[0];
  const Odometry at_release = descent.lower_bound(std::floor(released_at) - 1e-9)->second;  // the second before
  EXPECT_GT(at_release.p_WB[2] + 100.0, 4.0);
  EXPECT_LT(at_release.p_WB[2] + 100.0, 4.0 + 1.0 * std::abs(v20));
  // Landed: at rest on its legs, whose feet are 0.89 m below B.
  const Odometry resting = odometry.at(t);
  EXPECT_NEAR(resting.p_WB[2], -100.0 + 0.89, 0.02);
  EXPECT_LT(std::abs(resting.v_WB_B[2]), 0.01);

  // The acoustic release: the client drops the ascent weight (commands [descent, ascent]).
  s.client().set_commands("lander", {0.0, 1.0});
  for (int i = 0; i < 60; ++i) t = s.client().step(100);
  ASSERT_TRUE(wait_until([&] { return odometry.has(t) && weights.has(t); }, kWait));
  const DropWeightStates released = weights.at(t);
  EXPECT_FALSE(released.attached[1]);
  EXPECT_EQ(released.reason[1], DropWeightStates::kReleasedOnCommand);
  EXPECT_NEAR(released.release_time[1], 95.0, 1e-9);
  EXPECT_EQ(released.force[1], 0.0);
  // Rising at a steady speed, with nothing left to hold it down (40 kg buoyant).
  const Odometry rising = odometry.at(t);
  const Odometry earlier = odometry.at(t - 20.0);
  EXPECT_GT(rising.v_WB_B[2], 0.3);
  EXPECT_NEAR(rising.v_WB_B[2], earlier.v_WB_B[2], 0.005 * rising.v_WB_B[2]);
  EXPECT_GT(rising.p_WB[2], -100.0 + 0.89 + 0.3 * 40.0);
}

// configs/scenarios/glider.yaml: the glider flies its saw-tooth -- down while the buoyancy engine makes
// it heavy, up while it makes it light -- at one glide angle each way, and reports its engine's volume
// and the energy the pump drew against the sea's pressure. (That the angle is the one its lift and drag
// give is checked in-process, where the fluid model's forces can be read: simulation_zoo_test.cc.)
TEST(ZooTest, GliderFliesASawToothOnItsBuoyancyEngine) {
  LockstepServer s("configs/scenarios/glider.yaml");
  SampleLog<Odometry> odometry;
  SampleLog<BuoyancyEngineStates> engine;
  s.client().on_odometry("glider", [&](const Odometry& o) { odometry.add(o); });
  s.client().on_buoyancy_engine_state("glider", [&](const BuoyancyEngineStates& b) { engine.add(b); });
  s.connect();

  // 440 s (50 Hz physics) of the schedule: dive 0-200 s, climb 200-400 s, dive again.
  double t = 0.0;
  for (int i = 0; i < 44; ++i) t = s.client().step(500);
  ASSERT_TRUE(wait_until([&] { return odometry.has(t) && engine.has(t); }, kWait));
  const std::map<double, Odometry> flight = odometry.all();
  const auto at = [&](double time) { return flight.lower_bound(time - 1e-9)->second; };
  // Glide path angle below the horizontal from the velocity (v_WB_B turned into W).
  const auto path_angle_deg = [](const Odometry& o) {
    // v_W = R(q) v_B for the unit quaternion (x, y, z, w): v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z).
    const double x = o.q_WB[0], y = o.q_WB[1], z = o.q_WB[2], w = o.q_WB[3];
    const double vx = o.v_WB_B[0], vy = o.v_WB_B[1], vz = o.v_WB_B[2];
    const double cx = y * vz - z * vy, cy = z * vx - x * vz, cz = x * vy - y * vx;  // u x v
    const double v_Wx = vx + 2.0 * (w * cx + y * cz - z * cy);
    const double v_Wy = vy + 2.0 * (w * cy + z * cx - x * cz);
    const double v_Wz = vz + 2.0 * (w * cz + x * cy - y * cx);
    return std::atan2(-v_Wz, std::hypot(v_Wx, v_Wy)) * 180.0 / M_PI;
  };
  // Steady legs: the second half of each, one glide angle to 0.1 deg, the same angle down and up to
  // 1 deg (the hull is neutral to ~30 g), between 15 and 35 deg.
  const double dive = path_angle_deg(at(150.0)), climb = path_angle_deg(at(350.0));
  EXPECT_NEAR(path_angle_deg(at(190.0)), dive, 0.1);
  EXPECT_NEAR(path_angle_deg(at(390.0)), climb, 0.1);
  EXPECT_GT(dive, 15.0);
  EXPECT_LT(dive, 35.0);
  EXPECT_NEAR(climb, -dive, 1.0);
  // The saw-tooth: deepest just after the first inflection (the pump takes 25 s to turn it around), back
  // up by 400 s, and down again after.
  double deepest_t = 0.0, deepest_z = 0.0;
  for (const auto& [stamp, o] : flight) {
    if (o.p_WB[2] < deepest_z) {
      deepest_z = o.p_WB[2];
      deepest_t = stamp;
    }
  }
  EXPECT_GT(deepest_t, 200.0);
  EXPECT_LT(deepest_t, 240.0);
  EXPECT_LT(deepest_z, -35.0);
  EXPECT_GT(at(400.0).p_WB[2], -30.0);
  EXPECT_LT(at(440.0).p_WB[2], at(430.0).p_WB[2]);
  EXPECT_GT(at(440.0).p_WB[0], 85.0);  // ~0.23 m/s forward all along

  // The engine: heavy again at 440 s (driven from +250 to -250 cm^3 from 400 s, 10 cm^3/s), and the one
  // pump stroke it paid for, out from -250 to +250 cm^3 at 35-41 m depth: (p - p_atm) 500 cm^3 / 0.5.
  const BuoyancyEngineStates state = engine.at(t);
  ASSERT_EQ(state.names, std::vector<std::string>{"pump"});
  EXPECT_EQ(state.setpoint[0], -1.0);
  EXPECT_NEAR(state.volume_change[0], 2.5e-4 - 40.0 * 1e-5, 1e-9);
  EXPECT_NEAR(state.volume_rate[0], -1e-5, 1e-12);
  EXPECT_EQ(state.power[0], 0.0);  // the valve
  const double per_metre = 1025.0 * 9.80665 * 5e-4 / 0.5;
  EXPECT_GT(state.energy[0], 35.0 * per_metre);
  EXPECT_LT(state.energy[0], 41.0 * per_metre);
  EXPECT_EQ(state.command_source, 1);  // the scenario's schedule
}

// configs/scenarios/auv.yaml: the finned AUV, cruising at 20 m, is ordered 10 m deeper and follows with
// its elevators alone under a client's autopilot at 10 Hz (the main propeller held at 0.6): a depth loop
// asks for a pitch (at most 20 deg), a pitch loop turns the elevators; the rudders hold the heading.
TEST(ZooTest, AuvFollowsADepthChangeWithItsFins) {
  LockstepServer s("configs/scenarios/auv.yaml");
  SampleLog<Odometry> odometry;
  SampleLog<FinStates> fins;
  s.client().on_odometry("auv", [&](const Odometry& o) { odometry.add(o); });
  s.client().on_fin_state("auv", [&](const FinStates& f) { fins.add(f); });
  s.connect();

  const double target_z = -30.0;
  double t = s.client().step(100);  // 1 s of cruise
  double deepest = 0.0, max_pitch = 0.0, max_elevator = 0.0;
  std::map<double, double> depth_error;
  for (int i = 0; i < 800; ++i) {  // 80 s at 10 Hz
    ASSERT_TRUE(wait_until([&] { return odometry.has(t); }, kWait)) << t;
    const Odometry o = odometry.at(t);
    const double z = o.p_WB[2], theta = nose_up_pitch(o), q = -o.w_WB_B[1];
    const double w_z = o.v_WB_B[2] * std::cos(theta) + o.v_WB_B[0] * std::sin(theta);  // ~ dz/dt
    // Depth loop: a nose-down pitch when too shallow, damped by the climb rate; pitch loop: elevators
    // (positive: nose up), damped by the pitch rate; heading loop: rudders (positive: nose to starboard).
    const double theta_cmd = std::clamp(0.08 * (target_z - z) - 0.4 * w_z, -0.35, 0.35);
    const double elevator = std::clamp(2.0 * (theta_cmd - theta) - 1.0 * q, -1.0, 1.0);
    const double rudder = std::clamp(2.0 * yaw(o) + 1.0 * o.w_WB_B[2], -1.0, 1.0);
    s.client().set_commands("auv", {0.6, rudder, rudder, elevator, elevator});
    t = s.client().step(10);
    deepest = std::min(deepest, z);
    max_pitch = std::max(max_pitch, std::abs(theta));
    max_elevator = std::max(max_elevator, std::abs(elevator));
    depth_error[t] = z - target_z;
  }
  ASSERT_TRUE(wait_until([&] { return odometry.has(t) && fins.has(t); }, kWait));
  const Odometry end = odometry.at(t);
  // It went down on its fins: pitched nose down by more than 10 deg on the way, arrived within 0.2 m and
  // stays there (the last 20 s), overshooting by less than 1 m, on its heading to 2 deg.
  EXPECT_GT(max_pitch, 10.0 * M_PI / 180.0);
  EXPECT_LT(max_pitch, 25.0 * M_PI / 180.0);
  EXPECT_GT(max_elevator, 0.2);
  for (auto it = depth_error.lower_bound(t - 20.0); it != depth_error.end(); ++it) {
    ASSERT_LT(std::abs(it->second), 0.2) << "at t = " << it->first;
  }
  EXPECT_GT(deepest, target_z - 1.0);
  EXPECT_LT(std::abs(yaw(end)), 2.0 * M_PI / 180.0);
  EXPECT_GT(end.v_WB_B[0], 1.0);
  // The fins report what they were told and the lift they make: the elevators turned alike.
  const FinStates state = fins.at(t);
  ASSERT_EQ(state.names,
            (std::vector<std::string>{"rudder_top", "rudder_bottom", "elevator_port", "elevator_starboard"}));
  EXPECT_EQ(state.setpoint[2], state.setpoint[3]);
  EXPECT_NEAR(state.angle[2], state.angle[3], 1e-12);
  EXPECT_LE(std::abs(state.angle[2]), 25.0 * M_PI / 180.0 + 1e-12);
  EXPECT_EQ(state.command_source, 2);
}

// configs/scenarios/vessel.yaml: the catamaran, let go 5 cm high on a calm sea, floats at the draft its
// displacement predicts and, driven east on both thrusters, reports GPS fixes around its track.
TEST(ZooTest, VesselFloatsAtItsDraftAndReportsGpsFixes) {
  LockstepServer s("configs/scenarios/vessel.yaml");
  SampleLog<Odometry> odometry;
  SampleLog<NavSatFix> fixes;
  s.client().on_odometry("vessel", [&](const Odometry& o) { odometry.add(o); });
  s.client().on_nav_sat_fix("vessel", "gps", [&](const NavSatFix& f) { fixes.add(f); });
  s.connect();

  // 10 s adrift (100 Hz). Draft T = m / (rho A_wp) = 147.6 / (1025 x 2 x 2.0 x 0.3) = 0.120 m: B (the
  // hulls' mid-height, 0.2 m above their bottoms) 0.08 m above the water. Without waves there is no
  // radiation damping: it bobs about that height (period 1.25 s, ~1 % damping), so the test averages
  // 2-10 s (6.4 periods: the mean is off the equilibrium by at most amplitude / (pi x 6.4) ~ 2 mm).
  double t = 0.0;
  for (int i = 0; i < 10; ++i) t = s.client().step(100);
  ASSERT_TRUE(wait_until([&] { return odometry.has(t); }, kWait));
  double sum = 0.0;
  int n = 0;
  for (const auto& [stamp, o] : odometry.all()) {
    if (stamp < 2.0) continue;
    sum += o.p_WB[2];
    ++n;
    EXPECT_LT(std::abs(nose_up_pitch(o)), 0.01);
  }
  const double draft = 147.6 / (1025.0 * 2.0 * 2.0 * 0.3);
  EXPECT_NEAR(0.2 - sum / n, draft, 0.003);

  // 30 s east at 0.6 on both thrusters (commands refreshed every 0.5 s): fixes at 5 Hz, every one a fix.
  for (int i = 0; i < 60; ++i) {
    s.client().set_commands("vessel", {0.6, 0.6});
    t = s.client().step(50);
  }
  ASSERT_TRUE(wait_until([&] { return odometry.has(t) && fixes.has(t); }, kWait));
  EXPECT_GT(odometry.at(t).p_WB[0], 20.0);
  // Each fix against the antenna's true position (B + 1 m of mast, upright) in the local tangent plane at
  // world.origin (43.1 N, 5.9 E; metres per degree of WGS84 latitude and longitude there): within 5
  // sigma (1.5 m) on each axis, and the mean error within 4 sigma / sqrt(n) of zero.
  const double lat0 = 43.1, lon0 = 5.9, phi = lat0 * M_PI / 180.0;
  const double m_per_deg_lat = 111132.92 - 559.82 * std::cos(2 * phi) + 1.175 * std::cos(4 * phi);
  const double m_per_deg_lon = 111412.84 * std::cos(phi) - 93.5 * std::cos(3 * phi);
  double east_sum = 0.0, north_sum = 0.0;
  int count = 0;
  for (const auto& [stamp, fix] : fixes.all()) {
    if (stamp < 10.0 + 1e-9 || !odometry.has(stamp)) continue;
    ASSERT_TRUE(fix.has_fix()) << stamp;
    const Odometry o = odometry.at(stamp);
    const double east = (fix.longitude - lon0) * m_per_deg_lon - o.p_WB[0];
    const double north = (fix.latitude - lat0) * m_per_deg_lat - o.p_WB[1];
    EXPECT_LT(std::abs(east), 5.0 * 1.5) << stamp;
    EXPECT_LT(std::abs(north), 5.0 * 1.5) << stamp;
    east_sum += east;
    north_sum += north;
    ++count;
  }
  ASSERT_GE(count, 140);  // 30 s at 5 Hz, less the odometry samples not on the fixes' stamps
  EXPECT_LT(std::abs(east_sum / count), 4.0 * 1.5 / std::sqrt(count));
  EXPECT_LT(std::abs(north_sum / count), 4.0 * 1.5 / std::sqrt(count));
}

}  // namespace
}  // namespace hadal::test
