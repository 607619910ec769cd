// The USBL kind alone (no Bullet): interrogations and replies through the acoustic channel, stepped as the
// simulation steps it (advance() every step, sample() on the rate's ticks), against closed forms: the fix's
// time, range and direction for a transponder at rest and for one moving away, range noise unbiased with
// the configured sigma, errors that grow as the SNR falls, no fix out of the cone, range, SNR or sight, the
// same seed the same fixes, and the message.
#include "hadal/sensors/usbl_sensor.h"

#include <gtest/gtest.h>
#include <hadal_msgs.h>

#include <cmath>
#include <functional>
#include <vector>

#include "hadal/sensors/acoustic_channel.h"
#include "hadal/sensors/geodesy.h"
#include "hadal/sensors/interrogator_keys.h"
#include "hadal/physics/ocean.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::rpy;
using testing::SensorTestWorld;

// The vessel (vehicle 0, yawed 30 deg, rolled 2 deg) with the transceiver 1.5 m forward, 0.5 m to port and
// 3 m below B; the AUV (vehicle 1) with its transponder 0.4 m above its B, at 1.2 km east, 0.5 km north,
// 1.8 km deep: every axis and lever arm differs.
const Eigen::Isometry3d kX_BS = pose(Eigen::Vector3d(1.5, 0.5, -3.0));

Model survey(double seabed_z = -4000.0) {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, 0.0), seabed_z);
  model.vehicles[0].name = "vessel";
  model.vehicles[0].X_WB_initial.linear() = rpy(0.02, 0.0, 30.0 * kDegToRad);
  VehicleSpec auv = model.vehicles[0];
  auv.name = "auv";
  auv.X_WB_initial = pose(Eigen::Vector3d(1200.0, 500.0, -1800.0), rpy(0.0, 0.1, -1.0));
  auv.transponder = TransponderSpec{};
  auv.transponder->p_BT = Eigen::Vector3d(0.0, 0.0, 0.4);
  model.vehicles.push_back(auv);
  return model;
}

UsblSpec exact() {
  UsblSpec spec;
  spec.range_stddev = 0.0;
  spec.bearing_stddev = 0.0;
  return spec;
}

Eigen::Vector3d transponder_W(const SensorTestWorld& world, int vehicle = 1) {
  return world.state.vehicles[static_cast<std::size_t>(vehicle)].body.X_WB *
         world.model.vehicles[static_cast<std::size_t>(vehicle)].transponder->p_BT;
}

// Every fix of the transceiver at kX_BS on the vessel over the run (testing::step_events).
std::vector<UsblFix> run(SensorTestWorld& world, const UsblSpec& spec, UsblSensor::State& state, double until,
                         double dt = 0.01, int every = 100, const std::function<void(double)>& move = {}) {
  std::vector<UsblFix> fixes;
  testing::step_events<UsblSensor>(world, spec, state, kX_BS, until, dt, every, move, [&](const UsblSensor::State& s) {
    fixes.insert(fixes.end(), s.fixes.begin(), s.fixes.end());
  });
  return fixes;
}

// At rest: the interrogation at t = 0 comes back at two travel times plus the turnaround (the stamp to 1e-9
// s, the travel time to 1e-6 s), the range is the distance to 1e-6 m, the direction is the transponder's in
// S, and the position in W and WGS84 is the transponder's.
TEST(UsblSensorTest, AFixAtRestIsTheTransponderAtTwoTravelTimesPlusTheTurnaround) {
  SensorTestWorld world(survey());
  const UsblSpec spec = exact();
  UsblSensor::State state = world.initial_state<UsblSensor>(spec, 1.0, "usbl");
  const std::vector<UsblFix> fixes = run(world, spec, state, 3.5, 0.01, 1000);  // one interrogation
  ASSERT_EQ(fixes.size(), 1u);
  const UsblFix& fix = fixes[0];
  const Eigen::Isometry3d X_WS = world.body(0).X_WB * kX_BS;
  const Eigen::Vector3d p_WT = transponder_W(world);
  const AcousticChannel channel(world.ocean, world.model.world.acoustics);
  const double one_way = channel.travel_time(X_WS.translation(), p_WT);
  EXPECT_GT(one_way, 1.3);
  EXPECT_NEAR(fix.stamp, 2.0 * one_way + 0.05, 1e-9);
  EXPECT_NEAR(fix.travel_time, 2.0 * one_way, 1e-6);
  EXPECT_NEAR(fix.range, (p_WT - X_WS.translation()).norm(), 1e-6);
  const Eigen::Vector3d p_S = X_WS.inverse() * p_WT;
  EXPECT_LT((fix.p_S - p_S).norm(), 1e-6);
  EXPECT_NEAR(fix.bearing, std::atan2(p_S.y(), p_S.x()), 1e-9);
  EXPECT_NEAR(fix.elevation, std::asin(p_S.z() / p_S.norm()), 1e-9);
  EXPECT_LT((fix.p_W - p_WT).norm(), 1e-6);
  const GeodeticPosition geo = world.environment.frame_W().to_geodetic(p_WT);
  EXPECT_NEAR(fix.latitude_deg, geo.latitude_rad / kDegToRad, 1e-9);
  EXPECT_NEAR(fix.longitude_deg, geo.longitude_rad / kDegToRad, 1e-9);
  EXPECT_NEAR(fix.height, geo.height_m, 1e-6);
  EXPECT_EQ(fix.target_name, "auv");
  EXPECT_EQ(fix.interrogation, 0u);
  // SNR = SL - TL - NL + DI by hand from the channel's parts.
  EXPECT_NEAR(fix.snr_db,
              185.0 - channel.transmission_loss_db(p_WT, X_WS.translation(), spec.frequency_hz) -
                  channel.noise_level_db(spec.frequency_hz, spec.bandwidth_hz) + spec.directivity_index_db,
              1e-9);
}

