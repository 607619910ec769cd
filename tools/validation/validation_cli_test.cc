// Smoke runs of the validation commands as users run them, shortened (a 30 m descent, a 200 m leg;
// under a second each): exit code, outputs written, and the printed JSON against the closed forms
// the tools print themselves.
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

TEST_F(ValidationCliTest, UsageErrors) {
  EXPECT_EQ(run(HADAL_VALIDATE_LANDER, "--depth -5").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_LANDER, "--segments 7").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_CORIOLIS, "--bogus 1").exit_code, 2);
  EXPECT_EQ(run(HADAL_VALIDATE_CORIOLIS, "--scenario " + dir_ + "/missing.yaml --out " + dir_).exit_code, 1);
}

}  // namespace
