// hadal-validate-vessel-waves: a floating vessel's heave and pitch spectra against its sea's (issue 44;
// tools/validation/README.md).
//
//   hadal-validate-vessel-waves [--minutes 20] [--out DIR] [--scenario PATH]
//
// Default scenario configs/scenarios/vessel_waves.yaml (the catamaran ASV in a JONSWAP sea of Hs 2 m, Tp 8 s). Its
// first vehicle drifts (its schedule dropped: no thrust) while hadal::Simulation steps for 1 min plus --minutes; after
// the first minute (the sea's build-up and the vessel's settling) it records at 10 Hz the height of B, B's nose-up
// pitch and starboard-down roll, and the sea at B's (x, y): the surface's height and its slopes along the vessel's
// heading and to port. For a vessel much shorter than the waves (2 m in 100 m) linear theory says it follows the
// surface: heave response 1 and pitch and roll the surface's slopes (response 1), over the sea's spectrum. The Welch
// spectra (1024-sample Hann segments, half overlapping: 0.0098 Hz bins) show it frequency by frequency.
//
// Writes into --out (default "."):
//   vessel_waves.png  left: the spectra of the sea's elevation at the vessel and of its heave; middle: of the slope
//                     along its heading and of its pitch; right: the first 2 minutes of the record
//   vessel_waves.csv  f_hz,sea_m2_per_hz,heave_m2_per_hz,slope_rad2_per_hz,pitch_rad2_per_hz
// and prints one JSON object (stdout): the sea's significant height at the vessel and the heave's (4 sqrt m0), their
// ratio, the rms slope along the heading and the rms pitch, their ratio, the same across for roll, and the heave
// response sqrt(S_heave / S_sea) averaged over the spectrum's peak (0.1-0.16 Hz).
//
// Exit status: 0 success; 1 the scenario does not load, the simulation throws or an output cannot be written;
// 2 usage error.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "hadal/core/simulation.h"
#include "hadal/physics/ocean.h"
#include "plot.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using namespace hadal::validation;

constexpr const char* kTool = "hadal-validate-vessel-waves";
constexpr const char* kUsage =
    "usage: hadal-validate-vessel-waves [--minutes M] [--out DIR] [--scenario PATH]\n"
    "  --minutes M      record length after a 1 min settling [min] (default 20, in [2, 600])\n"
    "  --out DIR        output directory for vessel_waves.{png,csv} (default .)\n"
    "  --scenario PATH  scenario (default configs/scenarios/vessel_waves.yaml; its first vehicle drifts)\n"
    "Records a floating vessel's heave, pitch and roll in its scenario's sea; prints JSON.\n";

constexpr double kDt = 0.1, kSettle = 60.0;
constexpr int kSegment = 1024;

double variance(const std::vector<double>& x) {
  double mean = 0.0, sum = 0.0;
  for (double v : x) mean += v / static_cast<double>(x.size());
  for (double v : x) sum += (v - mean) * (v - mean);
  return sum / static_cast<double>(x.size());
}

}  // namespace