// A transponder moving away at v along the transceiver's depth (a horizontal path: one sound speed c): the
// interrogation catches it at t_a = D0 / (c - v) at D0 + v t_a, it replies at t_r = t_a + turnaround from
// D0 + v t_r, and the reply is back at t_f = t_r + (D0 + v t_r) / c: the fix is stamped t_f, points where
// the transponder replied from, and its range is c tau / 2, the mean of the two legs (v turnaround / 2 short
// of the reply's leg, as a real USBL's two-way range is).
TEST(UsblSensorTest, AMovingTransponderIsFixedWhereItRepliedWithTheTrueLatency) {
  SensorTestWorld world(survey());
  world.body(0).X_WB = pose(Eigen::Vector3d(0.0, 0.0, -1000.0));  // a lander's transceiver, level
  const UsblSpec spec = [] {
    UsblSpec s = exact();
    s.cone_half_angle = EIGEN_PI;
    return s;
  }();
  const double d0 = 900.0, v = 2.5;
  const auto move = [&](double t) {
    world.body(1).X_WB = pose(Eigen::Vector3d(1.5 + d0 + v * t, 0.5, -1003.0 - 0.4));
  };
  move(0.0);
  UsblSensor::State state = world.initial_state<UsblSensor>(spec, 1.0, "usbl");
  const std::vector<UsblFix> fixes = run(world, spec, state, 1.9, 0.01, 1000, move);
  ASSERT_EQ(fixes.size(), 1u);
  const double c = world.ocean.sound_speed(1003.0);
  const double t_a = d0 / (c - v);
  const double t_r = t_a + 0.05;
  const double t_f = t_r + (d0 + v * t_r) / c;
  EXPECT_NEAR(fixes[0].stamp, t_f, 1e-9);
  EXPECT_NEAR(fixes[0].range, d0 + v * (t_a + t_r) / 2.0, 1e-6);
  EXPECT_NEAR(fixes[0].p_W.x(), 1.5 + d0 + v * (t_a + t_r) / 2.0, 1e-6);
  EXPECT_NEAR(fixes[0].p_W.y(), 0.5, 1e-6);
  EXPECT_NEAR(fixes[0].p_W.z(), -1003.0, 1e-6);
}

// 400 fixes at high SNR: the range errors have mean 0 (within 3 sigma / sqrt(n)) and the configured sigma
// (within 15 %: the chi distribution's 3-sigma band for n = 400 is +-10.6 %), and so does each direction error
// across the direction, in metres at the range (r sigma_b).
TEST(UsblSensorTest, RangeAndDirectionErrorsAreUnbiasedWithTheConfiguredSigma) {
  SensorTestWorld world(survey());
  UsblSpec spec;
  spec.range_stddev = 0.2;
  spec.bearing_stddev = 0.25 * kDegToRad;
  spec.reference_snr_db = 0.0;  // every fix above it
  UsblSensor::State state = world.initial_state<UsblSensor>(spec, 1.0, "usbl");
  const std::vector<UsblFix> fixes = run(world, spec, state, 403.0, 0.02, 50);
  ASSERT_GE(fixes.size(), 400u);
  const Eigen::Isometry3d X_WS = world.body(0).X_WB * kX_BS;
  const Eigen::Vector3d p_S = X_WS.inverse() * transponder_W(world);
  const double r = p_S.norm();
  const Eigen::Vector3d u = p_S / r;
  double sum = 0.0, sum2 = 0.0, across2 = 0.0;
  const std::size_t n = 400;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = fixes[i].range - r;
    sum += e;
    sum2 += e * e;
    const Eigen::Vector3d direction = fixes[i].p_S / fixes[i].p_S.norm();
    across2 += (r * (direction - direction.dot(u) * u)).squaredNorm() / 2.0;  // two axes
  }
  EXPECT_NEAR(sum / n, 0.0, 3.0 * 0.2 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.2, 0.15 * 0.2);
  EXPECT_NEAR(std::sqrt(across2 / n), r * spec.bearing_stddev, 0.15 * r * spec.bearing_stddev);
}

