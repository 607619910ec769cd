// Integration test of hadal-geomag as users run it: one JSON object per call, checked against NOAA's
// WMM2025 test values (the full 12-point table is tested on the library in geomagnetic_test.cc), or the
// documented exit codes with nothing on stdout.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "cli_test_support.h"

namespace {

using hadal::test::Json;
using hadal::test::RunResult;

class GeomagCliTest : public hadal::test::CliTest {
 protected:
  RunResult geomag(const std::string& args) const { return run(std::string(HADAL_GEOMAG) + " " + args); }
};

// Rows 3 and 10 of WMM2025_TEST_VALUE_TABLE_FOR_REPORT.txt; tolerances as in the issue (0.1 nT, 0.01 deg,
// 0.1 nT/yr; I_dot, D_dot printed to 0.01 deg/yr: half a unit).
TEST_F(GeomagCliTest, PrintsTheOfficialTestValues) {
  const RunResult r = geomag("-80 240 0 2025.0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const Json j = parse(r.out);
  EXPECT_EQ(j["model"].string, "WMM-2025");
  EXPECT_EQ(j["latitude_deg"].number, -80.0);
  EXPECT_EQ(j["longitude_deg"].number, 240.0);
  EXPECT_EQ(j["height_km"].number, 0.0);
  EXPECT_EQ(j["decimal_year"].number, 2025.0);
  EXPECT_NEAR(j["X_nT"].number, 6117.5, 0.1);
  EXPECT_NEAR(j["Y_nT"].number, 15751.9, 0.1);
  EXPECT_NEAR(j["Z_nT"].number, -52022.5, 0.1);
  EXPECT_NEAR(j["H_nT"].number, 16898.1, 0.1);
  EXPECT_NEAR(j["F_nT"].number, 54698.2, 0.1);
  EXPECT_NEAR(j["I_deg"].number, -72.00, 0.01);
  EXPECT_NEAR(j["D_deg"].number, 68.78, 0.01);
  EXPECT_NEAR(j["Xdot_nT_per_yr"].number, 33.3, 0.1);
  EXPECT_NEAR(j["Ydot_nT_per_yr"].number, -8.6, 0.1);
  EXPECT_NEAR(j["Zdot_nT_per_yr"].number, 95.5, 0.1);
  EXPECT_NEAR(j["Hdot_nT_per_yr"].number, 4.0, 0.1);
  EXPECT_NEAR(j["Fdot_nT_per_yr"].number, -89.6, 0.1);
  EXPECT_NEAR(j["Idot_deg_per_yr"].number, 0.03, 0.005 + 1e-9);
  EXPECT_NEAR(j["Ddot_deg_per_yr"].number, -0.12, 0.005 + 1e-9);
  EXPECT_EQ(j.object.size(), 19u);

  const Json k = parse(geomag("80 0 100 2027.5").out);
  EXPECT_NEAR(k["X_nT"].number, 6196.7, 0.1);
  EXPECT_NEAR(k["Y_nT"].number, 233.8, 0.1);
  EXPECT_NEAR(k["Z_nT"].number, 52670.5, 0.1);
  EXPECT_NEAR(k["D_deg"].number, 2.16, 0.01);
  EXPECT_NEAR(k["Ddot_deg_per_yr"].number, 0.52, 0.005 + 1e-9);
}

TEST_F(GeomagCliTest, CofOverride) {
  const std::string path = dir_ + "/dipole.COF";
  std::ofstream(path) << "2025.0 DIPOLE\n1 0 -30000 0 0 0\n1 1 0 0 0 0\n999999999\n";
  // At the equator at r = 6371.2 km (height 6371.2 - 6378.137 km): X = -g10 = 30000 nT exactly.
  const RunResult r = geomag("0 0 -6.937 2026 --cof " + path);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json j = parse(r.out);
  EXPECT_EQ(j["model"].string, "DIPOLE");
  EXPECT_NEAR(j["X_nT"].number, 30000.0, 1e-6);
  EXPECT_NEAR(j["Z_nT"].number, 0.0, 1e-9);
}

TEST_F(GeomagCliTest, BadCoefficientFileExitsOneWithFileLine) {
  const std::string path = dir_ + "/bad.COF";
  std::ofstream(path) << "2025.0 WMM-2025\n1 0 -30000 0 0\n";
  RunResult r = geomag("0 0 0 2026 --cof " + path);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, path + ":2: error: expected 'n m g h g_dot h_dot' (6 numbers), got '1 0 -30000 0 0'\n");

  r = geomag("0 0 0 2026 --cof " + dir_ + "/missing.COF");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, dir_ + "/missing.COF: error: cannot open geomagnetic coefficient file: No such file or directory\n");
}

TEST_F(GeomagCliTest, UsageErrorsExitTwo) {
  for (const std::string args : {"", "0 0 0", "0 0 0 2026 1", "x 0 0 2026", "0 0 0 2026y", "91 0 0 2026",
                                 "0 0 0 2024.5", "0 0 0 2030.5", "0 0 0 2026 --cof", "0 0 0 2026 --bogus",
                                 "0 0 nan 2026"}) {
    const RunResult r = geomag(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_NE(r.err.find("usage: hadal-geomag"), std::string::npos) << args;
  }
  const RunResult r = geomag("0 0 0 2031");
  EXPECT_NE(r.err.find("hadal-geomag: DECIMAL_YEAR 2031 is outside WMM-2025's validity 2025..2030"),
            std::string::npos)
      << r.err;
  const RunResult help = geomag("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("usage: hadal-geomag"), std::string::npos);
}

}  // namespace
