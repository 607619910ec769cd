// hadal-validate-sonar: the sonar figure (docs/ARCHITECTURE.md, "Sonars"): a survey line run through
// hadal::Simulation, the three sonars of its first vehicle that has them in one PNG:
//   left    the forward-looking sonar's last ping as a fan (beams at their azimuths, ranges outwards)
//   middle  the multibeam's swath: every ping's soundings (p_WS + r R_WS axis_k, the beam's axis at the
//           detected range) gridded in x_W, y_W at 0.25 m and coloured by depth
//   right   the side-scan waterfall: one row per ping, port reversed on the left, starboard on the right
// The soundings are checked against the seabed they sounded (the scenario's seabed mesh under each
// sounding; soundings on a vehicle, the targets, are counted apart): the JSON summary gives the pings of
// each sonar, the soundings and the median and 95th percentile of |z_sounding - h(x, y)| over the seabed.
// Captures are delivered without latency here (latency_s 0 on the model's copy), so that each ping's
// pose is the state's when it is read.
//   hadal-validate-sonar [--seconds 60] [--scenario PATH] [--out DIR]   (default configs/scenarios/
//   sonar_survey.yaml, validation_out/sonar)
// Writes DIR/sonar_figure.png; prints one JSON object. Exit 0, 1 when the scenario does not load, has no
// sonars, or DIR cannot be written, 2 on a usage error.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/core/simulation.h"
#include "hadal/geometry/seabed_height.h"
#include "hadal/sensors/fls_sensor.h"
#include "hadal/sensors/multibeam_sensor.h"
#include "hadal/sensors/sidescan_sensor.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using validation::json_rounded;

constexpr const char* kTool = "hadal-validate-sonar";
constexpr const char* kUsage =
    "usage: hadal-validate-sonar [--seconds S] [--scenario PATH] [--out DIR]\n"
    "  --seconds S      simulated time to run (default 60)\n"
    "  --scenario PATH  a scenario whose vehicle carries an fls, a multibeam and a sidescan\n"
    "                   (default configs/scenarios/sonar_survey.yaml)\n"
    "  --out DIR        output directory (default validation_out/sonar)\n"
    "Runs the survey and writes DIR/sonar_figure.png (FLS fan, multibeam swath, side-scan waterfall); prints\n"
    "a JSON summary.\n";

constexpr int kPanelHeight = 600;

// Where each sonar kind sits: (vehicle, sensor) or -1.
struct Mounts {
  int vehicle = -1;
  int fls = -1, multibeam = -1, sidescan = -1;
};

Mounts find_sonars(const Model& model) {
  for (std::size_t v = 0; v < model.vehicles.size(); ++v) {
    Mounts m;
    m.vehicle = static_cast<int>(v);
    const auto& sensors = model.vehicles[v].sensors;
    for (std::size_t s = 0; s < sensors.size(); ++s) {
      const std::string_view type = sensors[s].type();
      if (type == sensors::FlsSensor::kType && m.fls < 0) m.fls = static_cast<int>(s);
      if (type == sensors::MultibeamSensor::kType && m.multibeam < 0) m.multibeam = static_cast<int>(s);
      if (type == sensors::SidescanSensor::kType && m.sidescan < 0) m.sidescan = static_cast<int>(s);
    }
    if (m.fls >= 0 || m.multibeam >= 0 || m.sidescan >= 0) return m;
  }
  return {};
}

// A sample of an image (uint8 as is; float32 as its level over the display window) as a grey level 0..255.
double grey(const sensors::SonarImageEncoding& encoding, const std::vector<std::uint8_t>& data, std::size_t i) {
  if (!encoding.float32) return data[i];
  float v = 0.0f;
  std::memcpy(&v, &data[4 * i], sizeof v);
  if (!(v > 0.0f)) return 0.0;
  const double level = 10.0 * std::log10(static_cast<double>(v));
  return std::clamp(255.0 * (level - encoding.display_min_db) / (encoding.display_max_db - encoding.display_min_db), 0.0, 255.0);
}

