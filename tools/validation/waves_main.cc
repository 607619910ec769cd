// hadal-validate-waves: a generated sea's record against its target spectrum (issue 44; tools/validation/README.md).
//
//   hadal-validate-waves [--hs 2] [--tp 8] [--gamma 3.3] [--components 128] [--hours 3] [--seed 7] [--out DIR]
//
// The sea state of physics/waves.h (a JONSWAP spectrum, long-crested, deep water) sampled at one point at 4 Hz for
// --hours; the record's Welch spectrum (2048-sample Hann segments, half overlapping: 0.002 Hz bins) against the target
// S(f) = 2 pi alpha S_J(2 pi f), alpha such that its m0 over the sampled band [0.5, 4] f_p is (Hs / 4)^2 (what the
// waves are scaled to). Its significant height 4 sqrt(variance) and peak period (the S^4-weighted mean frequency of
// the Welch spectrum, Young 1995) against Hs and Tp.
//
// Writes into --out (default "."):
//   waves_spectrum.png  left: the Welch spectrum and the target (log y); right: the first 5 minutes of the record
//   waves_spectrum.csv  f_hz,welch_m2_per_hz,target_m2_per_hz
// and prints one JSON object (stdout): the targets, the record's Hs and Tp and their relative differences, the
// spectrum's sampling bin, the record's m0 against the target's.
//
// Exit status: 0 success; 1 an output cannot be written; 2 usage error.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "hadal/physics/waves.h"
#include "plot.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using namespace hadal::validation;

constexpr const char* kTool = "hadal-validate-waves";
constexpr const char* kUsage =
    "usage: hadal-validate-waves [--hs H] [--tp T] [--gamma G] [--components N] [--hours H] [--seed S] [--out DIR]\n"
    "  --hs H           significant height [m] (default 2, in (0, 30])\n"
    "  --tp T           peak period [s] (default 8, in [2, 30])\n"
    "  --gamma G        JONSWAP peak enhancement (default 3.3, in [1, 10])\n"
    "  --components N   components sampling the spectrum (default 128, in [16, 2048])\n"
    "  --hours H        record length [h] (default 3, in [0.25, 24])\n"
    "  --seed S         world seed (default 7)\n"
    "  --out DIR        output directory for waves_spectrum.{png,csv} (default .)\n"
    "Samples a JONSWAP sea's elevation at one point and compares its spectrum, Hs and Tp with the target; prints JSON.\n";

constexpr double kG = 9.80665, kRho = 1025.0, kDt = 0.25;  // kPi: validation_support.h
constexpr int kSegment = 2048;

}  // namespace

