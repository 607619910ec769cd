// The acoustic channel (sensors/acoustic_channel.h) against closed forms: travel times along slanted paths
// through a CTD water column against a brute-force integral of the slowness, transmission loss as
// spreading plus absorption, Wenz's noise at hand-computed points, wavefront arrival at moving receivers,
// and occlusion by a body between two others.
#include "hadal/sensors/acoustic_channel.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hadal/physics/ocean.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

// A water column with a thermocline: 20 degC at the surface, 4 at 1000 m, 2 at 4000 m (sound speed
// ~1520 m/s at the surface, a minimum ~1480 near 1000 m, rising with pressure below).
WaterSpec ctd_water() {
  WaterSpec water;
  water.density_model = DensityModel::kCtd;
  water.ctd = {{0.0, 20.0, 35.5}, {200.0, 12.0, 35.2}, {1000.0, 4.0, 34.6}, {4000.0, 2.0, 34.7}};
  return water;
}

// integral over the straight path a -> b of ds / c(depth(s)), by the midpoint rule on n pieces.
double brute_force_travel_time(const physics::Ocean& ocean, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               int n = 400000) {
  const double length = (b - a).norm();
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = a + (i + 0.5) / n * (b - a);
    sum += 1.0 / ocean.sound_speed(ocean.depth(p.z()));
  }
  return sum * length / n;
}

// Travel times through the thermocline equal the path over the harmonic-mean speed, to 1e-6 s (the
// acceptance figure; the midpoint rule on 400,000 pieces is good to ~1e-11 s here). The harmonic mean is
// not the arithmetic mean of c over the depths: that one is off by more than twice the tolerance on each path.
TEST(AcousticChannelTest, TravelTimeIsThePathOverTheHarmonicMeanSoundSpeed) {
  const physics::Ocean ocean(ctd_water(), 9.80665, 1);
  const AcousticChannel channel(ocean, AcousticsSpec{});
  const Eigen::Vector3d a(10.0, -20.0, -5.0);
  for (const Eigen::Vector3d& b : {Eigen::Vector3d(1500.0, 300.0, -2600.0), Eigen::Vector3d(-200.0, 50.0, -180.0),
                                   Eigen::Vector3d(2900.0, -900.0, -1100.0)}) {
    const double expected = brute_force_travel_time(ocean, a, b);
    EXPECT_NEAR(channel.travel_time(a, b), expected, 1e-6) << b.transpose();
    EXPECT_NEAR(channel.travel_time(b, a), expected, 1e-6) << b.transpose();
    double arithmetic = 0.0;
    for (int i = 0; i < 1000; ++i) arithmetic += ocean.sound_speed(ocean.depth(a.z() + (i + 0.5) / 1000 * (b.z() - a.z())));
    arithmetic /= 1000;
    EXPECT_GT(std::abs((b - a).norm() / arithmetic - expected), 2e-6) << b.transpose();
  }
  // A horizontal path: the speed at its depth, exactly.
  const Eigen::Vector3d c(400.0, 300.0, -5.0);
  EXPECT_DOUBLE_EQ(channel.travel_time(a, c), (c - a).norm() / ocean.sound_speed(5.0));
}

// TL = k 10 log10 r + alpha r to 0.1 dB (acceptance): on a horizontal path alpha is the water's at that
// depth (Francois–Garrison at 26 kHz: ~4 dB/km), so the closed form holds to rounding; on a vertical one
// alpha is its depth average, checked against a 2000-point average. Spherical (k = 2) and practical (1.5).
TEST(AcousticChannelTest, TransmissionLossIsSpreadingPlusAbsorption) {
  const physics::Ocean ocean(ctd_water(), 9.80665, 1);
  for (const double k : {2.0, 1.5}) {
    AcousticsSpec acoustics;
    acoustics.spreading_exponent = k;
    const AcousticChannel channel(ocean, acoustics);
    const Eigen::Vector3d a(0.0, 0.0, -500.0), b(0.0, 2500.0, -500.0);
    const double alpha = ocean.sound_absorption_db_per_m(500.0, 26000.0);
    EXPECT_GT(alpha, 2e-3);
    EXPECT_NEAR(channel.transmission_loss_db(a, b, 26000.0), k * 10.0 * std::log10(2500.0) + alpha * 2500.0, 1e-9);
    const Eigen::Vector3d deep(0.0, 0.0, -3500.0);
    double mean_alpha = 0.0;
    for (int i = 0; i < 2000; ++i) mean_alpha += ocean.sound_absorption_db_per_m(500.0 + (i + 0.5) * 1.5, 26000.0);
    mean_alpha /= 2000;
    EXPECT_NEAR(channel.transmission_loss_db(a, deep, 26000.0), k * 10.0 * std::log10(3000.0) + mean_alpha * 3000.0,
                0.1);
    EXPECT_NEAR(channel.transmission_loss_db(a, deep, 26000.0), channel.transmission_loss_db(deep, a, 26000.0), 1e-9);
    // Closer than 1 m: the loss at 1 m (no gain).
    EXPECT_NEAR(channel.transmission_loss_db(a, a + Eigen::Vector3d(0.0, 0.3, 0.0), 26000.0), alpha, 1e-12);
  }
}