// The forward-looking sonar's ping as a fan: pixel (u, v) at x = across [m], y = ahead [m]; each pixel takes
// the sample of the beam and bin it falls in (nearest), black outside the fan.
cv::Mat fan_panel(const sensors::FlsSensor::Spec& spec, const sensors::FlsSensor::State& state) {
  const double max_range = spec.acoustics.max_range, half = 0.5 * spec.fov;
  const double width_m = 2.0 * max_range * std::sin(std::min(half, kPi / 2.0));
  const double scale = (kPanelHeight - 20) / max_range;  // px per m
  const int width = std::max(200, static_cast<int>(width_m * scale) + 20);
  cv::Mat panel(kPanelHeight, width, CV_8UC1, cv::Scalar(0));
  const std::size_t beams = static_cast<std::size_t>(spec.beams), size = spec.encoding.bytes_per_sample();
  if (state.image.size() != beams * static_cast<std::size_t>(spec.acoustics.bins) * size) return panel;
  for (int v = 0; v < kPanelHeight; ++v) {
    for (int u = 0; u < width; ++u) {
      const double x = (u - 0.5 * width) / scale, y = (kPanelHeight - 10 - v) / scale;
      const double r = std::hypot(x, y), azimuth = std::atan2(-x, y);  // positive to port (left)
      if (std::abs(azimuth) > half) continue;
      const int bin = spec.ping->bin_of(r);
      if (bin < 0) continue;
      const int beam = std::clamp(static_cast<int>(std::floor((azimuth + half) / spec.fov * spec.beams)), 0, spec.beams - 1);
      // Beam 0 is the most starboard (negative azimuth): on the right of the image.
      panel.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(grey(spec.encoding, state.image, (static_cast<std::size_t>(bin) * beams + beam)));
    }
  }
  return panel;
}

struct Sounding {
  Eigen::Vector3d p_W;
  bool on_seabed = true;
};

}  // namespace

