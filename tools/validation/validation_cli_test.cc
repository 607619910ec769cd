// Smoke runs of the validation commands as users run them, shortened (a 30 m descent, a 200 m leg, a
// 180 s IMU record, a 60 s heading track, a 15 min DVL record, 6 s of crawler driving; under a second each): exit code, outputs
// written, and the printed JSON against the closed forms the tools print themselves.
#include <gtest/gtest.h>

#include "cli_test_support.h"
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
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

// The crawler figure, 6 s of driving: traction balances the water's drag once the speed is steady,
// exceeds it while accelerating, the lateral forces stay near zero, and the tracks sink what Bekker
// predicts (3 %, the tolerance).
TEST_F(ValidationCliTest, CrawlerShortDrive) {
  const RunResult r = run(HADAL_VALIDATE_CRAWLER, "--duration 6 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  expect_outputs("crawler_forces");
  const double traction = json["steady_traction_N"].number, resistance = json["steady_resistance_N"].number;
  EXPECT_GT(resistance, 0.0);
  EXPECT_NEAR(traction, resistance, 0.02 * resistance);
  EXPECT_GT(json["peak_net_force_N"].number, 10.0 * resistance);
  EXPECT_LT(json["peak_lateral_force_N"].number, 0.01 * resistance + 1.0);
  EXPECT_NEAR(json["steady_speed_m_s"].number, json["belt_speed_m_s"].number, 0.01 * json["belt_speed_m_s"].number);
  const double z = json["sinkage_closed_form_m"].number;
  EXPECT_NEAR(json["sinkage_m"].number, z, 0.03 * z);
  EXPECT_EQ(run(HADAL_VALIDATE_CRAWLER, "--setpoint 1.5").exit_code, 2);
}

// The arm figure, 10 s: the coupled base pitches nose-down (the arm's wet weight forward of the centre of
// buoyancy) and moves, by more than a degree and a centimetre; the uncoupled base stays at its trim (the
// scenario's centre of mass trims the stowed arm level to 0.1 deg).
TEST_F(ValidationCliTest, ArmShortUnfolding) {
  const RunResult r = run(HADAL_VALIDATE_ARM, "--duration 10 --start 1 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  expect_outputs("arm_reaction");
  EXPECT_GT(json["coupled_final_pitch_deg"].number, 1.0);
  EXPECT_GT(json["coupled_peak_displacement_m"].number, 0.01);
  EXPECT_LT(json["uncoupled_peak_pitch_deg"].number, 0.1);
  EXPECT_LT(json["uncoupled_peak_displacement_m"].number, 0.005);
  EXPECT_EQ(run(HADAL_VALIDATE_ARM, "--start -1").exit_code, 2);
}

// The towfish figure on 400 s runs (the fish settles in ~300 s from its 30 deg start): at 3 and 5 kn the steady
// depth, layback and top tension land within 1 % of the towed-cable solution (the figure, 600 s runs: 0.1 %),
// and the fish flies shallower at the faster speed. Speeds in the wrong order are a usage error.
TEST_F(ValidationCliTest, TowfishSteadyDepth) {
  const RunResult r = run(HADAL_VALIDATE_TOWFISH, "--duration 400 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  expect_outputs("towfish_depth");
  for (const char* speed : {"slow", "fast"}) {
    EXPECT_LT(std::abs(json[speed]["depth_relative_difference"].number), 0.01) << speed;
    EXPECT_LT(std::abs(json[speed]["layback_relative_difference"].number), 0.01) << speed;
    EXPECT_LT(std::abs(json[speed]["top_tension_relative_difference"].number), 0.01) << speed;
  }
  EXPECT_GT(json["slow"]["fish_depth_m"].number, json["fast"]["fish_depth_m"].number + 20.0);
  EXPECT_EQ(run(HADAL_VALIDATE_TOWFISH, "--slow-kn 5 --fast-kn 3").exit_code, 2);
}

// The waves figure on a 1 h record: its Hs within 2 % and its (S^4-weighted) peak within one sampling bin of the
// target's, the Welch spectrum holding nearly the target's m0 (the band 0.02-0.6 Hz, and the record's own scatter).
TEST_F(ValidationCliTest, WavesSpectrum) {
  const RunResult r = run(HADAL_VALIDATE_WAVES, "--hours 1 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  expect_outputs("waves_spectrum");
  EXPECT_LT(std::abs(json["significant_height_relative_difference"].number), 0.02);
  EXPECT_LT(std::abs(json["peak_frequency_difference_hz"].number), json["sampling_bin_hz"].number);
  EXPECT_NEAR(json["welch_m0_over_target"].number, 1.0, 0.05);
  EXPECT_EQ(run(HADAL_VALIDATE_WAVES, "--components 100.5").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_WAVES, "--tp 0").exit_code, 2);
}

// The vessel figure on 6 min: a 2 m catamaran drifting in 100 m waves follows the surface (linear theory for a body
// much shorter than the waves: response 1): its heave's significant height and its response at the spectrum's peak
// within 5 % of the sea's at the vessel; its pitch follows the slope along its heading, above it by up to 25 % (its
// pitch resonance at ~0.8 Hz lifts the spectrum's tail, 1 / (1 - (f / f_n)^2) = 1.1-1.4 above 0.3 Hz; 20 min: 1.09).
TEST_F(ValidationCliTest, VesselFollowsItsSea) {
  const RunResult r = run(HADAL_VALIDATE_VESSEL_WAVES, "--minutes 6 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  expect_outputs("vessel_waves");
  EXPECT_GT(json["sea_significant_height_m"].number, 1.5);
  EXPECT_NEAR(json["heave_over_sea"].number, 1.0, 0.05);
  EXPECT_NEAR(json["heave_response_at_peak"].number, 1.0, 0.05);
  EXPECT_GT(json["pitch_over_slope"].number, 1.0);
  EXPECT_LT(json["pitch_over_slope"].number, 1.25);
  EXPECT_EQ(run(HADAL_VALIDATE_VESSEL_WAVES, "--minutes 1").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_VESSEL_WAVES, "--scenario " HADAL_VALIDATION_SCENARIOS "/dvl_static.yaml").exit_code, 1);
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

// Reads a whole file (the CSV comparison of two runs).
std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The printed JSON without what legitimately differs between two identical runs: wall times and
// throughput, and the output paths.
std::string without_timing_and_paths(const std::string& json) {
  std::istringstream in(json);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.find("wall") != std::string::npos || line.find("\"png\"") != std::string::npos ||
        line.find("\"csv\"") != std::string::npos || line.find("\"parameters\"") != std::string::npos) {
      continue;
    }
    out += line + "\n";
  }
  return out;
}

TEST_F(ValidationCliTest, DvlShortRecord) {
  // 15 min at 5 Hz: 4500 pings per run, drift sampled every minute; about 0.2 s for both runs.
  const std::string args = "--hours 0.25 --interval 1";
  const RunResult r = run(HADAL_VALIDATE_DVL, args + " --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  EXPECT_GT(fs::file_size(dir_ + "/dvl_drift.png"), 20000u);
  // Header + 2 x 4500 rows of 13 fields.
  EXPECT_GT(fs::file_size(dir_ + "/dvl_record.csv"), 2u * 4500u * 13u * 8u);
  EXPECT_GT(fs::file_size(dir_ + "/dvl_parameters.json"), 500u);
  EXPECT_EQ(json["pings"].number, 4500.0);
  EXPECT_EQ(json["preset"].string, "teledyne_workhorse_navigator_600");
  const Json& full = json["full_model"];
  const Json& white = json["white_noise_only"];
  const Json& closed = json["closed_form"];

  // Truly at rest and in 4-beam bottom lock on every ping of both runs.
  for (const Json* run : {&full, &white}) {
    EXPECT_EQ((*run)["max_displacement_m"].number, 0.0);
    EXPECT_EQ((*run)["max_rotation_rad"].number, 0.0);
    EXPECT_EQ((*run)["bottom_track_four_beam_pings"].number, 4500.0);
  }

  // Per-axis velocity std of the 4-beam least squares, computed here: X layout at theta = 30 deg gives
  // D^T D = diag(2 sin^2, 2 sin^2, 4 cos^2), so sigma_h = sigma_beam / sqrt(2 sin^2 30) and
  // sigma_z = sigma_beam / (2 cos 30), sigma_beam = 5 mm/s (Workhorse preset). The JSON prints 9
  // significant digits: 1e-8 relative.
  const double kPi = 3.14159265358979323846;
  const double sigma_beam = 0.005, T = 0.2, t = 900.0;
  const double sigma[3] = {sigma_beam / std::sqrt(2.0 * 0.25), sigma_beam / std::sqrt(2.0 * 0.25),
                           sigma_beam / (2.0 * std::cos(kPi / 6.0))};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(closed["sigma_v_S_m_s"][i].number, sigma[i], 1e-8 * sigma[i]) << i;
    EXPECT_NEAR(closed["sigma_v_reported_by_dvl_S_m_s"][i].number, sigma[i], 1e-8 * sigma[i]) << i;
    // The white-only run's sample std: relative scatter 1 / sqrt(2 n) = 1.05 % for n = 4500; 5 % is
    // 4.7 sigma (seed 1: within 1.7 %). Catches a missing, doubled or per-axis instead of per-beam noise.
    EXPECT_NEAR(white["std_velocity_S_m_s"][i].number / sigma[i], 1.0, 0.05) << i;
  }

  // S (z down, x forward, rolled 180 deg) on a body yawed 30 deg: R_WS = Rz(30) diag(1, -1, -1).
  const double c = std::cos(kPi / 6.0), s = std::sin(kPi / 6.0);
  const double R_WS[3][3] = {{c, s, 0.0}, {s, -c, 0.0}, {0.0, 0.0, -1.0}};
  // The white-only dead-reckoning error is a random walk: per W axis std sigma_i sqrt(T t) (sigma_W =
  // sigma_S here: the rotation is about z and sigma_x = sigma_y). Two-sided 4 sigma: 6e-5 per axis for a
  // correct model (seed 1: 1.7, 1.1, 0.5 sigma); an integration without T, or of the beam velocities
  // instead of the solution, is off by factors.
  for (int i = 0; i < 3; ++i) {
    const double expected_std = sigma[i] * std::sqrt(T * t);
    EXPECT_NEAR(closed["white_drift_std_at_end_W_m"][i].number, expected_std, 1e-5 * expected_std) << i;
    EXPECT_LT(std::fabs(white["drift_at_end_W_m"][i].number), 4.0 * expected_std) << i;
  }
  // The full model's error is R_WS (b0 t + xi0 t^2 / 2) (b0, xi0 the drawn values from the DVL state, as
  // printed) plus the white random walk and the integrated bias walk K W, of variance
  // sigma_i^2 T t + K^2 t^3 / 3 per axis: within 4 of those sigma (seed 1: 0.67, 0.79, 0.10).
  const double K = 1e-5;
  const Json& b0 = closed["drawn_turn_on_bias_S_m_s"];
  const Json& xi0 = closed["drawn_drift_rate_S_m_s2"];
  for (int i = 0; i < 3; ++i) {
    double expected = 0.0;
    for (int j = 0; j < 3; ++j) expected += R_WS[i][j] * (b0[j].number * t + xi0[j].number * t * t / 2.0);
    const double spread = std::sqrt(sigma[i] * sigma[i] * T * t + K * K * t * t * t / 3.0);
    EXPECT_LT(std::fabs(full["drift_at_end_W_m"][i].number - expected), 4.0 * spread) << i;
  }
  // The drawn turn-on bias is not negligible against the noise (otherwise the check above would hold
  // for a model without bias too): |b0| t is 5.1 times the white-noise RMS magnitude here.
  double b0_norm = 0.0;
  for (int j = 0; j < 3; ++j) b0_norm += b0[j].number * b0[j].number;
  EXPECT_GT(std::sqrt(b0_norm) * t, 4.0 * closed["white_drift_rms_at_end_m"].number);

  // Monotonic growth with the bias model, sampled every minute (16 samples from t = 0); the white-only
  // drift of the same seed is not monotonic (it dips at 3 min), so the check tells the two apart.
  const Json& samples = full["drift_samples_m"];
  ASSERT_EQ(samples.array.size(), 16u);
  for (std::size_t j = 1; j < samples.array.size(); ++j) {
    EXPECT_GT(samples[j].number, samples[j - 1].number) << j;
  }
  EXPECT_TRUE(full["monotonic"].boolean);
  EXPECT_FALSE(white["monotonic"].boolean);
  // The runs share their per-beam noise: their difference is the integrated bias to rounding.
  EXPECT_LT(json["runs_difference_minus_integrated_bias_max_m"].number, 1e-8);
  EXPECT_TRUE(json["pass"]["all"].boolean);

  // Same seed twice: identical record and figures; another seed: a different record.
  const RunResult again = run(HADAL_VALIDATE_DVL, args + " --out " + dir_ + "/again");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(read_file(dir_ + "/again/dvl_record.csv"), read_file(dir_ + "/dvl_record.csv"));
  EXPECT_EQ(read_file(dir_ + "/again/dvl_parameters.json"), read_file(dir_ + "/dvl_parameters.json"));
  EXPECT_EQ(without_timing_and_paths(again.out), without_timing_and_paths(r.out));
  const RunResult other = run(HADAL_VALIDATE_DVL, args + " --seed 2 --no-record --out " + dir_ + "/other");
  ASSERT_EQ(other.exit_code, 0) << other.err;
  EXPECT_FALSE(fs::exists(dir_ + "/other/dvl_record.csv"));
  EXPECT_NE(without_timing_and_paths(other.out), without_timing_and_paths(r.out));
  EXPECT_EQ(parse(other.out)["seed"].number, 2.0);
}

// The camera figure (its whole run, ~1 s): six 480 x 360 panels in one PNG; backscatter, the mean of a
// patch looking into open water beside the target, grows with the scattering coefficient (panel 6 vs 5
// vs 1: b = 0.4, 0.05, 0.01 /m), and the shallow panel is lit by daylight alone.
TEST_F(ValidationCliTest, CameraFigure) {
  const RunResult r = run(HADAL_VALIDATE_CAMERA, "--out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  ASSERT_TRUE(std::filesystem::exists(dir_ + "/camera_figure.png"));
  const Json& panels = json["panels"];
  ASSERT_EQ(panels.array.size(), 6u);
  const auto top = [&](std::size_t p) { return panels[p]["open_water_mean_counts"][1].number; };  // green
  EXPECT_GT(top(5), 2.0 * top(4));
  EXPECT_GT(top(4), top(0));
  EXPECT_GT(panels[3]["mean_counts"][2].number, 10.0);  // shallow: daylight, blue
  EXPECT_EQ(run(HADAL_VALIDATE_CAMERA, "--frames 3").exit_code, 2);
}

// The sonar figure over 4 s of the survey scenario: every sonar pings (5 Hz: 20 pings), the multibeam's
// soundings on the seabed lie on it (median within 5 cm: the 1.25 cm bins, speckle and the 2 m grid of the
// generated seabed's triangles, whose facets the rays see and the height interpolates alike), and the PNG
// is written. A bad --seconds is a usage error.
TEST_F(ValidationCliTest, SonarFigure) {
  const RunResult r = run(HADAL_VALIDATE_SONAR, "--seconds 4 --out " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json json = parse(r.out);
  ASSERT_TRUE(std::filesystem::exists(dir_ + "/sonar_figure.png"));
  EXPECT_EQ(json["fls_pings"].number, 20.0);
  EXPECT_EQ(json["multibeam_pings"].number, 20.0);
  EXPECT_EQ(json["sidescan_pings"].number, 20.0);
  EXPECT_GT(json["soundings_on_seabed"].number, 20.0 * 200.0);
  EXPECT_LT(json["seabed_residual_median_m"].number, 0.05);
  EXPECT_EQ(run(HADAL_VALIDATE_SONAR, "--seconds 0").exit_code, 2);
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
  EXPECT_EQ(run(HADAL_VALIDATE_DVL, "--hours 0").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_DVL, "--hours 0.001").exit_code, 2);  // 18 pings
  EXPECT_EQ(run(HADAL_VALIDATE_DVL, "--interval 0").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_DVL, "--hours 0.25 --interval 20").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_DVL, "--seed -1").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_DVL, "--seed 1.5").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_DVL, "--bogus").exit_code, 2);
  // A scenario without a DVL.
  EXPECT_EQ(run(HADAL_VALIDATE_DVL, "--hours 0.25 --scenario " HADAL_VALIDATION_SCENARIOS "/imu_static.yaml --out " +
                                        dir_)
                .exit_code,
            1);
}

}  // namespace