// Wenz's curves at hand-computed points (f = 10 kHz: turbulence -13.0, shipping 5.92, wind 29.32 at 0 m/s
// and 53.04 at 10 m/s, thermal 5.0 dB re 1 uPa^2/Hz; powers summed: 29.355 and 53.036); at 50 Hz with heavy
// shipping the shipping term (81.99) dominates; at 200 kHz thermal noise (31.02) does. Band levels: a
// 100 Hz band is the density plus 20 dB to 0.01 dB; a 10 kHz band around 26 kHz against a 20,000-point sum.
TEST(AcousticChannelTest, AmbientNoiseFollowsWenzCurves) {
  AmbientNoiseSpec calm{0.5, 0.0};
  EXPECT_NEAR(ambient_noise_psd_db(10000.0, calm), 29.3547, 1e-3);
  EXPECT_NEAR(ambient_noise_psd_db(10000.0, {0.5, 10.0}), 53.0359, 1e-3);
  EXPECT_NEAR(ambient_noise_psd_db(50.0, {1.0, 0.0}), 81.9990, 1e-3);
  EXPECT_NEAR(ambient_noise_psd_db(200000.0, calm), 31.0291, 1e-3);
  EXPECT_NEAR(ambient_noise_level_db(10000.0, 100.0, calm), 29.3547 + 20.0, 0.01);
  const AmbientNoiseSpec windy{0.5, 8.0};
  double power = 0.0;
  for (int i = 0; i < 20000; ++i) power += std::pow(10.0, ambient_noise_psd_db(21000.0 + (i + 0.5) * 0.5, windy) / 10.0);
  EXPECT_NEAR(ambient_noise_level_db(26000.0, 10000.0, windy), 10.0 * std::log10(power * 0.5), 1e-3);
}

// The wavefront from (t_e, p_e) reaches a receiver at rest at t_e + travel time, to 1e-9 s; one moving
// straight at the source along a horizontal path (constant c) at D0 / (c + v) after the emission; outside
// the interval, none.
TEST(AcousticChannelTest, WavefrontArrivalAtMovingReceivers) {
  const physics::Ocean ocean(ctd_water(), 9.80665, 1);
  const AcousticChannel channel(ocean, AcousticsSpec{});
  const Eigen::Vector3d source(0.0, 0.0, -800.0);
  const Eigen::Vector3d rest(900.0, -400.0, -2100.0);
  const double t_e = 3.25;
  const double expected = t_e + channel.travel_time(source, rest);
  const std::optional<double> at_rest = channel.arrival(t_e, source, expected - 0.002, rest, expected + 0.003, rest);
  ASSERT_TRUE(at_rest);
  EXPECT_NEAR(*at_rest, expected, 1e-9);
  EXPECT_FALSE(channel.arrival(t_e, source, expected - 0.004, rest, expected - 0.001, rest));  // not yet
  EXPECT_FALSE(channel.arrival(t_e, source, expected + 0.001, rest, expected + 0.004, rest));  // already
  // Moving at v = 3 m/s towards the source along y at the source's depth, 1200 m away at t = t_e.
  const double c = ocean.sound_speed(800.0), v = 3.0, d0 = 1200.0;
  const double t_hit = t_e + d0 / (c + v);
  const auto p_at = [&](double t) { return Eigen::Vector3d(0.0, d0 - v * (t - t_e), -800.0); };
  const double t0 = t_hit - 0.004, t1 = t_hit + 0.001;
  const std::optional<double> moving = channel.arrival(t_e, source, t0, p_at(t0), t1, p_at(t1));
  ASSERT_TRUE(moving);
  EXPECT_NEAR(*moving, t_hit, 1e-9);
  // Emitted within the interval: measured from the emission.
  const std::optional<double> close = channel.arrival(t_e, source, t_e - 0.01, Eigen::Vector3d(0.0, 3.0, -800.0),
                                                      t_e + 0.01, Eigen::Vector3d(0.0, 3.0, -800.0));
  ASSERT_TRUE(close);
  EXPECT_NEAR(*close, t_e + 3.0 / c, 1e-9);
}

CollisionShape box(const Eigen::Vector3d& size) {
  CollisionShape shape;
  shape.type = CollisionShapeType::kBox;
  shape.box_size = size;
  return shape;
}

// Two hulls 200 m apart, each device inside its own hull: clear. A 4 m box between them blocks the path; moved
// 10 m aside it does not; the seabed (a ridge is a plane here: the devices on either side of it) blocks too.
TEST(AcousticChannelTest, OccludedByABodyOrTheSeabedBetweenNotByTheEndsOwnHulls) {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(0.0, 0.0, -50.0), -100.0);
  model.vehicles[0].links[0].collisions = {box(Eigen::Vector3d(6.0, 2.0, 2.0))};
  VehicleSpec other = model.vehicles[0];
  other.name = "other";
  other.X_WB_initial.translation() = Eigen::Vector3d(200.0, 0.0, -60.0);
  VehicleSpec block = model.vehicles[0];
  block.name = "block";
  block.links[0].collisions = {box(Eigen::Vector3d(4.0, 4.0, 4.0))};
  block.X_WB_initial.translation() = Eigen::Vector3d(100.0, 0.0, -55.0);
  model.vehicles.push_back(other);
  model.vehicles.push_back(block);
  testing::SensorTestWorld world(model, true);
  const Eigen::Vector3d a(1.0, 0.0, -50.0), b(199.0, 0.0, -60.0);
  EXPECT_TRUE(AcousticChannel::occluded(*world.rays, world.state, a, 0, b, 1));
  world.state.vehicles[2].body.X_WB.translation() = Eigen::Vector3d(100.0, 10.0, -55.0);
  world.state.step_count = 1;  // re-pose
  EXPECT_FALSE(AcousticChannel::occluded(*world.rays, world.state, a, 0, b, 1));
  EXPECT_TRUE(AcousticChannel::occluded(*world.rays, world.state, a, 0, Eigen::Vector3d(199.0, 0.0, -140.0), 1));
}

}  // namespace
}  // namespace hadal::sensors
