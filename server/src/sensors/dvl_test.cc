#include "hadal/sensors/dvl.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/reference_csv_test_support.h"

namespace hadal::sensors {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kDeg = kPi / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::uint64_t kSeed = 2025;

std::uint64_t bits(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// A noiseless DVL with the default geometry (30 deg, X layout, 0.7-90 m window).
DvlParams ideal_params() { return DvlParams{}; }

// Per-ping white noise of std sigma at sample period dt (density sigma sqrt(dt)).
void set_beam_sigma(DvlParams& params, double sigma, double dt) {
  params.beam_velocity_noise.noise.white_noise_density = sigma * std::sqrt(dt);
  params.water_track_velocity_noise.noise.white_noise_density = sigma * std::sqrt(dt);
}

// Flat seabed at altitude h below a DVL looking straight down: every beam's slant range is h / cos(theta).
DvlPingInput flat_bottom(const DvlParams& params, const Eigen::Vector3d& v_WS_S, double altitude, double dt) {
  DvlPingInput input;
  input.v_WS_S = v_WS_S;
  input.slant_range.fill(altitude / std::cos(params.beam_tilt));
  input.dt = dt;
  return input;
}

void expect_relative(const Eigen::Vector3d& got, const Eigen::Vector3d& want, double tolerance) {
  EXPECT_LE((got - want).norm(), tolerance * want.norm()) << "got " << got.transpose() << " want " << want.transpose();
}

// ----- geometry ----------------------------------------------------------------------------------------

// d_i = (s cos phi_i, s sin phi_i, c): unit norm to rounding (2 eps: three rounded squares), z exactly
// cos(theta), horizontal magnitude sin(theta), azimuths 45 + 90 k deg, and the exact symmetry the
// quarter-turn construction guarantees.
TEST(DvlGeometryTest, BeamUnitVectorsNormsTiltAndSymmetry) {
  for (double tilt_deg : {22.5, 25.0, 30.0}) {
    const double tilt = tilt_deg * kDeg;
    const auto d = dvl_beam_unit_vectors(tilt, 45.0 * kDeg);
    for (int i = 0; i < kDvlBeams; ++i) {
      EXPECT_NEAR(d[i].norm(), 1.0, 2 * kEps) << "beam " << i + 1;
      EXPECT_EQ(d[i].z(), std::cos(tilt));
      EXPECT_NEAR(std::acos(d[i].z() / d[i].norm()), tilt, 4 * kEps);
      EXPECT_NEAR(std::hypot(d[i].x(), d[i].y()), std::sin(tilt), 2 * kEps);
      EXPECT_NEAR(std::atan2(d[i].y(), d[i].x()), std::remainder((45.0 + 90.0 * i) * kDeg, 2 * kPi), 4 * kEps);
    }
    // Quarter turns about z: (x, y) -> (-y, x), exactly.
    for (int i = 0; i < kDvlBeams; ++i) {
      const Eigen::Vector3d& a = d[i];
      const Eigen::Vector3d& b = d[(i + 1) % kDvlBeams];
      EXPECT_EQ(b.x(), -a.y());
      EXPECT_EQ(b.y(), a.x());
      EXPECT_EQ(b.z(), a.z());
    }
    const Eigen::Vector3d sum = d[0] + d[1] + d[2] + d[3];
    EXPECT_NEAR(sum.x(), 0.0, 2 * kEps);
    EXPECT_NEAR(sum.y(), 0.0, 2 * kEps);
    EXPECT_NEAR(sum.z(), 4.0 * std::cos(tilt), 4 * kEps);
  }
  // "+" layout: beam 1 along x_S.
  const auto plus = dvl_beam_unit_vectors(30.0 * kDeg, 0.0);
  EXPECT_EQ(plus[0], Eigen::Vector3d(std::sin(30.0 * kDeg), 0.0, std::cos(30.0 * kDeg)));
  EXPECT_EQ(plus[1].x(), -0.0);
  EXPECT_EQ(plus[1].y(), std::sin(30.0 * kDeg));
}

// D^T D = diag(2 s^2, 2 s^2, 4 c^2), so the 4-beam covariance is sigma^2 diag(1/(2 s^2), 1/(2 s^2), 1/(4 c^2))
// (algebra: tolerance 16 eps relative, a 3x3 inverse and two products of rounded entries).
TEST(DvlGeometryTest, NormalMatrixAndCovarianceClosedForm) {
  const double tilt = 30.0 * kDeg;
  const double s = std::sin(tilt), c = std::cos(tilt);
  const auto d = dvl_beam_unit_vectors(tilt, 45.0 * kDeg);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (const auto& di : d) A += di * di.transpose();
  const Eigen::Matrix3d A_want = Eigen::Vector3d(2 * s * s, 2 * s * s, 4 * c * c).asDiagonal();
  EXPECT_LE((A - A_want).cwiseAbs().maxCoeff(), 4 * kEps);

  const double sigma2 = 0.005 * 0.005;
  std::array<double, kDvlBeams> variance;
  variance.fill(sigma2);
  const DvlBeamSolution solution = solve_dvl_beams(d, {0.0, 0.0, 0.0, 0.0}, {true, true, true, true}, variance);
  ASSERT_TRUE(solution.valid);
  const Eigen::Vector3d diag_want(sigma2 / (2 * s * s), sigma2 / (2 * s * s), sigma2 / (4 * c * c));
  for (int r = 0; r < 3; ++r) {
    EXPECT_NEAR(solution.covariance(r, r), diag_want[r], 16 * kEps * diag_want[r]);
    for (int col = 0; col < 3; ++col) {
      if (col != r) {
        EXPECT_NEAR(solution.covariance(r, col), 0.0, 16 * kEps * diag_want.maxCoeff());
      }
    }
  }
  // Three beams: sigma^2 (D^T D)^-1 = sigma^2 D^-1 D^-T with D square.
  Eigen::Matrix3d D;
  for (int i = 0; i < 3; ++i) D.row(i) = d[i].transpose();
  const DvlBeamSolution three = solve_dvl_beams(d, {0.0, 0.0, 0.0, 0.0}, {true, true, true, false}, variance);
  ASSERT_TRUE(three.valid);
  const Eigen::Matrix3d want3 = sigma2 * D.inverse() * D.inverse().transpose();
  EXPECT_LE((three.covariance - want3).cwiseAbs().maxCoeff(), 16 * kEps * want3.cwiseAbs().maxCoeff());
  EXPECT_FALSE(solve_dvl_beams(d, {0.0, 0.0, 0.0, 0.0}, {true, false, true, false}, variance).valid);
}

TEST(DvlGeometryTest, WaterTrackLayerPointsLieOnTheBeamInTheLayer) {
  DvlParams params = ideal_params();
  params.water_track_layer_near = 2.0;
  params.water_track_layer_far = 6.0;
  const auto d = dvl_beam_unit_vectors(params);
  for (int i = 0; i < kDvlBeams; ++i) {
    const auto points = water_track_layer_points(params, i, 4);
    ASSERT_EQ(points.size(), 4u);
    for (int j = 0; j < 4; ++j) {
      EXPECT_NEAR(points[j].z(), 2.5 + j, 8 * kEps);                 // cell centres along the axis
      EXPECT_NEAR(points[j].normalized().dot(d[i]), 1.0, 4 * kEps);  // on beam i
    }
  }
  EXPECT_THROW(water_track_layer_points(params, 4, 4), std::invalid_argument);
  EXPECT_THROW(water_track_layer_points(params, 0, 0), std::invalid_argument);
}

// ----- velocity solution -------------------------------------------------------------------------------

const std::vector<Eigen::Vector3d> kVelocities = {
    {1.5, 0.0, 0.0}, {0.7, -0.3, 0.12}, {-2.1, 0.8, -0.45}, {0.0, 0.0, 0.3}, {1e-3, 2e-3, -5e-4}};

// Zero noise: the per-beam velocities (v + b) . d_i, solved by least squares over 4 beams, give back
// v + b to rounding, and are consistent with it: the aggregate projected on each beam reproduces the beam
// velocity. Bound 8 eps = 1.8e-15 relative (over 2e5 random velocities the worst seen was 2.6 eps for 4
// beams, 5.0 eps for 3, 2.5 eps in water track).
TEST(DvlSolutionTest, ZeroNoiseFourBeamsReproduceTheAggregate) {
  DvlParams params = ideal_params();
  params.bias.initial = Eigen::Vector3d(0.01, -0.02, 0.005);
  DvlState state = make_dvl_state(params, kSeed, "auv", "dvl");
  for (const Eigen::Vector3d& v : kVelocities) {
    const DvlPing ping = dvl_ping(params, state, flat_bottom(params, v, 20.0, 0.1));
    ASSERT_EQ(ping.mode, DvlMode::kBottomTrack);
    EXPECT_EQ(ping.num_good_beams, 4);
    EXPECT_TRUE(ping.beam_ranges_valid);
    EXPECT_TRUE(ping.beam_velocities_valid);
    const Eigen::Vector3d want = v + params.bias.initial;
    expect_relative(ping.velocity, want, 8 * kEps);
    for (int i = 0; i < kDvlBeams; ++i) {
      EXPECT_TRUE(ping.velocity_valid[i]);
      EXPECT_NEAR(ping.beam_velocity[i], want.dot(ping.beam_unit_vec[i]), 4 * kEps * want.norm());
      EXPECT_NEAR(ping.velocity.dot(ping.beam_unit_vec[i]), ping.beam_velocity[i], 8 * kEps * want.norm());
      EXPECT_EQ(ping.beam_velocity_covar[i], 0.0);
    }
    EXPECT_EQ(ping.course_gnd, std::atan2(ping.velocity.y(), ping.velocity.x()));
    EXPECT_EQ(ping.speed_gnd, std::hypot(ping.velocity.x(), ping.velocity.y()));
    EXPECT_NEAR(ping.altitude, 20.0, 8 * kEps * 20.0);
  }
}

// Any one beam without a return: the exact 3-beam solution, still v + b to rounding (8 eps, as above).
TEST(DvlSolutionTest, ZeroNoiseThreeBeamsReproduceTheAggregate) {
  DvlParams params = ideal_params();
  params.water_track = false;
  params.bias.initial = Eigen::Vector3d(-0.003, 0.004, 0.01);
  DvlState state = make_dvl_state(params, kSeed, "auv", "dvl");
  for (int missing = 0; missing < kDvlBeams; ++missing) {
    for (const Eigen::Vector3d& v : kVelocities) {
      DvlPingInput input = flat_bottom(params, v, 30.0, 0.1);
      input.slant_range[missing] = missing % 2 ? kInf : std::numeric_limits<double>::quiet_NaN();
      const DvlPing ping = dvl_ping(params, state, input);
      ASSERT_EQ(ping.mode, DvlMode::kBottomTrack);
      EXPECT_EQ(ping.num_good_beams, 3);
      EXPECT_FALSE(ping.velocity_valid[missing]);
      EXPECT_FALSE(ping.range_valid[missing]);
      EXPECT_TRUE(std::isnan(ping.beam_velocity[missing]));
      EXPECT_TRUE(std::isnan(ping.range[missing]));
      EXPECT_EQ(ping.beam_quality[missing], 0.0);
      const Eigen::Vector3d want = v + params.bias.initial;
      expect_relative(ping.velocity, want, 8 * kEps);
      for (int i = 0; i < kDvlBeams; ++i) {
        if (i == missing) continue;
        EXPECT_NEAR(ping.velocity.dot(ping.beam_unit_vec[i]), ping.beam_velocity[i], 8 * kEps * want.norm());
      }
    }
  }
}

// Monte Carlo with a fixed seed against Cov(v) = sigma^2 (D^T D)^-1, for 4 beams and for 3. n pings give
// a sample variance with relative std sqrt(2 / (n - 1)) and a sample covariance C_ij with std
// sqrt((C_ii C_jj + C_ij^2) / n); the mean has std sqrt(C_ii / n). Bounds: 5 of those sigmas.
TEST(DvlSolutionTest, CovarianceFormulaMatchesMonteCarlo) {
  const double sigma = 0.01;
  const double dt = 0.2;
  const int n = 20000;
  for (int beams : {4, 3}) {
    DvlParams params = ideal_params();
    params.water_track = false;
    set_beam_sigma(params, sigma, dt);
    DvlState state = make_dvl_state(params, kSeed, "auv", beams == 4 ? "dvl4" : "dvl3");
    const Eigen::Vector3d v(0.8, -0.2, 0.05);
    DvlPingInput input = flat_bottom(params, v, 25.0, dt);
    if (beams == 3) input.slant_range[2] = kInf;
    Eigen::Matrix3d reported = Eigen::Matrix3d::Zero();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d sum2 = Eigen::Matrix3d::Zero();
    for (int k = 0; k < n; ++k) {
      const DvlPing ping = dvl_ping(params, state, input);
      ASSERT_EQ(ping.num_good_beams, beams);
      reported = ping.velocity_covariance;
      for (int i = 0; i < kDvlBeams; ++i) {
        if (ping.velocity_valid[i]) {
          EXPECT_NEAR(ping.beam_velocity_covar[i], sigma * sigma, 4 * kEps * sigma * sigma);
        }
      }
      const Eigen::Vector3d e = ping.velocity - v;
      sum += e;
      sum2 += e * e.transpose();
    }
    // The reported covariance is the closed form.
    const auto d = dvl_beam_unit_vectors(params);
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    for (int i = 0; i < kDvlBeams; ++i) {
      if (beams == 4 || i != 2) A += d[i] * d[i].transpose();
    }
    const Eigen::Matrix3d C = sigma * sigma * A.inverse();
    EXPECT_LE((reported - C).cwiseAbs().maxCoeff(), 16 * kEps * C.cwiseAbs().maxCoeff()) << beams << " beams";
    const Eigen::Vector3d mean = sum / n;
    const Eigen::Matrix3d sample = (sum2 - n * mean * mean.transpose()) / (n - 1);
    for (int r = 0; r < 3; ++r) {
      EXPECT_NEAR(mean[r], 0.0, 5.0 * std::sqrt(C(r, r) / n)) << beams << " beams, axis " << r;
      for (int col = 0; col < 3; ++col) {
        const double std_of_estimate = r == col ? C(r, r) * std::sqrt(2.0 / (n - 1))
                                                : std::sqrt((C(r, r) * C(col, col) + C(r, col) * C(r, col)) / n);
        EXPECT_NEAR(sample(r, col), C(r, col), 5.0 * std_of_estimate)
            << beams << " beams, (" << r << ", " << col << ")";
      }
    }
    if (beams == 3) {
      EXPECT_GT(std::abs(C(0, 2)), 0.1 * C(0, 0));  // the 3-beam case is genuinely correlated
    }
  }
}

// ----- bottom lock -------------------------------------------------------------------------------------

// Workhorse Navigator 600 (0.7-90 m): lock while the altitude is inside the window, lost above 90 m
// (water track takes over: the layer is clear of the seabed) and regained on the way down; below 0.7 m
// the bottom is inside the blanking and the water-track layer, so there is no velocity at all.
TEST(DvlLockTest, LostAboveMaxAltitudeAndRegainedBelow) {
  const auto* preset = config::find_preset(dvl_presets(), "teledyne_workhorse_navigator_600");
  ASSERT_NE(preset, nullptr);
  const DvlParams params = dvl_params(preset->figures, 1.0 / 7.0);
  DvlState state = make_dvl_state(params, kSeed, "auv", "dvl");
  const Eigen::Vector3d v(1.0, 0.1, 0.0);
  struct Step {
    double altitude;
    DvlMode mode;
  };
  const Step steps[] = {{10.0, DvlMode::kBottomTrack}, {60.0, DvlMode::kBottomTrack}, {89.9, DvlMode::kBottomTrack},
                        {90.1, DvlMode::kWaterTrack},  {150.0, DvlMode::kWaterTrack}, {90.1, DvlMode::kWaterTrack},
                        {89.9, DvlMode::kBottomTrack}, {5.0, DvlMode::kBottomTrack},  {0.8, DvlMode::kBottomTrack},
                        {0.6, DvlMode::kNone},         {3.0, DvlMode::kBottomTrack}};
  for (const Step& step : steps) {
    const DvlPing ping = dvl_ping(params, state, flat_bottom(params, v, step.altitude, 1.0 / 7.0));
    EXPECT_EQ(ping.mode, step.mode) << "altitude " << step.altitude;
    const bool locked = step.mode == DvlMode::kBottomTrack;
    EXPECT_EQ(ping.beam_ranges_valid, locked) << "altitude " << step.altitude;
    if (locked) {
      EXPECT_EQ(ping.num_good_beams, 4);
      EXPECT_NEAR(ping.altitude, step.altitude, 8 * kEps * step.altitude);
      EXPECT_NEAR((ping.velocity - v).norm(), 0.0, 10 * 0.005);  // beam sigma 5 mm/s
    } else {
      EXPECT_TRUE(std::isnan(ping.altitude));
      for (int i = 0; i < kDvlBeams; ++i) EXPECT_FALSE(ping.range_valid[i]);
    }
  }
}

// Fewer than 3 beams return: no bottom lock and, without water track, no velocity (NaN, covariance -1,
// course/speed NaN), yet the returning beams' ranges and altitude are reported. With water track on, the
// two returns at 3 m cut the 2-6 m layer, leaving 2 usable beams: still no velocity.
TEST(DvlLockTest, FewerThanThreeBeamsNoLock) {
  for (bool water_track : {false, true}) {
    DvlParams params = ideal_params();
    params.water_track = water_track;
    DvlState state = make_dvl_state(params, kSeed, "auv", "dvl");
    DvlPingInput input = flat_bottom(params, Eigen::Vector3d(0.5, 0.0, 0.0), 3.0, 0.1);
    input.slant_range[1] = std::numeric_limits<double>::quiet_NaN();
    input.slant_range[3] = kInf;
    const DvlPing ping = dvl_ping(params, state, input);
    EXPECT_EQ(ping.mode, DvlMode::kNone);
    EXPECT_FALSE(ping.beam_ranges_valid);
    EXPECT_FALSE(ping.beam_velocities_valid);
    EXPECT_EQ(ping.num_good_beams, 2);
    EXPECT_TRUE(ping.velocity.array().isNaN().all());
    EXPECT_TRUE((ping.velocity_covariance.array() == -1.0).all());
    EXPECT_TRUE(std::isnan(ping.course_gnd));
    EXPECT_TRUE(std::isnan(ping.speed_gnd));
    EXPECT_NEAR(ping.altitude, 3.0, 8 * kEps * 3.0);
    EXPECT_TRUE(ping.range_valid[0] && ping.range_valid[2]);
    EXPECT_FALSE(ping.range_valid[1] || ping.range_valid[3]);
    EXPECT_EQ(ping.range_covar[1], -1.0);
    for (int i = 0; i < kDvlBeams; ++i) {
      EXPECT_FALSE(ping.velocity_valid[i]);
      EXPECT_EQ(ping.beam_velocity_covar[i], -1.0);
    }
  }
}

// Dropout p per beam per ping (fixed seed): the dropped count over n beam-pings is binomial, std
// sqrt(n p (1 - p)); the locked fraction is P(>= 3 of 4 kept) = q^4 + 4 p q^3 (q = 1 - p), std
// sqrt(P (1 - P) / pings). Bounds: 5 sigma. p = 0 never drops, p = 1 always does.
TEST(DvlLockTest, DropoutStatistics) {
  const double p = 0.2;
  const int pings = 20000;
  DvlParams params = ideal_params();
  params.water_track = false;
  params.dropout_probability = p;
  DvlState state = make_dvl_state(params, kSeed, "auv", "dvl");
  const DvlPingInput input = flat_bottom(params, Eigen::Vector3d(0.3, 0.2, 0.0), 15.0, 0.1);
  int dropped = 0;
  int locked = 0;
  for (int k = 0; k < pings; ++k) {
    const DvlPing ping = dvl_ping(params, state, input);
    for (int i = 0; i < kDvlBeams; ++i) dropped += !ping.range_valid[i];
    locked += ping.mode == DvlMode::kBottomTrack;
    EXPECT_EQ(ping.mode == DvlMode::kBottomTrack, ping.num_good_beams >= 3);
  }
  const double n = kDvlBeams * static_cast<double>(pings);
  EXPECT_NEAR(dropped, n * p, 5.0 * std::sqrt(n * p * (1 - p)));
  const double q = 1 - p;
  const double P = q * q * q * q + 4 * p * q * q * q;
  EXPECT_NEAR(locked, pings * P, 5.0 * std::sqrt(pings * P * (1 - P)));

  for (double probability : {0.0, 1.0}) {
    params.dropout_probability = probability;
    DvlState s = make_dvl_state(params, kSeed, "auv", "dvl");
    for (int k = 0; k < 100; ++k) {
      const DvlPing ping = dvl_ping(params, s, input);
      EXPECT_EQ(ping.num_good_beams, probability == 0.0 ? 4 : 0);
    }
  }
}

// ----- water track -------------------------------------------------------------------------------------

// Bottom out of reach (no returns, or returns beyond max altitude) and a current u: the water-track
// velocity is v_vehicle - v_water (zero noise: to 8 eps relative), beams (v - u) . d_i.
TEST(DvlWaterTrackTest, VelocityIsVehicleMinusWater) {
  DvlParams params = ideal_params();
  DvlState state = make_dvl_state(params, kSeed, "auv", "dvl");
  const Eigen::Vector3d u(0.25, -0.4, 0.02);
  for (const Eigen::Vector3d& v : kVelocities) {
    for (double altitude : {kInf, 500.0}) {
      DvlPingInput input = flat_bottom(params, v, altitude, 0.1);
      input.v_water_S.fill(u);
      const DvlPing ping = dvl_ping(params, state, input);
      ASSERT_EQ(ping.mode, DvlMode::kWaterTrack);
      EXPECT_EQ(ping.num_good_beams, 4);
      EXPECT_FALSE(ping.beam_ranges_valid);
      EXPECT_TRUE(std::isnan(ping.altitude));
      expect_relative(ping.velocity, v - u, 8 * kEps);
      for (int i = 0; i < kDvlBeams; ++i) {
        EXPECT_NEAR(ping.beam_velocity[i], (v - u).dot(ping.beam_unit_vec[i]), 4 * kEps * (v - u).norm());
      }
    }
  }
  // Bottom track ignores the current; water track off leaves no velocity.
  DvlPingInput input = flat_bottom(params, kVelocities[1], 20.0, 0.1);
  input.v_water_S.fill(u);
  expect_relative(dvl_ping(params, state, input).velocity, kVelocities[1], 8 * kEps);
  params.water_track = false;
  input.slant_range.fill(kInf);
  EXPECT_EQ(dvl_ping(params, state, input).mode, DvlMode::kNone);
}

// ----- sound speed -------------------------------------------------------------------------------------

// A DVL assuming 1500 m/s in 1530 m/s water reads velocities and ranges scaled by k = 1500 / 1530
// (Doppler and two-way travel time alike); assumed_sound_speed = 0 means measured c, k = 1.
TEST(DvlSoundSpeedTest, AssumedSoundSpeedScalesVelocityAndRange) {
  EXPECT_EQ(dvl_sound_speed_scale(1500.0, 1530.0), 1500.0 / 1530.0);
  EXPECT_EQ(dvl_sound_speed_scale(0.0, 1530.0), 1.0);
  DvlParams params = ideal_params();
  params.assumed_sound_speed = 1500.0;
  DvlState state = make_dvl_state(params, kSeed, "auv", "dvl");
  const double k = 1500.0 / 1530.0;
  for (const Eigen::Vector3d& v : kVelocities) {
    DvlPingInput input = flat_bottom(params, v, 40.0, 0.1);
    input.sound_speed = 1530.0;
    const DvlPing ping = dvl_ping(params, state, input);
    ASSERT_EQ(ping.mode, DvlMode::kBottomTrack);
    EXPECT_EQ(ping.sound_speed, 1500.0);
    expect_relative(ping.velocity, k * v, 8 * kEps);
    for (int i = 0; i < kDvlBeams; ++i) EXPECT_NEAR(ping.range[i], k * input.slant_range[i], 4 * kEps * 40.0);
    EXPECT_NEAR(ping.altitude, k * 40.0, 8 * kEps * 40.0);
  }
  params.assumed_sound_speed = 0.0;
  DvlPingInput input = flat_bottom(params, kVelocities[1], 40.0, 0.1);
  input.sound_speed = 1530.0;
  const DvlPing ping = dvl_ping(params, state, input);
  EXPECT_EQ(ping.sound_speed, 1530.0);
  expect_relative(ping.velocity, kVelocities[1], 8 * kEps);
}

// ----- bias --------------------------------------------------------------------------------------------

// Noise off, drift rate xi: b(t) = xi t, which a stationary DVL reads as its velocity, and the
// dead-reckoned position error grows as xi t^2 / 2 (monotonically). Tolerance: the summation of n
// increments xi dt carries at most ~n eps relative error (n = 36000: 8e-12); 1e-11 relative.
TEST(DvlBiasTest, DriftGrowsAsXiTimesT) {
  DvlParams params = ideal_params();
  params.bias.drift_rate = Eigen::Vector3d(1e-6, -2e-6, 5e-7);
  DvlState state = make_dvl_state(params, kSeed, "auv", "dvl");
  EXPECT_EQ(state.bias, Eigen::Vector3d::Zero());
  const double dt = 0.1;
  const int n = 36000;  // one hour
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double previous_error = 0.0;
  for (int k = 1; k <= n; ++k) {
    const DvlPing ping = dvl_ping(params, state, flat_bottom(params, Eigen::Vector3d::Zero(), 20.0, dt));
    const double t = k * dt;
    position += ping.velocity * dt;
    if (k % 3600 == 0) {
      expect_relative(state.bias, params.bias.drift_rate * t, 1e-11);
      expect_relative(ping.velocity, params.bias.drift_rate * t, 1e-11);
      // Rectangle rule over b = xi t_k: xi dt^2 n (n + 1) / 2.
      expect_relative(position, params.bias.drift_rate * dt * dt * k * (k + 1) / 2.0, 1e-10);
      EXPECT_GT(position.norm(), previous_error);
      previous_error = position.norm();
    }
  }
}

// Random-walk part: b_x(T) = K W(T) has variance K^2 T whatever the ping interval (fixed seeds over
// 2000 sensors; sample variance relative std sqrt(2 / (m - 1)), bound 5 sigma). The drawn drift rate and
// turn-on bias have their configured spreads (same bound).
TEST(DvlBiasTest, RandomWalkAndDrawsHaveTheirVariances) {
  DvlParams params = ideal_params();
  params.bias.random_walk_density = 1e-4;
  params.bias.initial_sigma = 2e-3;
  params.bias.drift_rate_sigma = 3e-6;
  const int m = 2000;
  const double T = 10.0;
  for (double dt : {0.1, 0.5}) {
    double sum_walk2 = 0.0, sum_b02 = 0.0, sum_xi2 = 0.0;
    for (int j = 0; j < m; ++j) {
      DvlState state = make_dvl_state(params, kSeed, "auv", "dvl" + std::to_string(j));
      const Eigen::Vector3d b0 = state.bias;
      const Eigen::Vector3d xi = state.drift_rate;
      const int pings = static_cast<int>(std::lround(T / dt));
      for (int k = 0; k < pings; ++k) dvl_ping(params, state, flat_bottom(params, Eigen::Vector3d::Zero(), 20.0, dt));
      const double walk = state.bias.x() - b0.x() - xi.x() * pings * dt;
      sum_walk2 += walk * walk;
      sum_b02 += b0.y() * b0.y();
      sum_xi2 += xi.z() * xi.z();
    }
    const double tolerance = 5.0 * std::sqrt(2.0 / (m - 1));
    const double K = params.bias.random_walk_density;
    EXPECT_NEAR(sum_walk2 / m / (K * K * T), 1.0, tolerance) << "dt " << dt;
    EXPECT_NEAR(sum_b02 / m / (params.bias.initial_sigma * params.bias.initial_sigma), 1.0, tolerance);
    EXPECT_NEAR(sum_xi2 / m / (params.bias.drift_rate_sigma * params.bias.drift_rate_sigma), 1.0, tolerance);
  }
}

// ----- determinism -------------------------------------------------------------------------------------

DvlParams noisy_params() {
  DvlParams params = ideal_params();
  set_beam_sigma(params, 0.005, 0.1);
  params.range_noise.noise.white_noise_density = 0.01 * std::sqrt(0.1);
  params.range_noise.lsb = 1e-3;
  params.beam_velocity_noise.noise.bias_random_walk_density = 1e-5;
  params.dropout_probability = 0.05;
  params.assumed_sound_speed = 1500.0;
  params.bias.initial_sigma = 1e-3;
  params.bias.drift_rate_sigma = 1e-6;
  params.bias.random_walk_density = 1e-5;
  return params;
}

// Varying altitude (through the lock window, and below it every 97th ping), velocity, current and sound
// speed, so every mode occurs.
DvlPingInput varied_input(const DvlParams& params, int k) {
  const double altitude = k % 97 == 0 ? 0.5 : 60.0 + 45.0 * std::sin(0.01 * k);
  DvlPingInput input = flat_bottom(params, Eigen::Vector3d(std::cos(0.02 * k), 0.3, 0.01 * (k % 7)), altitude, 0.1);
  if (k % 13 == 0) input.slant_range[k % 4] = kInf;
  input.v_water_S.fill(Eigen::Vector3d(0.1, -0.05 * (k % 3), 0.0));
  input.sound_speed = 1480.0 + (k % 50);
  return input;
}

bool bit_identical(const DvlPing& a, const DvlPing& b) {
  bool same = a.mode == b.mode && a.num_good_beams == b.num_good_beams && a.beam_ranges_valid == b.beam_ranges_valid &&
              a.beam_velocities_valid == b.beam_velocities_valid && bits(a.altitude) == bits(b.altitude) &&
              bits(a.course_gnd) == bits(b.course_gnd) && bits(a.speed_gnd) == bits(b.speed_gnd) &&
              bits(a.sound_speed) == bits(b.sound_speed);
  for (int r = 0; r < 3; ++r) {
    same = same && bits(a.velocity[r]) == bits(b.velocity[r]);
    for (int c = 0; c < 3; ++c) same = same && bits(a.velocity_covariance(r, c)) == bits(b.velocity_covariance(r, c));
  }
  for (int i = 0; i < kDvlBeams; ++i) {
    same = same && bits(a.range[i]) == bits(b.range[i]) && bits(a.range_covar[i]) == bits(b.range_covar[i]) &&
           bits(a.beam_velocity[i]) == bits(b.beam_velocity[i]) &&
           bits(a.beam_velocity_covar[i]) == bits(b.beam_velocity_covar[i]) && a.range_valid[i] == b.range_valid[i] &&
           a.velocity_valid[i] == b.velocity_valid[i] && bits(a.beam_quality[i]) == bits(b.beam_quality[i]);
  }
  return same;
}

// Same seed, same inputs: bit-identical pings and states; a state copied mid-run continues identically
// (snapshot/restore); another seed or another sensor name differs.
TEST(DvlDeterminismTest, SameSeedGivesIdenticalPings) {
  const DvlParams params = noisy_params();
  DvlState a = make_dvl_state(params, kSeed, "auv", "dvl");
  DvlState b = make_dvl_state(params, kSeed, "auv", "dvl");
  DvlState other_seed = make_dvl_state(params, kSeed + 1, "auv", "dvl");
  DvlState other_sensor = make_dvl_state(params, kSeed, "auv", "dvl2");
  EXPECT_EQ(a, b);
  EXPECT_NE(a, other_seed);
  int modes[3] = {0, 0, 0};
  int differ_seed = 0, differ_sensor = 0;
  DvlState snapshot;
  std::vector<DvlPing> tail;
  for (int k = 0; k < 2000; ++k) {
    if (k == 1000) snapshot = a;
    const DvlPingInput input = varied_input(params, k);
    const DvlPing pa = dvl_ping(params, a, input);
    const DvlPing pb = dvl_ping(params, b, input);
    ASSERT_TRUE(bit_identical(pa, pb)) << "ping " << k;
    if (k >= 1000) tail.push_back(pa);
    differ_seed += !bit_identical(pa, dvl_ping(params, other_seed, input));
    differ_sensor += !bit_identical(pa, dvl_ping(params, other_sensor, input));
    ++modes[static_cast<int>(pa.mode)];
  }
  EXPECT_EQ(a, b);
  EXPECT_GT(modes[0], 0);
  EXPECT_GT(modes[1], 0);
  EXPECT_GT(modes[2], 0);
  EXPECT_GT(differ_seed, 1900);
  EXPECT_GT(differ_sensor, 1900);
  for (int k = 1000; k < 2000; ++k) {
    ASSERT_TRUE(bit_identical(dvl_ping(params, snapshot, varied_input(params, k)), tail[k - 1000])) << k;
  }
}

// ----- presets and validation --------------------------------------------------------------------------

// Every preset is its row of docs/reference/sensors/dvl_specs.csv (read from the file); its parameters at
// the sheet's rate are valid and give the sheet's per-ping beam sigma. Workhorse Navigator 600 row: 30 deg,
// 0.7-90 m, 0.005 m/s per beam per ping at its 7 Hz.
TEST(DvlPresetTest, PresetsFollowTheReferenceRows) {
  const auto rows = reference_tables::csv_rows(std::string(HADAL_SENSOR_REFERENCE_DIR) + "/dvl_specs.csv",
                                               "model,freq_kHz,beam_angle_deg,beam_width_deg,min_alt_m,max_alt_m", 11);
  ASSERT_EQ(dvl_presets().size(), 6u);
  for (const config::Preset<DvlDatasheet>& preset : dvl_presets()) {
    SCOPED_TRACE(std::string(preset.id));
    const auto row = rows.find(std::string(preset.product));
    ASSERT_NE(row, rows.end()) << "no row '" << preset.product << "'";
    const auto cell = [&](std::size_t column) {
      const std::vector<double> figures = reference_tables::cell_figures(row->second[column]);
      return figures.empty() ? 0.0 : figures[0];  // an empty cell: not listed
    };
    const DvlDatasheet& sheet = preset.figures;
    EXPECT_EQ(sheet.frequency_khz, cell(0));
    EXPECT_EQ(sheet.beam_tilt_deg, cell(1));
    EXPECT_EQ(sheet.min_altitude_m, cell(3));
    EXPECT_EQ(sheet.max_altitude_m, cell(4));
    EXPECT_EQ(sheet.update_hz, cell(5));
    EXPECT_EQ(sheet.beam_velocity_sigma, cell(6));
    EXPECT_EQ(sheet.water_track_velocity_sigma, cell(7));
    EXPECT_EQ(sheet.type == DvlType::kPhasedArray, preset.product.find("phased array") != std::string_view::npos);
    const DvlParams params = dvl_params(sheet, 1.0 / sheet.update_hz);
    EXPECT_NO_THROW(validate(params));
    EXPECT_NEAR(white_noise_sigma(params.beam_velocity_noise.noise.white_noise_density, 1.0 / sheet.update_hz),
                sheet.beam_velocity_sigma, 4 * kEps * sheet.beam_velocity_sigma);
  }

  const DvlDatasheet& whn = config::find_preset(dvl_presets(), "teledyne_workhorse_navigator_600")->figures;
  const DvlParams p = dvl_params(whn, 1.0 / 7.0);
  EXPECT_DOUBLE_EQ(p.beam_tilt, 30.0 * kDeg);
  EXPECT_EQ(p.min_altitude, 0.7);
  EXPECT_EQ(p.max_altitude, 90.0);
  EXPECT_EQ(p.type, DvlType::kPiston);
  // No water-track figure on the row: the bottom-track one.
  EXPECT_EQ(p.water_track_velocity_noise.noise.white_noise_density, p.beam_velocity_noise.noise.white_noise_density);
  const DvlParams pn = dvl_params(config::find_preset(dvl_presets(), "nortek_dvl1000_4000m")->figures, 1.0 / 8.0);
  EXPECT_DOUBLE_EQ(pn.beam_tilt, 25.0 * kDeg);
  EXPECT_NEAR(white_noise_sigma(pn.water_track_velocity_noise.noise.white_noise_density, 1.0 / 8.0), 0.015,
              4 * kEps * 0.015);
  EXPECT_EQ(config::find_preset(dvl_presets(), "no_such_dvl"), nullptr);
  EXPECT_THROW(dvl_params(whn, 0.0), std::invalid_argument);
}

TEST(DvlValidationTest, RejectsBadParametersAndInputs) {
  auto throws_naming = [](const DvlParams& params, const std::string& field) {
    try {
      validate(params);
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "no error for " << field;
  };
  DvlParams p = ideal_params();
  EXPECT_NO_THROW(validate(p));
  p.beam_tilt = 0.0;
  throws_naming(p, "beam_tilt");
  p = ideal_params();
  p.max_altitude = 0.5;
  throws_naming(p, "max_altitude");
  p = ideal_params();
  p.dropout_probability = 1.5;
  throws_naming(p, "dropout_probability");
  p = ideal_params();
  p.water_track_layer_far = 1.0;
  throws_naming(p, "water_track_layer_far");
  p = ideal_params();
  p.beam_velocity_noise.noise.white_noise_density = -1.0;
  throws_naming(p, "beam_velocity_noise");
  p = ideal_params();
  p.bias.random_walk_density = std::numeric_limits<double>::quiet_NaN();
  throws_naming(p, "bias.random_walk_density");
  EXPECT_THROW(make_dvl_state(p, kSeed, "auv", "dvl"), std::invalid_argument);

  p = ideal_params();
  DvlState state = make_dvl_state(p, kSeed, "auv", "dvl");
  DvlPingInput input = flat_bottom(p, Eigen::Vector3d::Zero(), 10.0, 0.0);
  EXPECT_THROW(dvl_ping(p, state, input), std::invalid_argument);
  input.dt = 0.1;
  input.sound_speed = 0.0;
  EXPECT_THROW(dvl_ping(p, state, input), std::invalid_argument);
}

}  // namespace
}  // namespace hadal::sensors
