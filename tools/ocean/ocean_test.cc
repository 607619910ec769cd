// Integration test of hadal-ocean as users run it: a scenario file in, one JSON object per depth out
// (parsed here and checked against the closed forms), or the documented exit codes with nothing on stdout.
#include <gtest/gtest.h>

#include "cli_test_support.h"
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using hadal::test::Json;
using hadal::test::JsonParser;
using hadal::test::RunResult;

class OceanCliTest : public hadal::test::CliTest {
 protected:
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path) << text;
    return path;
  }

  RunResult ocean(const std::string& args) const { return run(std::string(HADAL_OCEAN) + " " + args); }

  static std::vector<Json> parse_lines(const std::string& out) {
    std::vector<Json> lines;
    std::istringstream stream(out);
    for (std::string line; std::getline(stream, line);) lines.push_back(parse(line));
    return lines;
  }
};

constexpr const char* kVehicles = R"(vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30, inertia: {ixx: 1, iyy: 1, izz: 1}}
)";

TEST_F(OceanCliTest, PrintsTheRampWaterColumn) {
  const std::string scenario = write("ramp.yaml", std::string(R"(world:
  gravity: [0, 0, -9.81]
  water:
    surface_z: 5
    density_model: ramp
    current:
      uniform: [0.2, 0, 0]
      shear: {surface: [0, 0.4, 0], decay_depth: 100}
)") + kVehicles);
  const RunResult r = ocean(scenario + " --depths 0,500,1000,6000 --time 12.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const std::vector<Json> lines = parse_lines(r.out);
  ASSERT_EQ(lines.size(), 4u);
  const double g = 9.81, p_atm = 101325.0, p1000 = p_atm + g * (1025000.0 + 1537.5);
  const double depth[] = {0, 500, 1000, 6000};
  const double pressure[] = {p_atm, p_atm + g * (1025.0 * 500 + 3.075 * 500 * 500 / 2000), p1000,
                             p1000 + g * 1028.075 * 5000};
  for (std::size_t i = 0; i < 4; ++i) {
    const Json& j = lines[i];
    EXPECT_EQ(j["depth"].number, depth[i]);
    EXPECT_EQ(j["z"].number, 5.0 - depth[i]);
    // Printed with round-trip precision: the closed form holds to 1e-9 relative (issue 4).
    EXPECT_NEAR(j["pressure"].number, pressure[i], 1e-9 * pressure[i]);
    EXPECT_NEAR(j["density"].number, 1025.0 + 3.075 * std::min(depth[i], 1000.0) / 1000.0, 1e-9);
    EXPECT_NEAR(j["kappa"].number, 1.0 - pressure[i] / 2.2e9, 1e-12);
    EXPECT_EQ(j["temperature_degc"].number, 4.0);
    EXPECT_EQ(j["salinity"].number, 35.0);
    // Chen-Millero at 4 degC, S = 35: ~1466 m/s at the surface, rising with pressure (~1.6 m/s per 100 m).
    EXPECT_GT(j["sound_speed"].number, 1460.0);
    EXPECT_LT(j["sound_speed"].number, 1570.0);
    ASSERT_EQ(j["current"].array.size(), 3u);
    EXPECT_NEAR(j["current"][0].number, 0.2, 1e-15);
    EXPECT_NEAR(j["current"][1].number, 0.4 * std::exp(-depth[i] / 100.0), 1e-15);
    EXPECT_EQ(j["current"][2].number, 0.0);
  }
  EXPECT_LT(lines[0]["sound_speed"].number, lines[3]["sound_speed"].number);
}

TEST_F(OceanCliTest, DefaultDepthsAndCtdWater) {
  const std::string scenario = write("ctd.yaml", std::string(R"(world:
  water:
    density_model: ctd
    ctd:
      - {depth: 0, temperature_degc: 20, salinity: 35}
      - {depth: 1000, temperature_degc: 4, salinity: 34.6}
)") + kVehicles);
  const RunResult r = ocean(scenario);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<Json> lines = parse_lines(r.out);
  ASSERT_EQ(lines.size(), 9u);
  EXPECT_EQ(lines[2]["depth"].number, 100.0);
  EXPECT_NEAR(lines[2]["temperature_degc"].number, 18.4, 1e-12);
  // EOS-80 at 20 degC, S = 35, p = 0: 1024.76 kg/m^3; compression makes the deep water denser.
  EXPECT_NEAR(lines[0]["density"].number, 1024.76, 0.01);
  EXPECT_GT(lines[8]["density"].number, lines[4]["density"].number);
}

// --frequency adds Francois–Garrison absorption at each depth (at 4 degC and S = 35, ~6 dB/km at 25 kHz near the
// surface, less under pressure, ~1.3 dB/km at 12 kHz); --bandwidth the ambient noise in the band, the same at every
// depth and higher in a wider band.
TEST_F(OceanCliTest, AcousticFiguresAtAFrequency) {
  const std::string scenario = write("acoustic.yaml", std::string(R"(world:
  water: {density_model: ramp}
  acoustics: {ambient_noise: {shipping: 0.5, wind_speed: 6.0}}
)") + kVehicles);
  const auto run = [&](const std::string& args) {
    const RunResult r = ocean(scenario + " --depths 0,3000 " + args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return parse_lines(r.out);
  };
  const std::vector<Json> plain = run("");
  ASSERT_EQ(plain.size(), 2u);
  EXPECT_EQ(plain[0].object.count("absorption_db_per_m"), 0u);
  const std::vector<Json> at25 = run("--frequency 25000 --bandwidth 4000");
  const std::vector<Json> at12 = run("--frequency 12000 --bandwidth 4000");
  const std::vector<Json> wide = run("--frequency 25000 --bandwidth 8000");
  ASSERT_EQ(at25.size(), 2u);
  EXPECT_GT(at25[0]["absorption_db_per_m"].number, 0.004);
  EXPECT_LT(at25[0]["absorption_db_per_m"].number, 0.009);
  EXPECT_LT(at25[1]["absorption_db_per_m"].number, at25[0]["absorption_db_per_m"].number);
  EXPECT_LT(at12[0]["absorption_db_per_m"].number, 0.5 * at25[0]["absorption_db_per_m"].number);
  EXPECT_EQ(at25[0]["noise_level_db"].number, at25[1]["noise_level_db"].number);
  EXPECT_GT(at25[0]["noise_level_db"].number, 50.0);
  EXPECT_LT(at25[0]["noise_level_db"].number, 90.0);
  EXPECT_NEAR(wide[0]["noise_level_db"].number - at25[0]["noise_level_db"].number, 3.0, 1.0);
}

TEST_F(OceanCliTest, ScenarioErrorsExitOneWithPositions) {
  const std::string scenario = write("bad.yaml", std::string(R"(world:
  water: {density_model: ramp, density: 1030}
)") + kVehicles);
  const RunResult r = ocean(scenario);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, scenario + ":2:32: error: world.water.density: key 'density' is not used by density_model "
                              "'ramp'\n");
}

TEST_F(OceanCliTest, UsageErrorsExitTwo) {
  for (const std::string args : {"", "a.yaml b.yaml", "s.yaml --depths 1,x", "s.yaml --time -1",
                                 "s.yaml --time", "s.yaml --bogus", "s.yaml --bandwidth 100",
                                 "s.yaml --frequency 1000 --bandwidth 3000"}) {
    const RunResult r = ocean(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_NE(r.err.find("usage: hadal-ocean"), std::string::npos) << args;
  }
}

}  // namespace