// Errors grow as 10^((ref - SNR) / 20) below the reference SNR: with the reference 12 dB above the fixes'
// SNR the range sigma is 10^(12/20) = 3.98 times the configured one (within 15 %, as above).
TEST(UsblSensorTest, ErrorsGrowAsTheSnrFalls) {
  SensorTestWorld world(survey());
  UsblSpec spec;
  spec.range_stddev = 0.05;
  UsblSensor::State probe = world.initial_state<UsblSensor>(spec, 1.0, "usbl");
  const std::vector<UsblFix> one = run(world, spec, probe, 3.5, 0.01, 1000);
  ASSERT_EQ(one.size(), 1u);
  spec.reference_snr_db = one[0].snr_db + 12.0;
  EXPECT_NEAR(error_scale(spec, one[0].snr_db), std::pow(10.0, 12.0 / 20.0), 1e-12);
  EXPECT_EQ(error_scale(spec, spec.reference_snr_db + 5.0), 1.0);
  SensorTestWorld fresh(survey());
  UsblSensor::State state = fresh.initial_state<UsblSensor>(spec, 1.0, "usbl");
  const std::vector<UsblFix> fixes = run(fresh, spec, state, 403.0, 0.02, 50);
  ASSERT_GE(fixes.size(), 400u);
  const Eigen::Isometry3d X_WS = fresh.body(0).X_WB * kX_BS;
  const double r = (transponder_W(fresh) - X_WS.translation()).norm();
  double sum2 = 0.0;
  for (std::size_t i = 0; i < 400; ++i) sum2 += (fixes[i].range - r) * (fixes[i].range - r);
  EXPECT_NEAR(std::sqrt(sum2 / 400), 0.05 * std::pow(10.0, 12.0 / 20.0), 0.15 * 0.05 * std::pow(10.0, 12.0 / 20.0));
}

// No fix when the transponder is outside the cone (above a downward-looking transceiver), beyond max_range,
// too weak to hear the interrogation, or behind a body; and a vehicle without a transponder is never
// interrogated.
TEST(UsblSensorTest, NoFixOutOfConeRangeSnrOrSight) {
  const auto fixes_with = [](const std::function<void(Model&, UsblSpec&)>& change) {
    Model model = survey();
    UsblSpec spec = exact();
    change(model, spec);
    SensorTestWorld world(model, true);
    UsblSensor::State state = world.initial_state<UsblSensor>(spec, 1.0, "usbl");
    return run(world, spec, state, 3.5, 0.01, 1000).size();
  };
  EXPECT_EQ(fixes_with([](Model&, UsblSpec&) {}), 1u);
  EXPECT_EQ(fixes_with([](Model&, UsblSpec& s) { s.cone_half_angle = 20.0 * kDegToRad; }), 0u);  // ~38 deg off
  EXPECT_EQ(fixes_with([](Model& m, UsblSpec&) { m.vehicles[0].X_WB_initial = pose(Eigen::Vector3d(0, 0, -2500.0)); }),
            0u);  // above the transceiver
  EXPECT_EQ(fixes_with([](Model&, UsblSpec& s) { s.max_range = 2000.0; }), 0u);
  EXPECT_EQ(fixes_with([](Model&, UsblSpec& s) { s.source_level_db = 120.0; }), 0u);  // interrogation unheard
  EXPECT_EQ(fixes_with([](Model& m, UsblSpec&) { m.vehicles[1].transponder->source_level_db = 120.0; }), 0u);
  EXPECT_EQ(fixes_with([](Model& m, UsblSpec&) { m.vehicles[1].transponder.reset(); }), 0u);
  EXPECT_EQ(fixes_with([](Model& m, UsblSpec&) {
              VehicleSpec block = m.vehicles[0];
              block.name = "block";
              CollisionShape shape;
              shape.type = CollisionShapeType::kBox;
              shape.box_size = Eigen::Vector3d(30.0, 30.0, 30.0);
              block.links[0].collisions = {shape};
              block.X_WB_initial = pose(Eigen::Vector3d(600.0, 250.0, -900.0));
              m.vehicles.push_back(block);
            }),
            0u);
}

