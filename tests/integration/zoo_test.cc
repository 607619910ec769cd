// End-to-end tests of the vehicle zoo's signature behaviours (issue 12): each zoo scenario under a real
// lockstep hadald over DDS, commanded through libhadal_client as a user would.
#include "hadal_client/client.h"
#include "lockstep_server.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hadal::test {
namespace {

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
    s.client().set_thrusters("crawler", {0.6, 0.6});
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

}  // namespace
}  // namespace hadal::test
