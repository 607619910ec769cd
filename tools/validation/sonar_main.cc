// hadal-validate-sonar: the sonar figure (docs/ARCHITECTURE.md, "Sonars"): a survey line run through
// hadal::Simulation, the three sonars of its first vehicle that has them in one PNG:
//   left    a forward-looking sonar ping as a fan (beams at their azimuths, ranges outwards, rings every
//           10 m): the first ping at or after --fls-at (default 20 s: the survey's pipeline ~30 m ahead)
//   middle  the multibeam's swath: every ping's soundings (p_WS + r R_WS axis_k, the beam's axis at the
//           detected range) gridded in x_W, y_W at 0.25 m (an empty cell takes a neighbour's sounding) and
//           coloured by height above the median sounding (the plain) from -0.5 m to +1.5 m
//   right   the side-scan waterfall: one row per ping, newest at the top, port reversed on the left,
//           starboard on the right
// The soundings are checked against the seabed they sounded (the scenario's seabed mesh under each
// sounding; soundings on a vehicle, the targets, are counted apart): the JSON summary gives the pings of
// each sonar, the soundings and the median and 95th percentile of |z_sounding - h(x, y)| over the seabed, the
// time of the FLS ping shown and the plain's z (the median sounding).
// Captures are delivered without latency here (latency_s 0 on the model's copy), so that each ping's
// pose is the state's when it is read.
//   hadal-validate-sonar [--seconds 70] [--fls-at 20] [--scenario PATH] [--out DIR]   (default
//   configs/scenarios/sonar_survey.yaml, validation_out/sonar)
// Writes DIR/sonar_figure.png; prints one JSON object. Exit 0, 1 when the scenario does not load, has no
// sonars, or DIR cannot be written, 2 on a usage error.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
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
    "usage: hadal-validate-sonar [--seconds S] [--fls-at T] [--scenario PATH] [--out DIR]\n"
    "  --seconds S      simulated time to run (default 70: the survey line)\n"
    "  --fls-at T       show the forward-looking sonar's first ping at or after T seconds (default 20;\n"
    "                   its last ping if the run ends before)\n"
    "  --scenario PATH  a scenario whose vehicle carries an fls, a multibeam and a sidescan\n"
    "                   (default configs/scenarios/sonar_survey.yaml)\n"
    "  --out DIR        output directory (default validation_out/sonar)\n"
    "Runs the survey and writes DIR/sonar_figure.png (FLS fan, multibeam swath, side-scan waterfall); prints\n"
    "a JSON summary.\n";

constexpr int kPanelHeight = 600;
// The swath's colours: height above the median sounding [m].
constexpr double kSwathLowM = -0.5, kSwathHighM = 1.5;

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

// The forward-looking sonar's ping as a fan (BGR; FlsSensor::fan_image) with range rings every 10 m.
cv::Mat fan_panel(const sensors::FlsSensor::Spec& spec, const std::vector<std::uint8_t>& image) {
  sensors::FlsSensor::FanImage fan = sensors::FlsSensor::fan_image(spec, image, kPanelHeight);
  const cv::Mat grey(fan.height, fan.width, CV_8UC1, fan.grey.data());
  cv::Mat bgr;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  const double half_deg = 0.5 * spec.fov / kPi * 180.0;
  const cv::Point apex(fan.apex_u, fan.apex_v);
  for (double ring = 10.0; ring <= spec.acoustics.max_range + 1e-9; ring += 10.0) {
    const int radius = static_cast<int>(std::lround(ring * fan.px_per_m));
    cv::ellipse(bgr, apex, cv::Size(radius, radius), 0.0, -90.0 - half_deg, -90.0 + half_deg, cv::Scalar(0, 160, 255), 1,
                cv::LINE_AA);
    cv::putText(bgr, std::to_string(static_cast<int>(ring)) + " m", {apex.x + 4, apex.y - radius + 14},
                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 160, 255), 1, cv::LINE_AA);
  }
  return bgr;
}

struct Sounding {
  Eigen::Vector3d p_W;
  bool on_seabed = true;
};

