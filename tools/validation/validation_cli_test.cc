// Smoke runs of the validation commands as users run them, shortened (a 30 m descent, a 200 m leg, a
// 180 s IMU record, a 60 s heading track; under a second each): exit code, outputs written, and the
// printed JSON against the closed forms the tools print themselves.
#include <gtest/gtest.h>

#include "cli_test_support.h"
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace {

namespace fs = std::filesystem;

using hadal::test::Json;
using hadal::test::JsonParser;
using hadal::test::RunResult;

class ValidationCliTest : public hadal::test::CliTest {
 protected:
  RunResult run(const std::string& binary, const std::string& args) const {
    return CliTest::run(binary + " " + args);
  }
  // A PNG bigger than a blank image would be.
  void expect_outputs(const std::string& stem) const {
    EXPECT_GT(fs::file_size(dir_ + "/" + stem + ".png"), 20000u);
    EXPECT_GT(fs::file_size(dir_ + "/" + stem + ".csv"), 1000u);
  }
};

TEST_F(ValidationCliTest, LanderShortDescent) {
  const RunResult r = run(HADAL_VALIDATE_LANDER, "--depth 30 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  expect_outputs("lander_lift_magnus");
  const Json& on = json["with_lift_magnus"];
  const Json& off = json["without_lift_magnus"];
  EXPECT_TRUE(on["reached"].boolean);
  EXPECT_TRUE(off["reached"].boolean);
  // Terminal velocity: the closed form neglects spin and tilt; the upright, slowly spinning run
  // without lift must match it to 1 %, the run with lift (vanes at an angle of attack) to 3 %.
  const double v_closed = json["closed_form_terminal_velocity"]["at_depth_m_s"].number;
  EXPECT_NEAR(off["terminal_velocity_m_s"].number, v_closed, 0.01 * v_closed);
  EXPECT_NEAR(on["terminal_velocity_m_s"].number, v_closed, 0.03 * v_closed);
  // Lift on the canted vanes spins the lander up faster than their pressure drag alone.
  EXPECT_GT(on["spin_rate_deg_s"].number, 2.0 * off["spin_rate_deg_s"].number);
  EXPECT_LT(on["max_tilt_deg"].number, 1.0);
}

TEST_F(ValidationCliTest, CoriolisShortLeg) {
  const RunResult r = run(HADAL_VALIDATE_CORIOLIS, "--distance 200 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  expect_outputs("coriolis_deviation");
  EXPECT_TRUE(json["reached"].boolean);
  EXPECT_TRUE(json["coriolis_effect_detected"].boolean);
  const double with = json["lateral_deviation_with_coriolis_m"].number;
  const double without = json["lateral_deviation_without_coriolis_m"].number;
  // Northern hemisphere: deflected to starboard; without Coriolis the track stays straight.
  EXPECT_GT(with, 0.0);
  EXPECT_LT(std::fabs(without), 1e-3 * with);
  // The damped-hull closed form is steady-state at the cruise speed; the leg starts from rest, so
  // allow 10 %.
  EXPECT_NEAR(json["simulated_over_damped_hull"].number, 1.0, 0.1);
  EXPECT_LT(with, json["closed_form_lateral_deviation"]["free_particle_m"].number);
}

TEST_F(ValidationCliTest, AllanShortRecord) {
  // 180 s at 100 Hz: 18 000 samples per run, about 0.3 s for both runs.
  const RunResult r = run(HADAL_VALIDATE_ALLAN, "--hours 0.05 --rate 100 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  EXPECT_GT(fs::file_size(dir_ + "/allan_deviation.png"), 20000u);
  // Header + 18 000 rows of 7 numbers.
  EXPECT_GT(fs::file_size(dir_ + "/allan_record.csv"), 18000u * 7u * 10u);
  EXPECT_GT(fs::file_size(dir_ + "/allan_parameters.json"), 1000u);
  EXPECT_EQ(json["samples"].number, 18000.0);
  EXPECT_EQ(json["preset"].string, "honeywell_hg1700");
  // sigma(1 s) within 10 % of the configured ARW (the acceptance tolerance) on every gyro axis of both
  // runs, and of the VRW in the white-noise-only run (the HG1700's 1 mg bias floor hides it in the full
  // run). At tau = 1 s (m = 100) the overlapping estimator of white rate noise has
  // edf = (3 (N - 1) / (2 m) - 2 (N - 2) / N) 4 m^2 / (4 m^2 + 5) = 268 equivalent degrees of freedom
  // for N = 18 001 phase points (NIST SP 1065, section 5.3), a relative std of 1 / sqrt(2 edf) = 4.3 %:
  // 10 % is 2.3 sigma. The seed is fixed, so the outcome is deterministic (ratios 0.935 to 0.968).
  for (const char* run : {"full_model", "white_noise_only"}) {
    for (const char* axis : {"x", "y", "z"}) {
      EXPECT_NEAR(json[run]["gyro_rad_s"][axis]["sigma_1s_over_N"].number, 1.0, 0.10) << run << " " << axis;
    }
  }
  for (const char* axis : {"x", "y", "z"}) {
    EXPECT_NEAR(json["white_noise_only"]["accel_m_s2"][axis]["sigma_1s_over_N"].number, 1.0, 0.10) << axis;
  }
  EXPECT_TRUE(json["pass"]["gyro_noise_at_1s"].boolean);
  EXPECT_TRUE(json["pass"]["accel_noise_at_1s"].boolean);
  // No rate random walk in the HG1700 figures: nothing to check.
  EXPECT_EQ(json["pass"]["gyro_rate_random_walk"].type, Json::Type::kNull);
  // The vehicle stays at rest.
  EXPECT_EQ(json["full_model"]["max_speed_m_s"].number, 0.0);
  EXPECT_EQ(json["full_model"]["max_angular_rate_rad_s"].number, 0.0);

  const RunResult no_record =
      run(HADAL_VALIDATE_ALLAN, "--hours 0.01 --no-record --preset sensonor_stim300 --out " + dir_ + "/b");
  ASSERT_EQ(no_record.exit_code, 0) << no_record.err;
  EXPECT_EQ(parse(no_record.out)["preset"].string, "sensonor_stim300");
  EXPECT_FALSE(fs::exists(dir_ + "/b/allan_record.csv"));
  EXPECT_TRUE(fs::exists(dir_ + "/b/allan_deviation.png"));
}

TEST_F(ValidationCliTest, HeadingShortTrack) {
  // 60 s at 10 Hz: 601 samples, a few milliseconds.
  const RunResult r = run(HADAL_VALIDATE_HEADING, "--seconds 60 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  expect_outputs("magnetometer_heading");
  EXPECT_EQ(json["samples"].number, 601.0);
  const double declination = json["field"]["declination_deg"].number;
  const Json& naive = json["fixed_reference_model_naive_estimator_on_full_model_data"];
  const Json& calibrated = json["proposed_model_calibrated_estimator"];
  const Json& simulator = json["fixed_reference_simulator_naive_estimator"];
  // The naive estimator on the full model's data is biased by about -D (heading error = estimated -
  // true, clockwise; D < 0 at 30 W), plus the hard- and soft-iron errors, a few degrees.
  EXPECT_LT(declination, -5.0);
  EXPECT_NEAR(naive["mean_error_deg"].number, -declination, 3.0);
  EXPECT_GT(naive["max_abs_error_deg"].number, 10.0);
  // Calibrated and fixed-reference-on-its-own-data: white noise only (~0.25 deg RMS per sample).
  for (const Json* curve : {&calibrated, &simulator}) {
    EXPECT_LT(std::fabs((*curve)["mean_error_deg"].number), 0.1);
    EXPECT_LT((*curve)["rms_error_deg"].number, 0.4);
    EXPECT_LT((*curve)["max_abs_error_deg"].number, 1.5);
  }
  EXPECT_NEAR(json["track"]["max_pitch_deg"].number, 20.0, 0.5);
}

TEST_F(ValidationCliTest, UsageErrors) {
  EXPECT_EQ(run(HADAL_VALIDATE_LANDER, "--depth -5").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_LANDER, "--segments 7").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_CORIOLIS, "--bogus 1").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_CORIOLIS, "--scenario " + dir_ + "/missing.yaml --out " + dir_).exit_code, 1);
  EXPECT_EQ(run(HADAL_VALIDATE_ALLAN, "--hours 0").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_ALLAN, "--preset no_such_imu").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_ALLAN, "--hours 0.0001").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_HEADING, "--seconds 0").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_HEADING, "--bogus").exit_code, 2);
}

}  // namespace