int main(int argc, char** argv) {
  double hs = 2.0, tp = 8.0, gamma = 3.3, components = 128.0, hours = 3.0, seed = 7.0;
  std::string out_dir = ".";
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--hs", &hs, NumberRange::left_open(0.0, 30.0))
      .number("--tp", &tp, NumberRange::closed(2.0, 30.0))
      .number("--gamma", &gamma, NumberRange::closed(1.0, 10.0))
      .number("--components", &components, NumberRange::closed(16.0, 2048.0))
      .number("--hours", &hours, NumberRange::closed(0.25, 24.0))
      .number("--seed", &seed, NumberRange::closed(0.0, 9.0e15))
      .text("--out", &out_dir);
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (components != std::floor(components) || seed != std::floor(seed)) {
    std::fprintf(stderr, "%s: --components and --seed are whole numbers\n%s", kTool, kUsage);
    return 2;
  }
  if (const std::string error = ensure_directory(out_dir); !error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }
  physics::WaveSpec spec;
  spec.spectrum = physics::WaveSpectrum::kJonswap;
  spec.significant_height = hs;
  spec.peak_period = tp;
  spec.gamma = gamma;
  spec.components = static_cast<int>(components);
  spec.ramp_time = 0.0;  // the sea itself, not its build-up from calm
  const physics::Waves waves(spec, 0.0, kRho, kG, static_cast<std::uint64_t>(seed));

  // The record at W's origin.
  const auto n = static_cast<std::size_t>(std::llround(hours * 3600.0 / kDt));
  std::vector<double> eta(n);
  double mean = 0.0;
  for (std::size_t i = 0; i < n; ++i) mean += (eta[i] = waves.surface_height(0.0, 0.0, static_cast<double>(i) * kDt)) / n;
  double variance = 0.0;
  for (double e : eta) variance += (e - mean) * (e - mean) / n;

  // Welch, one-sided PSD [m^2/Hz] from 0.02 to 0.6 Hz (direct DFT at those bins).
  const double df = 1.0 / (kDt * kSegment);
  const int first = static_cast<int>(0.02 / df), last = static_cast<int>(0.6 / df);
  int segments = 0;
  const std::vector<double> psd = welch_psd(eta, kDt, kSegment, first, last, &segments);

  // The target: alpha from m0 over the sampled band.
  const double omega_p = 2.0 * kPi / tp;
  double band = 0.0;
  const int steps = 20000;
  const double lo = 0.5 * omega_p, hi = 4.0 * omega_p, h = (hi - lo) / steps;
  for (int i = 0; i < steps; ++i) band += physics::jonswap_shape(lo + (i + 0.5) * h, omega_p, gamma, kG) * h;
  const double alpha = (hs / 4.0) * (hs / 4.0) / band;
  const auto target = [&](double f) {
    const double omega = 2.0 * kPi * f;
    return omega < lo || omega > hi ? 0.0 : 2.0 * kPi * alpha * physics::jonswap_shape(omega, omega_p, gamma, kG);
  };

  double weighted = 0.0, weights = 0.0, m0_welch = 0.0;
  for (int b = first; b <= last; ++b) {
    const double w = std::pow(psd[b], 4.0);
    weighted += w * b * df;
    weights += w;
    m0_welch += psd[b] * df;
  }
  const double tp_record = weights > 0.0 ? weights / weighted : 0.0;
  const double hs_record = 4.0 * std::sqrt(variance);

  namespace plot = hadal::validation::plot;
  plot::Figure figure;
  figure.title = "JONSWAP sea, Hs " + json_rounded(hs, 3) + " m, Tp " + json_rounded(tp, 3) + " s, gamma " +
                 json_rounded(gamma, 3) + ": " + json_rounded(hours, 3) + " h record at one point";
  figure.panel_width = 620;
  figure.panel_height = 460;
  plot::Panel spectrum;
  spectrum.title = "Spectrum";
  spectrum.x.label = "frequency [Hz]";
  spectrum.y.label = "S(f) [m^2/Hz]";
  spectrum.y.scale = plot::Scale::kLog10;
  const double peak_density = target(1.0 / tp) * 1.1;
  spectrum.y.min = peak_density * 1e-4;
  spectrum.y.max = peak_density * 2.0;
  spectrum.x.min = 0.0;
  spectrum.x.max = 0.5;
  plot::Series welch, goal;
  welch.label = "record (Welch, " + std::to_string(segments) + " segments)";
  welch.color = plot::palette(1);
  welch.line_width = 1.5;
  goal.label = "target JONSWAP";
  goal.color = plot::palette(0);
  goal.dashed = true;
  for (int b = first; b <= last; ++b) {
    welch.x.push_back(b * df);
    welch.y.push_back(psd[b]);
    goal.x.push_back(b * df);
    goal.y.push_back(target(b * df));
  }
  spectrum.series = {welch, goal};
  plot::Panel record;
  record.title = "Elevation, the first 5 minutes";
  record.x.label = "time [s]";
  record.y.label = "surface height [m]";
  record.legend = plot::LegendPosition::kNone;
  plot::Series series;
  series.color = plot::palette(2);
  series.line_width = 1.5;
  for (std::size_t i = 0; i < n && i * kDt <= 300.0; ++i) {
    series.x.push_back(static_cast<double>(i) * kDt);
    series.y.push_back(eta[i]);
  }
  record.series = {series};
  figure.panels = {spectrum, record};
  const std::string png = join_path(out_dir, "waves_spectrum.png");
  const std::string csv = join_path(out_dir, "waves_spectrum.csv");
  std::string error = plot::write_png(figure, png);
  if (error.empty()) {
    std::vector<double> target_psd(psd.size(), 0.0);
    for (int b = first; b <= last; ++b) target_psd[static_cast<std::size_t>(b)] = target(b * df);
    error = write_bins_csv(csv, "f_hz,welch_m2_per_hz,target_m2_per_hz", df, first, last, {&psd, &target_psd});
  }
  if (!error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }
  JsonObject json;
  json.number("significant_height_m", hs)
      .number("peak_period_s", tp)
      .number("gamma", gamma)
      .number("components", components)
      .number("record_h", hours)
      .number("record_significant_height_m", hs_record)
      .number("significant_height_relative_difference", (hs_record - hs) / hs)
      .number("record_peak_period_s", tp_record)
      .number("peak_period_relative_difference", (tp_record - tp) / tp)
      .number("sampling_bin_hz", 3.5 / tp / components)
      .number("peak_frequency_difference_hz", 1.0 / tp_record - 1.0 / tp)
      .number("welch_m0_over_target", m0_welch / ((hs / 4.0) * (hs / 4.0)))
      .text("png", png)
      .text("csv", csv);
  std::printf("%s\n", json.str().c_str());
  return 0;
}
