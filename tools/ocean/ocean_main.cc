// hadal-ocean: prints the water column a scenario defines (world.water, hadal/physics/ocean.h), one JSON
// object per requested depth, one per line:
//   {"depth": d [m], "z": z_W [m], "pressure": absolute [Pa], "density": [kg/m^3],
//    "temperature_degc": ITS-90, "salinity": practical salinity, "sound_speed": [m/s] (UNESCO /
//    Chen-Millero), "current": [vx, vy, vz] in W [m/s] at (0, 0, z) and time T, "kappa": 1 - p/K}
// and with --frequency F also "absorption_db_per_m" (Francois–Garrison at F [dB/m]), with --bandwidth B as well
// "noise_level_db" (world.acoustics' Wenz ambient noise in the band [F - B/2, F + B/2], dB re 1 uPa^2): what an
// acoustic modem's or positioning sensor's SNR is worked out from (sensors/acoustic_channel.h).
//   hadal-ocean SCENARIO.yaml [--depths D1,D2,...] [--time T] [--frequency F [--bandwidth B]]
// Exit status: 0 success; 1 the scenario does not load (its file:line:col errors on stderr, nothing on
// stdout); 2 usage error.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "cli_args.h"
#include "json_number.h"
#include "parse_number.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/physics/ocean.h"
#include "hadal/sensors/acoustic_channel.h"

namespace {

using hadal::tools::json_number;
using hadal::tools::parse_number;

constexpr const char* kUsage =
    "usage: hadal-ocean SCENARIO.yaml [--depths D1,D2,...] [--time T] [--frequency F [--bandwidth B]]\n"
    "  --depths  depths below the water surface [m], comma-separated (default\n"
    "            0,10,100,500,1000,2000,4000,6000,11000)\n"
    "  --time T  simulation time [s] at which the current is sampled (default 0)\n"
    "  --frequency F  also the sound absorption at F [Hz] (dB/m)\n"
    "  --bandwidth B  with --frequency: also the ambient noise level in the band of B [Hz] (dB re 1 uPa^2)\n"
    "Prints one JSON object per depth (SI units; current in the world frame at (0, 0, z)).\n";

// "D1,D2,..." into *depths: "" when every item is a number, else the usage error.
std::string read_depths(const std::string& value, std::vector<double>* depths) {
  depths->clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = value.find(',', start);
    const std::string item = value.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    double depth = 0.0;
    if (!parse_number(item, &depth)) return "--depths: not a number: '" + item + "'";
    depths->push_back(depth);
    if (comma == std::string::npos) return "";
    start = comma + 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  using hadal::tools::NumberRange;
  std::string scenario;
  std::vector<double> depths = {0, 10, 100, 500, 1000, 2000, 4000, 6000, 11000};
  double time = 0.0, frequency_hz = 0.0, bandwidth_hz = 0.0;
  hadal::tools::CommandLine command_line("hadal-ocean", kUsage);
  command_line.option("--depths", [&](const std::string& value) { return read_depths(value, &depths); })
      .number("--time", &time, NumberRange::at_least(0.0))
      .number("--frequency", &frequency_hz, NumberRange::at_least(1.0))
      .number("--bandwidth", &bandwidth_hz, NumberRange::at_least(1.0))
      .one_positional(&scenario, "more than one scenario file");
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (scenario.empty()) return command_line.usage_error("missing SCENARIO.yaml");
  if (bandwidth_hz > 0.0 && frequency_hz == 0.0) return command_line.usage_error("--bandwidth needs --frequency");
  if (bandwidth_hz >= 2.0 * frequency_hz && bandwidth_hz > 0.0) {
    return command_line.usage_error("--bandwidth must be below twice --frequency");
  }

  const hadal::config::LoadResult loaded = hadal::config::load_scenario_file(scenario);
  for (const auto& warning : loaded.warnings) std::fprintf(stderr, "%s\n", warning.format().c_str());
  if (!loaded.model) {
    for (const auto& error : loaded.errors) std::fprintf(stderr, "%s\n", error.format().c_str());
    return 1;
  }
  const hadal::physics::Ocean ocean(loaded.model->world);
  for (const double d : depths) {
    const double z = ocean.surface_z() - d;
    const Eigen::Vector3d v_W = ocean.current_W(Eigen::Vector3d(0.0, 0.0, z), time);
    std::printf(
        "{\"depth\": %s, \"z\": %s, \"pressure\": %s, \"density\": %s, \"temperature_degc\": %s, "
        "\"salinity\": %s, \"sound_speed\": %s, \"current\": [%s, %s, %s], \"kappa\": %s",
        json_number(d).c_str(), json_number(z).c_str(), json_number(ocean.pressure(d)).c_str(),
        json_number(ocean.density(d)).c_str(), json_number(ocean.temperature(d)).c_str(),
        json_number(ocean.salinity(d)).c_str(), json_number(ocean.sound_speed(d)).c_str(),
        json_number(v_W.x()).c_str(), json_number(v_W.y()).c_str(), json_number(v_W.z()).c_str(),
        json_number(ocean.kappa(d)).c_str());
    if (frequency_hz > 0.0) {
      std::printf(", \"absorption_db_per_m\": %s", json_number(ocean.sound_absorption_db_per_m(d, frequency_hz)).c_str());
    }
    if (bandwidth_hz > 0.0) {
      std::printf(", \"noise_level_db\": %s",
                  json_number(hadal::sensors::ambient_noise_level_db(frequency_hz, bandwidth_hz,
                                                                     loaded.model->world.acoustics.ambient_noise))
                      .c_str());
    }
    std::printf("}\n");
  }
  return 0;
}