// Same seed, same fixes to the bit; another seed, other noise.
TEST(UsblSensorTest, SameSeedSameFixes) {
  const auto fixes_with_seed = [](std::uint64_t seed) {
    Model model = survey();
    model.world.seed = seed;
    SensorTestWorld world(model);
    UsblSensor::State state = world.initial_state<UsblSensor>(UsblSpec{}, 1.0, "usbl");
    std::vector<double> out;
    for (const UsblFix& fix : run(world, UsblSpec{}, state, 13.0)) {
      out.insert(out.end(), {fix.stamp, fix.range, fix.p_S.x(), fix.p_S.y(), fix.p_S.z()});
    }
    return out;
  };
  const std::vector<double> a = fixes_with_seed(7);
  EXPECT_EQ(a.size(), 10u * 5u);
  EXPECT_EQ(a, fixes_with_seed(7));
  EXPECT_NE(a, fixes_with_seed(8));
}

TEST(UsblSensorTest, MessageCarriesTheStepsFixes) {
  SensorTestWorld world(survey());
  const UsblSpec spec = exact();
  UsblSensor::State state = world.initial_state<UsblSensor>(spec, 1.0, "usbl");
  const std::vector<UsblFix> fixes = run(world, spec, state, 3.5, 0.01, 1000);
  ASSERT_EQ(fixes.size(), 1u);
  const std::string frame = "vessel/usbl";
  hadal_msgs::msg::UsblFixes msg;
  UsblSensor::fill_message(spec, state, MessageHeader{fixes[0].stamp, frame, 1.0}, msg);
  ASSERT_EQ(msg.fixes().size(), 1u);
  EXPECT_EQ(msg.header().frame_id(), frame);
  const hadal_msgs::msg::UsblFix& out = msg.fixes()[0];
  EXPECT_EQ(out.target(), "auv");
  EXPECT_EQ(out.range(), fixes[0].range);
  EXPECT_EQ(out.position().y(), fixes[0].p_S.y());
  EXPECT_EQ(out.position_covariance()[0], 0.0);
  EXPECT_EQ(out.stamp().sec(), static_cast<std::int32_t>(std::floor(fixes[0].stamp)));
  EXPECT_EQ(out.interrogation_stamp().sec(), 0);
  EXPECT_EQ(out.latitude(), fixes[0].latitude_deg);
}

// What is in flight, for monitors (acoustic_links): the interrogation from where the transceiver was at t = 0
// towards the transponder, then, after the turnaround, the reply from where the transponder replied towards the
// transceiver; nothing once the fix is in.
TEST(UsblSensorTest, LinksFollowTheInterrogationAndTheReply) {
  SensorTestWorld world(survey());
  const UsblSpec spec = exact();
  UsblSensor::State state = world.initial_state<UsblSensor>(spec, 1.0, "usbl");
  const Eigen::Vector3d p_WS = world.body(0).X_WB * kX_BS.translation();
  const AcousticChannel channel(world.ocean, world.model.world.acoustics);
  const double one_way = channel.travel_time(p_WS, transponder_W(world));
  SensorSpec sensor;
  sensor.name = "usbl";
  world.sensor_spec = &sensor;
  const auto links_at = [&](double t) {
    std::vector<AcousticLink> links;
    run(world, spec, state, t, 0.01, 100000);
    UsblSensor::acoustic_links(world.context(kX_BS, 1.0), spec, state, links);
    return links;
  };
  std::vector<AcousticLink> links = links_at(0.5 * one_way);
  ASSERT_EQ(links.size(), 1u);
  EXPECT_EQ(links[0].kind, AcousticLink::Kind::kInterrogation);
  EXPECT_EQ(links[0].source, "vessel/usbl");
  EXPECT_EQ(links[0].target, "auv");
  EXPECT_EQ(links[0].emit_time, 0.0);
  EXPECT_TRUE(links[0].p_Wemit.isApprox(p_WS, 1e-12));
  EXPECT_TRUE(links[0].p_Wtarget.isApprox(transponder_W(world), 1e-12));
  state = world.initial_state<UsblSensor>(spec, 1.0, "usbl");
  links = links_at(1.5 * one_way);
  ASSERT_EQ(links.size(), 1u);
  EXPECT_EQ(links[0].kind, AcousticLink::Kind::kReply);
  EXPECT_EQ(links[0].source, "auv");
  EXPECT_EQ(links[0].target, "vessel/usbl");
  EXPECT_NEAR(links[0].emit_time, one_way + 0.05, 0.011);  // heard within a 10 ms step, replied 50 ms later
  state = world.initial_state<UsblSensor>(spec, 1.0, "usbl");
  EXPECT_TRUE(links_at(2.0 * one_way + 0.2).empty());
}

}  // namespace
}  // namespace hadal::sensors