int main(int argc, char** argv) {
  std::string out_dir = "validation_out/sonar";
  std::string scenario = std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/sonar_survey.yaml";
  double seconds = 60.0;
  if (const auto status = validation::parse_command_line(
          argc, argv, kTool, kUsage, {"--out", "--scenario", "--seconds"}, {},
          [&](const std::string& option, const std::string& value) -> std::string {
            if (option == "--out") out_dir = value;
            if (option == "--scenario") scenario = value;
            if (option == "--seconds") {
              double parsed = 0.0;
              if (!validation::parse_number(value, &parsed) || !(parsed > 0.0 && parsed <= 3600.0)) {
                return "--seconds must be in (0, 3600]";
              }
              seconds = parsed;
            }
            return std::string();
          })) {
    return *status;
  }
  std::optional<Model> loaded = validation::load_model(scenario, kTool);
  if (!loaded) return 1;
  Model model = std::move(*loaded);
  const Mounts mounts = find_sonars(model);
  if (mounts.vehicle < 0) {
    std::fprintf(stderr, "%s: %s: no vehicle carries a sonar (fls, multibeam or sidescan)\n", kTool, scenario.c_str());
    return 1;
  }
  if (const std::string error = validation::ensure_directory(out_dir); !error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }
  VehicleSpec& carrier = model.vehicles[static_cast<std::size_t>(mounts.vehicle)];
  for (SensorSpec& s : carrier.sensors) s.latency_s = 0.0;
  const std::shared_ptr<const geometry::TriangleMesh> seabed_mesh = model.world.seabed.mesh;
  const geometry::SeabedHeight seabed =
      seabed_mesh ? geometry::SeabedHeight(*seabed_mesh, model.world.seabed.type != SeabedType::kMesh)
                  : geometry::SeabedHeight::plane(model.world.seabed.z);

  Simulation sim(model);
  sim.set_wait_for_captures(true);
  const auto v = static_cast<std::size_t>(mounts.vehicle);
  const auto sensor_pose = [&](int s) {
    const SensorSpec& spec = carrier.sensors[static_cast<std::size_t>(s)];
    return sim.state().vehicles[v].body.X_WB * carrier.links[static_cast<std::size_t>(spec.link_index)].X_BL * spec.X_LS;
  };
  std::vector<std::uint64_t> seen(carrier.sensors.size(), 0);
  std::vector<Sounding> soundings;
  std::vector<std::vector<double>> waterfall;  // rows of port (reversed) + starboard grey levels
  int fls_pings = 0, multibeam_pings = 0, sidescan_pings = 0;
  const auto steps = static_cast<std::uint64_t>(std::llround(seconds * model.world.physics_rate_hz));
  for (std::uint64_t n = 0; n < steps; ++n) {
    sim.step();
    const VehicleState& state = sim.state().vehicles[v];
    const auto fresh = [&](int s) {
      if (s < 0) return false;
      const std::uint64_t samples = state.sensors[static_cast<std::size_t>(s)].samples;
      const bool is_new = samples != seen[static_cast<std::size_t>(s)];
      seen[static_cast<std::size_t>(s)] = samples;
      return is_new;
    };
    if (fresh(mounts.fls)) ++fls_pings;
    if (fresh(mounts.multibeam)) {
      ++multibeam_pings;
      const auto& spec = spec_of<sensors::MultibeamSensor>(carrier.sensors[static_cast<std::size_t>(mounts.multibeam)]);
      const auto& mb = state_of<sensors::MultibeamSensor>(state.sensors[static_cast<std::size_t>(mounts.multibeam)]);
      const Eigen::Isometry3d X_WS = sensor_pose(mounts.multibeam);
      for (int k = 0; k < spec.beams; ++k) {
        const double r = mb.last.range_m[static_cast<std::size_t>(k)];
        if (!std::isfinite(r)) continue;
        Sounding sounding;
        sounding.p_W = X_WS * (r * spec.ping->beams[static_cast<std::size_t>(k)].axis_S);
        geometry::SeabedHeight::Sample h;
        sounding.on_seabed = seabed.sample(sounding.p_W.x(), sounding.p_W.y(), &h) && sounding.p_W.z() < h.height + 0.3;
        soundings.push_back(sounding);
      }
    }
    if (fresh(mounts.sidescan)) {
      ++sidescan_pings;
      const auto& spec = spec_of<sensors::SidescanSensor>(carrier.sensors[static_cast<std::size_t>(mounts.sidescan)]);
      const auto& ss = state_of<sensors::SidescanSensor>(state.sensors[static_cast<std::size_t>(mounts.sidescan)]);
      const std::size_t bins = static_cast<std::size_t>(spec.acoustics.bins);
      std::vector<double> row(2 * bins, 0.0);
      if (ss.port.size() == bins * spec.encoding.bytes_per_sample()) {
        for (std::size_t i = 0; i < bins; ++i) {
          row[bins - 1 - i] = grey(spec.encoding, ss.port, i);
          row[bins + i] = grey(spec.encoding, ss.starboard, i);
        }
      }
      waterfall.push_back(std::move(row));
    }
  }

  // Left: the fan.
  cv::Mat left(kPanelHeight, 200, CV_8UC1, cv::Scalar(0));
  if (mounts.fls >= 0) {
    left = fan_panel(spec_of<sensors::FlsSensor>(carrier.sensors[static_cast<std::size_t>(mounts.fls)]),
                     state_of<sensors::FlsSensor>(sim.state().vehicles[v].sensors[static_cast<std::size_t>(mounts.fls)]));
  }
  cv::Mat left_bgr;
  cv::cvtColor(left, left_bgr, cv::COLOR_GRAY2BGR);
  // Middle: the soundings' depths on a 0.25 m grid, x_W upwards, y_W to the left (looking down, north up).
  std::vector<double> residuals;
  double x_min = 1e300, x_max = -1e300, y_min = 1e300, y_max = -1e300, z_min = 1e300, z_max = -1e300;
  for (const Sounding& s : soundings) {
    x_min = std::min(x_min, s.p_W.x());
    x_max = std::max(x_max, s.p_W.x());
    y_min = std::min(y_min, s.p_W.y());
    y_max = std::max(y_max, s.p_W.y());
    z_min = std::min(z_min, s.p_W.z());
    z_max = std::max(z_max, s.p_W.z());
    geometry::SeabedHeight::Sample h;
    if (s.on_seabed && seabed.sample(s.p_W.x(), s.p_W.y(), &h)) residuals.push_back(std::abs(s.p_W.z() - h.height));
  }
  cv::Mat middle_bgr(kPanelHeight, 300, CV_8UC3, cv::Scalar(0, 0, 0));
  if (!soundings.empty()) {
    const double cell = 0.25;
    const int rows = std::max(1, static_cast<int>((x_max - x_min) / cell) + 1), cols = std::max(1, static_cast<int>((y_max - y_min) / cell) + 1);
    cv::Mat depth(rows, cols, CV_8UC1, cv::Scalar(0)), mask(rows, cols, CV_8UC1, cv::Scalar(0));
    const double span = std::max(z_max - z_min, 1e-3);
    for (const Sounding& s : soundings) {
      const int row = rows - 1 - static_cast<int>((s.p_W.x() - x_min) / cell), col = cols - 1 - static_cast<int>((s.p_W.y() - y_min) / cell);
      depth.at<std::uint8_t>(row, col) = static_cast<std::uint8_t>(1 + 254.0 * (s.p_W.z() - z_min) / span);
      mask.at<std::uint8_t>(row, col) = 255;
    }
    cv::Mat coloured;
    cv::applyColorMap(depth, coloured, cv::COLORMAP_JET);
    coloured.setTo(cv::Scalar(0, 0, 0), mask == 0);
    const double fit = std::min(static_cast<double>(kPanelHeight) / rows, 600.0 / cols);
    cv::resize(coloured, middle_bgr, cv::Size(std::max(1, static_cast<int>(cols * fit)), kPanelHeight), 0, 0, cv::INTER_NEAREST);
  }
  // Right: the waterfall, newest ping at the top, fitted into the panel.
  cv::Mat right_bgr(kPanelHeight, 300, CV_8UC3, cv::Scalar(0, 0, 0));
  if (!waterfall.empty()) {
    const int rows = static_cast<int>(waterfall.size()), cols = static_cast<int>(waterfall.front().size());
    cv::Mat grey_image(rows, cols, CV_8UC1);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) grey_image.at<std::uint8_t>(rows - 1 - r, c) = static_cast<std::uint8_t>(waterfall[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)]);
    }
    cv::Mat resized;
    cv::resize(grey_image, resized, cv::Size(600, kPanelHeight), 0, 0, cv::INTER_AREA);
    cv::cvtColor(resized, right_bgr, cv::COLOR_GRAY2BGR);
  }
  const auto label = [](cv::Mat& image, const std::string& text) {
    cv::putText(image, text, cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  };
  label(left_bgr, "forward-looking sonar (last ping)");
  label(middle_bgr, "multibeam swath, depth");
  label(right_bgr, "side-scan waterfall: port | starboard");
  cv::Mat figure;
  cv::hconcat(std::vector<cv::Mat>{left_bgr, middle_bgr, right_bgr}, figure);
  const std::string file = validation::join_path(out_dir, "sonar_figure.png");
  if (!cv::imwrite(file, figure)) {
    std::fprintf(stderr, "%s: cannot write %s\n", kTool, file.c_str());
    return 1;
  }
  std::sort(residuals.begin(), residuals.end());
  const auto percentile = [&](double p) {
    return residuals.empty() ? std::numeric_limits<double>::quiet_NaN()
                             : residuals[std::min(residuals.size() - 1, static_cast<std::size_t>(p * residuals.size()))];
  };
  std::printf(
      "{\"figure\": %s, \"seconds\": %s, \"fls_pings\": %d, \"multibeam_pings\": %d, \"sidescan_pings\": %d, "
      "\"soundings\": %zu, \"soundings_on_seabed\": %zu, \"seabed_residual_median_m\": %s, "
      "\"seabed_residual_p95_m\": %s}\n",
      validation::json_string(file).c_str(), json_rounded(seconds).c_str(), fls_pings, multibeam_pings, sidescan_pings,
      soundings.size(), residuals.size(), json_rounded(percentile(0.5)).c_str(), json_rounded(percentile(0.95)).c_str());
  return 0;
}