int main(int argc, char** argv) {
  double minutes = 20.0;
  std::string out_dir = ".", scenario = std::string(HADAL_SOURCE_DIR) + "/configs/scenarios/vessel_waves.yaml";
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--minutes", &minutes, NumberRange::closed(2.0, 600.0))
      .text("--out", &out_dir)
      .text("--scenario", &scenario);
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  std::optional<Model> model = prepare_run(out_dir, scenario, kTool);
  if (!model) return 1;
  if (model->vehicles.empty() || !model->world.waves.enabled()) {
    std::fprintf(stderr, "%s: %s: needs a vehicle and world.waves\n", kTool, scenario.c_str());
    return 1;
  }
  model->vehicles[0].schedule.clear();  // it drifts
  std::vector<double> sea, heave, slope_ahead, slope_port, pitch, roll, time;
  try {
    Simulation sim(*model);
    const physics::Waves& waves = sim.ocean().waves();
    const int per_sample = std::max(1, static_cast<int>(std::lround(kDt * model->world.physics_rate_hz)));
    const auto samples = static_cast<std::size_t>(std::llround(minutes * 60.0 / kDt));
    for (int k = 0; k < static_cast<int>(std::lround(kSettle / kDt)) * per_sample; ++k) sim.step();
    for (std::size_t i = 0; i < samples; ++i) {
      for (int k = 0; k < per_sample; ++k) sim.step();
      const Eigen::Isometry3d& X = sim.state().vehicles[0].body.X_WB;
      const Eigen::Matrix3d& R = X.linear();
      const double t = sim.time();
      double eta = 0.0;
      Eigen::Vector2d slope;
      waves.surface(X.translation().x(), X.translation().y(), t, &eta, &slope);
      // The heading's horizontal direction and its port side.
      const Eigen::Vector2d ahead = Eigen::Vector2d(R(0, 0), R(1, 0)).normalized();
      const Eigen::Vector2d port(-ahead.y(), ahead.x());
      time.push_back(t);
      sea.push_back(waves.surface_z() + eta);
      heave.push_back(X.translation().z());
      slope_ahead.push_back(slope.dot(ahead));
      slope_port.push_back(slope.dot(port));
      pitch.push_back(std::asin(std::clamp(R(2, 0), -1.0, 1.0)));    // x_B's rise: nose up
      roll.push_back(-std::asin(std::clamp(R(2, 1), -1.0, 1.0)));    // y_B's fall: port up (rising to port)
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }

  const double df = 1.0 / (kDt * kSegment);
  const int first = std::max(1, static_cast<int>(0.02 / df)), last = static_cast<int>(0.5 / df);
  int segments = 0;
  const std::vector<double> s_sea = welch_psd(sea, kDt, kSegment, first, last, &segments);
  const std::vector<double> s_heave = welch_psd(heave, kDt, kSegment, first, last, nullptr);
  const std::vector<double> s_slope = welch_psd(slope_ahead, kDt, kSegment, first, last, nullptr);
  const std::vector<double> s_pitch = welch_psd(pitch, kDt, kSegment, first, last, nullptr);
  double response = 0.0;
  int peak_bins = 0;
  for (int b = first; b <= last; ++b) {
    if (b * df < 0.1 || b * df > 0.16 || !(s_sea[b] > 0.0)) continue;
    response += std::sqrt(s_heave[b] / s_sea[b]);
    ++peak_bins;
  }
  response /= std::max(peak_bins, 1);
  const double hs_sea = 4.0 * std::sqrt(variance(sea)), hs_heave = 4.0 * std::sqrt(variance(heave));
  const double slope_rms = std::sqrt(variance(slope_ahead)), pitch_rms = std::sqrt(variance(pitch));
  const double cross_rms = std::sqrt(variance(slope_port)), roll_rms = std::sqrt(variance(roll));

  namespace plot = hadal::validation::plot;
  plot::Figure figure;
  figure.title = "Drifting vessel in its sea (" + scenario.substr(scenario.find_last_of('/') + 1) + "): " +
                 json_rounded(minutes, 3) + " min at 10 Hz";
  figure.panel_width = 520;
  figure.panel_height = 440;
  const auto spectrum_panel = [&](const std::string& title, const std::string& unit, const std::vector<double>& a,
                                  const std::string& a_label, const std::vector<double>& b, const std::string& b_label) {
    plot::Panel panel;
    panel.title = title;
    panel.x.label = "frequency [Hz]";
    panel.y.label = unit;
    panel.y.scale = plot::Scale::kLog10;
    double peak = 0.0;
    for (int i = first; i <= last; ++i) peak = std::max({peak, a[i], b[i]});
    panel.y.min = peak * 1e-4;
    panel.y.max = peak * 2.0;
    panel.x.min = 0.0;
    panel.x.max = 0.5;
    plot::Series sa, sb;
    sa.label = a_label;
    sa.color = plot::palette(0);
    sa.dashed = true;
    sb.label = b_label;
    sb.color = plot::palette(1);
    sb.line_width = 1.5;
    for (int i = first; i <= last; ++i) {
      sa.x.push_back(i * df);
      sa.y.push_back(a[i]);
      sb.x.push_back(i * df);
      sb.y.push_back(b[i]);
    }
    panel.series = {sa, sb};
    return panel;
  };
  plot::Panel record;
  record.title = "The first 2 minutes";
  record.x.label = "time [s]";
  record.y.label = "height [m]";
  plot::Series r_sea, r_heave;
  r_sea.label = "sea at the vessel";
  r_sea.color = plot::palette(0);
  r_sea.dashed = true;
  r_heave.label = "vessel's B";
  r_heave.color = plot::palette(1);
  r_heave.line_width = 1.5;
  for (std::size_t i = 0; i < time.size() && time[i] <= time.front() + 120.0; ++i) {
    r_sea.x.push_back(time[i]);
    r_sea.y.push_back(sea[i]);
    r_heave.x.push_back(time[i]);
    r_heave.y.push_back(heave[i]);
  }
  record.series = {r_sea, r_heave};
  figure.panels = {spectrum_panel("Heave", "S(f) [m^2/Hz]", s_sea, "sea's elevation at the vessel", s_heave, "heave"),
                   spectrum_panel("Pitch", "S(f) [rad^2/Hz]", s_slope, "sea's slope along the heading", s_pitch,
                                  "pitch (nose up)"),
                   record};
  const std::string png = join_path(out_dir, "vessel_waves.png"), csv = join_path(out_dir, "vessel_waves.csv");
  std::string error = plot::write_png(figure, png);
  if (error.empty()) {
    error = write_bins_csv(csv, "f_hz,sea_m2_per_hz,heave_m2_per_hz,slope_rad2_per_hz,pitch_rad2_per_hz", df, first,
                           last, {&s_sea, &s_heave, &s_slope, &s_pitch});
  }
  if (!error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }
  JsonObject json;
  json.number("record_min", minutes)
      .number("segments", segments)
      .number("sea_significant_height_m", hs_sea)
      .number("heave_significant_height_m", hs_heave)
      .number("heave_over_sea", hs_heave / hs_sea)
      .number("heave_response_at_peak", response)
      .number("slope_rms_rad", slope_rms)
      .number("pitch_rms_rad", pitch_rms)
      .number("pitch_over_slope", pitch_rms / slope_rms)
      .number("cross_slope_rms_rad", cross_rms)
      .number("roll_rms_rad", roll_rms)
      .number("roll_over_cross_slope", roll_rms / cross_rms)
      .text("png", png)
      .text("csv", csv);
  std::printf("%s\n", json.str().c_str());
  return 0;
}
