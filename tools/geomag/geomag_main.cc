// hadal-geomag: the World Magnetic Model at one point, like NOAA's point calculator, as one JSON object:
//   {"model": "WMM-2025", "latitude_deg", "longitude_deg", "height_km", "decimal_year",
//    "X_nT", "Y_nT", "Z_nT", "H_nT", "F_nT", "I_deg", "D_deg",
//    "Xdot_nT_per_yr", "Ydot_nT_per_yr", "Zdot_nT_per_yr", "Hdot_nT_per_yr", "Fdot_nT_per_yr",
//    "Idot_deg_per_yr", "Ddot_deg_per_yr"}
// X north, Y east, Z down (local geodetic frame), I inclination (down positive), D declination (east of
// true north); numbers at full precision (NaN -> null). Model: hadal/sensors/geomagnetic.h.
//   hadal-geomag LAT_DEG LON_DEG HEIGHT_KM DECIMAL_YEAR [--cof PATH]
// LAT_DEG geodetic latitude in [-90, 90], LON_DEG longitude (east positive), HEIGHT_KM above the WGS84
// ellipsoid (negative below it), DECIMAL_YEAR within the model's five-year span (2025.0 - 2030.0).
// Exit status: 0 success; 1 the coefficient file does not load (file:line error on stderr); 2 usage error
// (nothing on stdout).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "cli_args.h"
#include "hadal/sensors/geomagnetic.h"
#include "json_number.h"
#include "parse_number.h"
#include "hadal/core/units.h"

namespace {

using hadal::tools::json_number;
using hadal::tools::parse_number;

constexpr const char* kUsage =
    "usage: hadal-geomag LAT_DEG LON_DEG HEIGHT_KM DECIMAL_YEAR [--cof PATH]\n"
    "  LAT_DEG       geodetic latitude [deg], -90..90\n"
    "  LON_DEG       longitude [deg], east positive\n"
    "  HEIGHT_KM     height above the WGS84 ellipsoid [km] (negative below it)\n"
    "  DECIMAL_YEAR  e.g. 2027.5, within the model's validity (WMM2025: 2025.0..2030.0)\n"
    "  --cof PATH    coefficient file (default: hadald's WMM2025.COF; $HADAL_DATA_DIR overrides its folder)\n"
    "Prints X, Y, Z, H, F [nT], I, D [deg] and their yearly rates as one JSON object.\n";

// JSON string body: the model name comes from the file's header.
std::string json_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string cof_path = hadal::sensors::GeomagneticModel::default_cof_path();
  std::vector<std::string> positional;
  hadal::tools::CommandLine command_line("hadal-geomag", kUsage);
  command_line.option_syntax(hadal::tools::OptionSyntax::kDashNotNumber)
      .text("--cof", &cof_path)
      .positional([&](const std::string& arg) {
        positional.push_back(arg);
        return std::string();
      })
      .after_help([&] { std::printf("Default coefficient file here: %s\n", cof_path.c_str()); });
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (positional.size() != 4) {
    return command_line.usage_error("expected 4 arguments LAT_DEG LON_DEG HEIGHT_KM DECIMAL_YEAR (got " +
                                    std::to_string(positional.size()) + ")");
  }
  const char* names[4] = {"LAT_DEG", "LON_DEG", "HEIGHT_KM", "DECIMAL_YEAR"};
  double values[4];
  for (int k = 0; k < 4; ++k) {
    if (!parse_number(positional[k], &values[k])) {
      return command_line.usage_error(std::string(names[k]) + " is not a number: '" + positional[k] + "'");
    }
  }
  const double lat_deg = values[0], lon_deg = values[1], height_km = values[2], year = values[3];
  if (std::abs(lat_deg) > 90.0) {
    return command_line.usage_error("LAT_DEG must be in [-90, 90] (got " + positional[0] + ")");
  }

  hadal::sensors::GeomagneticModel model;
  try {
    model = hadal::sensors::GeomagneticModel::load_cof(cof_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  if (year < model.valid_from_year() || year > model.valid_until_year()) {
    return command_line.usage_error("DECIMAL_YEAR " + positional[3] + " is outside " + model.name() +
                                    "'s validity " + json_number(model.valid_from_year()) + ".." +
                                    json_number(model.valid_until_year()));
  }

  constexpr double kDeg = hadal::kDegToRad;
  const hadal::sensors::GeomagneticElements e =
      model.field(lat_deg * kDeg, lon_deg * kDeg, height_km * 1e3, year);
  std::printf(
      "{\"model\": \"%s\", \"latitude_deg\": %s, \"longitude_deg\": %s, \"height_km\": %s, \"decimal_year\": %s, "
      "\"X_nT\": %s, \"Y_nT\": %s, \"Z_nT\": %s, \"H_nT\": %s, \"F_nT\": %s, \"I_deg\": %s, \"D_deg\": %s, "
      "\"Xdot_nT_per_yr\": %s, \"Ydot_nT_per_yr\": %s, \"Zdot_nT_per_yr\": %s, \"Hdot_nT_per_yr\": %s, "
      "\"Fdot_nT_per_yr\": %s, \"Idot_deg_per_yr\": %s, \"Ddot_deg_per_yr\": %s}\n",
      json_escape(model.name()).c_str(), json_number(lat_deg).c_str(), json_number(lon_deg).c_str(),
      json_number(height_km).c_str(), json_number(year).c_str(), json_number(e.x_north_nT).c_str(),
      json_number(e.y_east_nT).c_str(), json_number(e.z_down_nT).c_str(), json_number(e.h_horizontal_nT).c_str(),
      json_number(e.f_total_nT).c_str(), json_number(hadal::to_degrees(e.inclination_rad)).c_str(),
      json_number(hadal::to_degrees(e.declination_rad)).c_str(), json_number(e.x_north_rate_nT_per_yr).c_str(),
      json_number(e.y_east_rate_nT_per_yr).c_str(), json_number(e.z_down_rate_nT_per_yr).c_str(),
      json_number(e.h_horizontal_rate_nT_per_yr).c_str(), json_number(e.f_total_rate_nT_per_yr).c_str(),
      json_number(hadal::to_degrees(e.inclination_rate_rad_per_yr)).c_str(),
      json_number(hadal::to_degrees(e.declination_rate_rad_per_yr)).c_str());
  return 0;
}