// A sim time option: "" when `text` is a number in `range` (into *out), else "OPTION must be in RANGE".
std::string read_seconds(const std::string& option, const std::string& text, const validation::NumberRange& range,
                         double* out) {
  double parsed = 0.0;
  if (!validation::parse_number(text, &parsed) || !range.contains(parsed)) return option + " must be " + range.text();
  *out = parsed;
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_dir = "validation_out/sonar";
  std::string scenario = std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/sonar_survey.yaml";
  double seconds = 70.0, fls_at = 20.0;
  validation::CommandLine command_line = validation::make_command_line(kTool, kUsage);
  command_line.text("--out", &out_dir)
      .text("--scenario", &scenario)
      .option("--seconds",
              [&](const std::string& value) {
                return read_seconds("--seconds", value, validation::NumberRange::left_open(0.0, 3600.0), &seconds);
              })
      .option("--fls-at", [&](const std::string& value) {
        return read_seconds("--fls-at", value, validation::NumberRange::closed(0.0, 3600.0), &fls_at);
      });
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
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
  std::vector<std::uint8_t> fls_image;
  double fls_time = -1.0;  // when fls_image was read
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
    if (fresh(mounts.fls)) {
      ++fls_pings;
      // Keep the first ping at or after --fls-at (else, until then, the latest).
      if (fls_time < fls_at) {
        fls_image = state_of<sensors::FlsSensor>(state.sensors[static_cast<std::size_t>(mounts.fls)]).image;
        fls_time = sim.time();
      }
    }
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
          const std::size_t at = i * spec.encoding.bytes_per_sample();
          row[bins - 1 - i] = spec.encoding.grey(&ss.port[at]);
          row[bins + i] = spec.encoding.grey(&ss.starboard[at]);
        }
      }
      waterfall.push_back(std::move(row));
    }
  }

  // Left: the fan.
  cv::Mat left_bgr(kPanelHeight, 200, CV_8UC3, cv::Scalar(0, 0, 0));
  if (mounts.fls >= 0) {
    left_bgr = fan_panel(spec_of<sensors::FlsSensor>(carrier.sensors[static_cast<std::size_t>(mounts.fls)]), fls_image);
  }
  // Middle: the soundings' heights above the plain (their median) on a 0.25 m grid, x_W upwards, y_W to the
  // left (looking down, north up).
  std::vector<double> residuals;
  double x_min = 1e300, x_max = -1e300, y_min = 1e300, y_max = -1e300;
  std::vector<double> depths;
  for (const Sounding& s : soundings) {
    x_min = std::min(x_min, s.p_W.x());
    x_max = std::max(x_max, s.p_W.x());
    y_min = std::min(y_min, s.p_W.y());
    y_max = std::max(y_max, s.p_W.y());
    depths.push_back(s.p_W.z());
    geometry::SeabedHeight::Sample h;
    if (s.on_seabed && seabed.sample(s.p_W.x(), s.p_W.y(), &h)) residuals.push_back(std::abs(s.p_W.z() - h.height));
  }
  double plain_z = std::numeric_limits<double>::quiet_NaN();
  cv::Mat middle_bgr(kPanelHeight, 300, CV_8UC3, cv::Scalar(0, 0, 0));
  if (!soundings.empty()) {
    std::nth_element(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2), depths.end());
    plain_z = depths[depths.size() / 2];
    const double cell = 0.25;
    const int rows = std::max(1, static_cast<int>((x_max - x_min) / cell) + 1), cols = std::max(1, static_cast<int>((y_max - y_min) / cell) + 1);
    cv::Mat level(rows, cols, CV_8UC1, cv::Scalar(0));  // 0: no sounding; 1..255 over [low, high]
    for (const Sounding& s : soundings) {
      const int row = rows - 1 - static_cast<int>((s.p_W.x() - x_min) / cell), col = cols - 1 - static_cast<int>((s.p_W.y() - y_min) / cell);
      const double t = std::clamp((s.p_W.z() - plain_z - kSwathLowM) / (kSwathHighM - kSwathLowM), 0.0, 1.0);
      level.at<std::uint8_t>(row, col) = std::max(level.at<std::uint8_t>(row, col), static_cast<std::uint8_t>(1 + std::lround(254.0 * t)));
    }
    // The outer beams' soundings lie up to ~0.5 m apart across the track: an empty cell takes its highest
    // neighbour's (one pass: gaps of one cell, not the swath's edges).
    cv::Mat grown;
    cv::dilate(level, grown, cv::Mat::ones(3, 3, CV_8UC1));
    grown.copyTo(level, level == 0);
    cv::Mat coloured;
    cv::applyColorMap(level, coloured, cv::COLORMAP_JET);
    coloured.setTo(cv::Scalar(0, 0, 0), level == 0);
    const double fit = std::min(static_cast<double>(kPanelHeight) / rows, 600.0 / cols);
    cv::resize(coloured, middle_bgr, cv::Size(std::max(1, static_cast<int>(cols * fit)), kPanelHeight), 0, 0, cv::INTER_NEAREST);
    // The colour scale, bottom left: low to high.
    const int bar_x = 10, bar_y = kPanelHeight - 30, bar_w = std::min(160, middle_bgr.cols - 20);
    for (int i = 0; i < bar_w; ++i) {
      cv::Mat one(1, 1, CV_8UC1, cv::Scalar(1 + 254 * i / std::max(1, bar_w - 1))), c;
      cv::applyColorMap(one, c, cv::COLORMAP_JET);
      cv::line(middle_bgr, {bar_x + i, bar_y}, {bar_x + i, bar_y + 10}, c.at<cv::Vec3b>(0, 0));
    }
    char scale_text[64];
    std::snprintf(scale_text, sizeof scale_text, "%+.1f .. %+.1f m over z %.1f m", kSwathLowM, kSwathHighM, plain_z);
    cv::putText(middle_bgr, scale_text, {bar_x, bar_y + 24}, cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
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
  // Labels in white on a black box (the waterfall can be bright under them).
  const auto label = [](cv::Mat& image, const std::string& text) {
    int baseline = 0;
    const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.55, 1, &baseline);
    cv::rectangle(image, cv::Rect(4, 4, size.width + 8, size.height + baseline + 8), cv::Scalar(0, 0, 0), cv::FILLED);
    cv::putText(image, text, cv::Point(8, 8 + size.height), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  };
  char fls_text[96];
  std::snprintf(fls_text, sizeof fls_text, "forward-looking sonar, ping at t = %.1f s", fls_time);
  label(left_bgr, fls_text);
  label(middle_bgr, "multibeam: height");
  label(right_bgr, "side-scan waterfall (newest at top): port | starboard");
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
      "\"seabed_residual_p95_m\": %s, \"fls_ping_time_s\": %s, \"plain_z_m\": %s}\n",
      validation::json_string(file).c_str(), json_rounded(seconds).c_str(), fls_pings, multibeam_pings, sidescan_pings,
      soundings.size(), residuals.size(), json_rounded(percentile(0.5)).c_str(), json_rounded(percentile(0.95)).c_str(),
      json_rounded(fls_pings > 0 ? fls_time : std::numeric_limits<double>::quiet_NaN()).c_str(), json_rounded(plain_z).c_str());
  return 0;
}
