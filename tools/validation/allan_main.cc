// hadal-validate-allan: the Allan-deviation validation of the IMU noise model (issue "stochastic
// navigation sensors", acceptance; the paper's Allan comparison of a white-noise-only model against
// the full model). A static IMU records --hours of samples at --rate through hadal::Simulation, twice:
// with the configured noise model and with white noise only, and the overlapping Allan deviation of
// every axis is compared with the configured figures.
//
//   hadal-validate-allan [--hours 3] [--rate 100] [--out DIR] [--scenario PATH] [--preset ID] [--no-record]
//
// Default scenario tools/validation/scenarios/imu_static.yaml: a neutrally buoyant body at rest 1000 m
// deep in still water (lumped fluid, gravity on) carrying an IMU with the Honeywell HG1700 preset.
// The first IMU of the scenario is used; the tool sets its rate_hz and world.physics_rate_hz to
// --rate (one physics step per sample) on the loaded Model. --preset replaces the IMU's noise figures
// by a preset's (sensors/noise.h, imu_noise_params), keeping the scenario's range and resolution.
// The white-noise-only run clears, on a copy of the Model, what the loader's `white_noise_only: true`
// clears: bias instability (the Gauss-Markov bank), rate random walk, scale-factor and misalignment
// draws. Both runs share their white-noise stream (noise.h: one sub-stream per process), so the
// curves differ exactly by the removed terms.
//
// Analysis (sensors/allan.h): overlapping Allan deviation at log-spaced cluster sizes (10 per decade
// up to N/10 samples: at least ten clusters at the longest tau). Configured figures are read back from
// the Model's triad parameters: N the white-noise density, K the rate-random-walk density, B the bias
// instability of the Gauss-Markov bank (each term's sigma is 0.664 B / 0.77585, noise.h). Per axis
// and run: sigma(1 s) / N; the minimum of the curve from the lower end of the configured flicker range
// on (1 s for the loader's bank; floor_search_start below), the bias-instability floor, / (0.664 B); the
// slope over the decade after the floor (read_allan; +1/2 where rate random walk dominates) and over
// the curve's last decade, with the closed form of the configured model,
//   sigma^2(tau) = N^2 / tau + sum_j sigma_GM,j^2 (2x - 3 + 4 e^-x - e^-2x) / x^2 + K^2 tau / 3,
//   x = tau / tau_c,j, beside it; and the IEEE 952 three-term fit (fit_allan_terms) of N, B and K.
//
// Criteria ("pass" in the JSON; null when the configuration has nothing to check; tolerances and
// their statistics in README.md):
//   *_noise_at_1s       sigma(1 s) within 10 % of N (ARW, VRW), in both runs, on every axis where the
//                       configured model is white-dominated at 1 s (closed form within 2 % of N; an
//                       accelerometer whose bias floor exceeds its white noise at 1 s is checked in the
//                       white-noise-only run only).
//   *_bias_instability_floor  full run: the curve's minimum within 30 % of 0.664 B.
//   *_bias_instability_fit    full run: B of the three-term fit within 30 % of B (the fit uses every tau
//                       of the flicker range, the minimum one point of a noisy curve: half the scatter).
//   *_rate_random_walk  full run, K > 0: the closed-form slope over the last decade is >= 0.25 (the
//                       +1/2 rise shows in the record) and K of the fit is within 30 % of K.
//   white_noise_only_slope    white-noise-only run: slope from 1 s to the longest tau within 0.1 of -1/2.
// The acceptance is the gyro's noise, floor and rate-random-walk criteria on a 3-hour record.
//
// Writes into --out (default "."):
//   allan_deviation.png   left: gyro Allan deviation [deg/h] vs tau [s], full vs white-only (x, y, z),
//                         with N / sqrt(tau), the 0.664 B floor, K sqrt(tau / 3) if K > 0 and the
//                         closed form; right: the same for the accelerometer [m/s^2]
//   allan_record.csv      the full-model record analysed: time_s, gyro_x, gyro_y, gyro_z [rad/s],
//                         accel_x, accel_y, accel_z [m/s^2] (not with --no-record)
//   allan_parameters.json the sensor parameters used, as datasheet figures and in SI
// and prints one JSON object (stdout): configuration, per-run per-axis readouts, pass flags, wall time.
//
// Exit status: 0 success (whatever the criteria say); 1 the scenario does not load or has no IMU, the
// simulation throws or an output cannot be written; 2 usage error.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "hadal/core/simulation.h"
#include "hadal/sensors/allan.h"
#include "hadal/sensors/noise.h"
#include "plot.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using namespace hadal::validation;
namespace ns = hadal::sensors;

constexpr const char* kTool = "hadal-validate-allan";
constexpr const char* kUsage =
    "usage: hadal-validate-allan [--hours H] [--rate HZ] [--out DIR] [--scenario PATH] [--preset ID] [--no-record]\n"
    "  --hours H        length of each record [h] (default 3, in (0, 100])\n"
    "  --rate HZ        IMU sample rate = physics rate [Hz] (default 100, in (0, 10000])\n"
    "  --out DIR        output directory for allan_deviation.png, allan_record.csv, allan_parameters.json\n"
    "                   (default .)\n"
    "  --scenario PATH  scenario with a static IMU (default tools/validation/scenarios/imu_static.yaml)\n"
    "  --preset ID      replace the IMU's noise figures by a preset's: honeywell_hg1700, honeywell_hg9900,\n"
    "                   safran_primus_200, sensonor_stim300, xsens_mti_300\n"
    "  --no-record      do not write allan_record.csv (120 MB for 3 h at 100 Hz)\n"
    "Records the IMU at rest with the full noise model and with white noise only; prints JSON.\n";

constexpr double kDegPerHourPerRadPerSecond = 180.0 / kPi * 3600.0;
constexpr double kArwTolerance = 0.10;          // issue acceptance: sigma(1 s) within 10 % of ARW
constexpr double kFloorTolerance = 0.30;        // issue acceptance: floor within 30 % of 0.664 B
constexpr double kWhiteDominated = 1.02;        // closed form at 1 s within 2 % of N: the N check applies
constexpr double kRrwVisibleSlope = 0.25;       // closed-form last-decade slope that counts as visible
constexpr double kRrwTolerance = 0.30;          // fitted K vs configured (as the floor)
constexpr double kWhiteSlopeTolerance = 0.10;   // white-only slope vs -1/2 (4 sigma at 3 h, README)

// --- configured figures ------------------------------------------------------------------------------

// Bias instability B of an axis's Gauss-Markov bank (noise.h, bias_instability_to_gauss_markov_bank:
// every term has sigma = 0.664 B / 0.77585); 0 without one.
double bias_instability_of(const ns::AxisNoiseParams& axis) {
  if (axis.gauss_markov.empty()) return 0.0;
  return axis.gauss_markov.front().sigma * ns::kDecadeBankAllanRatio / ns::kBiasInstabilityAllanFactor;
}

// Closed-form Allan variance of the configured processes at tau (constant biases do not enter).
double closed_form_variance(const ns::AxisNoiseParams& axis, double tau) {
  double v = axis.white_noise_density * axis.white_noise_density / tau;
  for (const ns::GaussMarkovParams& gm : axis.gauss_markov) v += ns::gauss_markov_allan_variance(gm, tau);
  v += axis.bias_random_walk_density * axis.bias_random_walk_density * tau / 3.0;
  return v;
}
double closed_form_deviation(const ns::AxisNoiseParams& axis, double tau) {
  return std::sqrt(closed_form_variance(axis, tau));
}

// What `white_noise_only: true` removes in the loader (read_imu): everything but white noise.
void keep_white_noise_only(ns::NoiseTriadParams& triad) {
  for (ns::AxisNoiseParams& axis : triad.axes) {
    axis.bias_random_walk_density = 0.0;
    axis.gauss_markov.clear();
  }
  triad.scale_factor_sigma = 0.0;
  triad.misalignment_sigma = 0.0;
}

bool same_axis(const ns::AxisNoiseParams& a, const ns::AxisNoiseParams& b) {
  return a.white_noise_density == b.white_noise_density && a.bias_random_walk_density == b.bias_random_walk_density &&
         a.gauss_markov == b.gauss_markov && a.turn_on_bias == b.turn_on_bias &&
         a.turn_on_bias_sigma == b.turn_on_bias_sigma;
}
bool same_noise(const ns::NoiseTriadParams& a, const ns::NoiseTriadParams& b) {
  for (int i = 0; i < 3; ++i) {
    if (!same_axis(a.axes[i], b.axes[i])) return false;
  }
  return a.scale_factor_sigma == b.scale_factor_sigma && a.misalignment_sigma == b.misalignment_sigma;
}
// The preset whose figures the IMU's noise parameters are exactly (as the loader builds them), or null.
const hadal::config::Preset<ns::ImuDatasheet>* identify_preset(const ns::ImuSensor::Spec& imu) {
  for (const hadal::config::Preset<ns::ImuDatasheet>& preset : ns::imu_presets()) {
    const ns::ImuNoiseParams p = ns::imu_noise_params(preset.figures);
    if (same_noise(p.gyro, imu.gyro) && same_noise(p.accel, imu.accel)) return &preset;
  }
  return nullptr;
}

// --- the record ----------------------------------------------------------------------------------------

struct Record {
  std::vector<double> time;                    // sample stamps [s]
  std::array<std::vector<double>, 6> channel;  // gyro x, y, z [rad/s], accel x, y, z [m/s^2]
  double max_speed = 0.0;                      // of the IMU's vehicle [m/s]
  double max_angular_rate = 0.0;               // [rad/s]
  double max_stamp_error = 0.0;                // |stamp spacing - 1 / rate| [s]
  double wall_s = 0.0;
};

Record record_imu(const Model& model, int vehicle, int sensor, std::size_t count, const std::string& name) {
  const auto start = std::chrono::steady_clock::now();
  Record record;
  record.time.reserve(count);
  for (auto& c : record.channel) c.reserve(count);
  Simulation sim(model);
  const double rate = model.vehicles[vehicle].sensors[sensor].rate_hz;
  const double period = 1.0 / rate;
  const double steps_per_sample = model.world.physics_rate_hz / rate;
  const auto max_steps = static_cast<std::uint64_t>(std::ceil(static_cast<double>(count) * steps_per_sample)) + 10;
  std::uint64_t seen = sim.state().vehicles[vehicle].sensors[sensor].samples;
  const double hours = static_cast<double>(count) * period / 3600.0;
  HourlyProgress progress(kTool, name, hours);
  while (record.time.size() < count && sim.state().step_count < max_steps) {
    sim.step();
    const VehicleState& state = sim.state().vehicles[vehicle];
    record.max_speed = std::max(record.max_speed, state.body.v_WB.norm());
    record.max_angular_rate = std::max(record.max_angular_rate, state.body.w_WB.norm());
    const SensorState& s = state.sensors[sensor];
    if (s.samples == seen) continue;
    seen = s.samples;
    if (!record.time.empty()) {
      record.max_stamp_error = std::max(record.max_stamp_error, std::fabs(s.stamp - record.time.back() - period));
    }
    record.time.push_back(s.stamp);
    const ns::ImuSensor::State& imu = state_of<ns::ImuSensor>(s);
    for (int c = 0; c < 3; ++c) {
      record.channel[c].push_back(imu.angular_velocity_S[c]);
      record.channel[3 + c].push_back(imu.specific_force_S[c]);
    }
    progress.update(s.stamp);
  }
  if (record.time.size() < count) {
    throw std::runtime_error(name + ": the IMU gave " + std::to_string(record.time.size()) + " samples in " +
                             std::to_string(max_steps) + " steps, expected " + std::to_string(count));
  }
  record.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return record;
}

// --- analysis ------------------------------------------------------------------------------------------

// Where a bias-instability floor is looked for: from the lower end of the configured flicker range on.
// The loader's bank (noise.h) has its first term's Allan peak one decade below that end (tau_min 1 s),
// and below it the bank rolls off as sqrt(tau) by design; a white-noise density far under the floor (an
// HG1700 accelerometer: N / (0.664 B) = 0.05) would otherwise put the curve's minimum at a few samples,
// in that roll-off. 0 without a bank.
double floor_search_start(const ns::AxisNoiseParams& axis) {
  if (axis.gauss_markov.empty()) return 0.0;
  double lowest = std::numeric_limits<double>::infinity();
  for (const ns::GaussMarkovParams& gm : axis.gauss_markov) lowest = std::min(lowest, gm.correlation_time_s);
  return 10.0 * ns::kGaussMarkovAllanPeakTauRatio * lowest;
}

struct AxisResult {
  std::vector<ns::AllanPoint> curve;
  ns::AllanReadout readout;  // read_allan's figures, the floor searched from floor_search_start on
  ns::AllanFit fit;
  double last_decade_slope = 0.0;              // measured, tau_end / 10 .. tau_end
  double closed_form_last_decade_slope = 0.0;  // configured model, same taus
  double white_slope = 0.0;                    // measured, 1 s .. tau_end
};

AxisResult analyse(const std::vector<double>& samples, double period, const ns::AxisNoiseParams& configured) {
  AxisResult r;
  r.curve = ns::overlapping_allan_deviation(samples, period);
  r.readout.deviation_at_1s = ns::allan_deviation_at(r.curve, 1.0);
  r.readout.floor = ns::allan_minimum(r.curve, floor_search_start(configured));
  r.readout.slope_after_floor = ns::allan_slope(r.curve, r.readout.floor.tau_s, 10.0 * r.readout.floor.tau_s);
  // The three-term fit over the same range: below the flicker range the bank's roll-off is no IEEE 952 term.
  const double start = floor_search_start(configured);
  std::vector<ns::AllanPoint> fitted;
  for (const ns::AllanPoint& p : r.curve) {
    if (p.tau_s >= start) fitted.push_back(p);
  }
  r.fit = ns::fit_allan_terms(fitted);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (r.curve.empty()) {
    r.last_decade_slope = r.closed_form_last_decade_slope = r.white_slope = nan;
    return r;
  }
  const double tau_end = r.curve.back().tau_s;
  r.last_decade_slope = ns::allan_slope(r.curve, tau_end / 10.0, tau_end);
  r.closed_form_last_decade_slope =
      std::log(closed_form_deviation(configured, tau_end) / closed_form_deviation(configured, tau_end / 10.0)) /
      std::log(10.0);
  r.white_slope = tau_end > 1.0 ? ns::allan_slope(r.curve, 1.0, tau_end) : nan;
  return r;
}

// Channels 0..5 of a record: gyro x, y, z then accel x, y, z.
std::array<AxisResult, 6> analyse(const Record& record, double period, const ns::ImuSensor::Spec& configured) {
  std::array<AxisResult, 6> out;
  for (int c = 0; c < 6; ++c) {
    const ns::AxisNoiseParams& axis = c < 3 ? configured.gyro.axes[c] : configured.accel.axes[c - 3];
    out[c] = analyse(record.channel[c], period, axis);
  }
  return out;
}

// A ratio, NaN when the reference is 0.
double ratio(double value, double reference) {
  return reference > 0.0 ? value / reference : std::numeric_limits<double>::quiet_NaN();
}

// A criterion over several checks: null until a check applies, then the AND of those that apply.
class Criterion {
 public:
  void check(bool ok) { state_ = state_.value_or(true) && ok; }
  std::optional<bool> value() const { return state_; }
  std::string json() const { return state_ ? (*state_ ? "true" : "false") : "null"; }

 private:
  std::optional<bool> state_;
};

// --- output ----------------------------------------------------------------------------------------------

// {"a": 1, "b": 2} on one line.
std::string compact(const std::vector<std::pair<std::string, std::string>>& fields) {
  std::string out = "{";
  for (std::size_t i = 0; i < fields.size(); ++i) {
    out += (i ? ", " : "") + json_string(fields[i].first) + ": " + fields[i].second;
  }
  return out + "}";
}

std::string axis_json(const AxisResult& r, const ns::AxisNoiseParams& configured) {
  const double N = configured.white_noise_density;
  const double B = bias_instability_of(configured);
  const double K = configured.bias_random_walk_density;
  const double floor_ref = ns::kBiasInstabilityAllanFactor * B;
  const ns::AllanPoint& floor = r.readout.floor;
  return compact({
      {"sigma_1s", json_rounded(r.readout.deviation_at_1s)},
      {"sigma_1s_over_N", json_rounded(ratio(r.readout.deviation_at_1s, N), 4)},
      {"closed_form_1s_over_N", json_rounded(ratio(closed_form_deviation(configured, 1.0), N), 4)},
      {"floor", json_rounded(floor.deviation)},
      {"floor_tau_s", json_rounded(floor.tau_s, 4)},
      {"floor_over_0664B", json_rounded(ratio(floor.deviation, floor_ref), 4)},
      {"closed_form_at_floor_tau_over_0664B",
       json_rounded(floor.tau_s > 0.0 ? ratio(closed_form_deviation(configured, floor.tau_s), floor_ref)
                                      : std::numeric_limits<double>::quiet_NaN(), 4)},
      {"slope_after_floor", json_rounded(r.readout.slope_after_floor, 3)},
      {"last_decade_slope", json_rounded(r.last_decade_slope, 3)},
      {"closed_form_last_decade_slope", json_rounded(r.closed_form_last_decade_slope, 3)},
      {"slope_from_1s", json_rounded(r.white_slope, 3)},
      {"fit_N_over_N", json_rounded(ratio(r.fit.white_noise_density, N), 4)},
      {"fit_B_over_B", json_rounded(ratio(r.fit.bias_instability, B), 4)},
      {"fit_K", json_rounded(r.fit.rate_random_walk_density)},
      {"fit_K_over_K", json_rounded(ratio(r.fit.rate_random_walk_density, K), 4)},
  });
}

std::string run_json(const std::array<AxisResult, 6>& results, const ns::ImuSensor::Spec& configured, const Record& record,
                     std::size_t steps) {
  static const char* kAxes[3] = {"x", "y", "z"};
  JsonObject gyro(4), accel(4);
  for (int i = 0; i < 3; ++i) {
    gyro.raw(kAxes[i], axis_json(results[i], configured.gyro.axes[i]));
    accel.raw(kAxes[i], axis_json(results[3 + i], configured.accel.axes[i]));
  }
  JsonObject run(2);
  run.raw("gyro_rad_s", gyro.str())
      .raw("accel_m_s2", accel.str())
      .number("max_speed_m_s", record.max_speed, 3)
      .number("max_angular_rate_rad_s", record.max_angular_rate, 3)
      .number("max_stamp_spacing_error_s", record.max_stamp_error, 3)
      .number("wall_time_s", record.wall_s, 3)
      .number("physics_steps_per_wall_second", record.wall_s > 0.0 ? static_cast<double>(steps) / record.wall_s : 0.0,
              4);
  return run.str();
}

// Per-axis values as a JSON array of three: round-trip numbers, or `digits` significant digits (figures
// converted back from SI, where the last bits are round-off).
template <typename F>
std::string per_axis(const ns::NoiseTriadParams& triad, F value, int digits = 0) {
  std::string out = "[";
  for (int i = 0; i < 3; ++i) {
    const double x = value(triad.axes[i]);
    out += (i ? ", " : "") + (digits > 0 ? json_rounded(x, digits) : json_number(x));
  }
  return out + "]";
}
constexpr int kSheetDigits = 12;

std::string gauss_markov_json(const ns::AxisNoiseParams& axis) {
  std::string out = "[";
  for (std::size_t j = 0; j < axis.gauss_markov.size(); ++j) {
    out += (j ? ", " : "") + compact({{"sigma", json_number(axis.gauss_markov[j].sigma)},
                                      {"correlation_time_s", json_number(axis.gauss_markov[j].correlation_time_s)}});
  }
  return out + "]";
}

// One triad's parameters: datasheet figures (converted back from SI with noise.h's factors) and SI.
std::string triad_parameters_json(const ns::NoiseTriadParams& t, bool gyro) {
  JsonObject sheet(4), si(4);
  using A = ns::AxisNoiseParams;
  // A datasheet figure per axis: the SI value over the unit's SI size.
  auto figure = [&](auto value, double unit) {
    return per_axis(t, [&](const A& a) { return value(a) / unit; }, kSheetDigits);
  };
  auto white = [](const A& a) { return a.white_noise_density; };
  auto bias = [](const A& a) { return bias_instability_of(a); };
  auto walk = [](const A& a) { return a.bias_random_walk_density; };
  auto scalar = [](double x) { return json_rounded(x, kSheetDigits); };
  if (gyro) {
    sheet.raw("arw_deg_per_sqrt_h", figure(white, ns::arw_to_noise_density(1.0)))
        .raw("bias_instability_deg_per_h", figure(bias, ns::deg_per_h_to_rad_per_s(1.0)))
        .raw("rrw_deg_per_h_per_sqrt_h", figure(walk, ns::rrw_to_random_walk_density(1.0)))
        .raw("scale_factor_ppm", scalar(t.scale_factor_sigma * 1e6))
        .raw("misalignment_deg", scalar(t.misalignment_sigma * kDegPerRad))
        .raw("range_deg_per_s", scalar(t.max * kDegPerRad))
        .raw("resolution_deg_per_s", scalar(t.lsb * kDegPerRad));
  } else {
    const double mg = ns::milli_g_to_mps2(1.0);
    sheet.raw("vrw_m_per_s_per_sqrt_h", figure(white, ns::vrw_to_noise_density(1.0)))
        .raw("noise_density_ug_per_sqrt_hz", figure(white, ns::micro_g_per_sqrt_hz_to_noise_density(1.0)))
        .raw("bias_instability_mg", figure(bias, mg))
        .raw("random_walk_m_per_s_per_h_per_sqrt_h", figure(walk, ns::accel_rrw_to_random_walk_density(1.0)))
        .raw("scale_factor_ppm", scalar(t.scale_factor_sigma * 1e6))
        .raw("misalignment_deg", scalar(t.misalignment_sigma * kDegPerRad))
        .raw("range_g", scalar(t.max / ns::kStandardGravity))
        .raw("resolution_mg", scalar(t.lsb / mg));
  }
  const std::string u = gyro ? "rad_s" : "m_s2";
  si.raw("white_noise_density_" + u + "_per_sqrt_hz", per_axis(t, [](const A& a) { return a.white_noise_density; }))
      .raw("bias_instability_" + u, per_axis(t, [](const A& a) { return bias_instability_of(a); }))
      .raw("allan_floor_0664B_" + u, per_axis(t, [](const A& a) {
             return ns::kBiasInstabilityAllanFactor * bias_instability_of(a);
           }))
      .raw("random_walk_density_" + u + "_per_s_per_sqrt_hz",
           per_axis(t, [](const A& a) { return a.bias_random_walk_density; }))
      .raw("gauss_markov_bank_x", gauss_markov_json(t.axes[0]))
      .raw("gauss_markov_bank_y", gauss_markov_json(t.axes[1]))
      .raw("gauss_markov_bank_z", gauss_markov_json(t.axes[2]))
      .raw("turn_on_bias_" + u, per_axis(t, [](const A& a) { return a.turn_on_bias; }))
      .raw("turn_on_bias_sigma_" + u, per_axis(t, [](const A& a) { return a.turn_on_bias_sigma; }))
      .raw("scale_factor_sigma", json_number(t.scale_factor_sigma))
      .raw("misalignment_sigma_rad", json_number(t.misalignment_sigma))
      .raw("lsb_" + u, json_number(t.lsb))
      .raw("min_" + u, json_number(t.min))
      .raw("max_" + u, json_number(t.max));
  JsonObject out(2);
  out.raw("datasheet", sheet.str()).raw("si", si.str());
  return out.str();
}

std::string write_text(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return path + ": cannot write";
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  return std::fclose(f) == 0 && ok ? std::string() : path + ": write failed";
}

// time_s + six channels, %.9e (10 significant digits: far below the noise), through a 4 MB buffer.
std::string write_record_csv(const Record& r, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return path + ": cannot write the CSV";
  std::vector<char> buffer(1 << 22);
  std::setvbuf(f, buffer.data(), _IOFBF, buffer.size());
  bool ok = std::fputs("time_s,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z\n", f) >= 0;
  const auto& c = r.channel;
  for (std::size_t i = 0; ok && i < r.time.size(); ++i) {
    ok = std::fprintf(f, "%.6f,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e\n", r.time[i], c[0][i], c[1][i], c[2][i], c[3][i],
                      c[4][i], c[5][i]) > 0;
  }
  const bool closed = std::fclose(f) == 0;
  return ok && closed ? std::string() : path + ": write failed";
}

// --- figure ----------------------------------------------------------------------------------------------

namespace plot = hadal::validation::plot;

plot::Panel allan_panel(const std::string& title, const std::string& unit, double scale,
                        const std::array<AxisResult, 6>& full, const std::array<AxisResult, 6>& white, int first,
                        const ns::AxisNoiseParams& configured, const std::string& white_name) {
  plot::Panel panel;
  panel.title = title;
  panel.x.label = "averaging time tau [s]";
  panel.y.label = "Allan deviation [" + unit + "]";
  panel.x.scale = panel.y.scale = plot::Scale::kLog10;
  panel.legend = plot::LegendPosition::kBottomLeft;
  const std::vector<ns::AllanPoint>& curve = full[first].curve;
  if (curve.empty()) return panel;
  const double tau0 = curve.front().tau_s, tau1 = curve.back().tau_s;
  std::vector<double> taus;
  for (int k = 0; k <= 200; ++k) taus.push_back(tau0 * std::pow(tau1 / tau0, k / 200.0));
  auto reference = [&](const std::string& label, plot::Color color, auto f) {
    plot::Series s;
    s.label = label;
    s.color = color;
    s.dashed = true;
    s.line_width = 1.5;
    for (double tau : taus) {
      s.x.push_back(tau);
      s.y.push_back(f(tau) * scale);
    }
    return s;
  };
  const double N = configured.white_noise_density;
  const double B = bias_instability_of(configured);
  const double K = configured.bias_random_walk_density;
  if (N > 0.0) {
    panel.series.push_back(
        reference(white_name + " N / sqrt(tau)", plot::palette(2), [&](double tau) { return N / std::sqrt(tau); }));
  }
  if (B > 0.0) {
    panel.series.push_back(reference("floor 0.664 B", plot::palette(3),
                                     [&](double) { return ns::kBiasInstabilityAllanFactor * B; }));
  }
  if (K > 0.0) {
    panel.series.push_back(
        reference("RRW K sqrt(tau / 3)", plot::palette(5), [&](double tau) { return K * std::sqrt(tau / 3.0); }));
  }
  plot::Series closed = reference("closed form, configured", plot::palette(7),
                                  [&](double tau) { return closed_form_deviation(configured, tau); });
  closed.line_width = 1.0;
  panel.series.push_back(closed);
  auto measured = [&](const std::array<AxisResult, 6>& results, const std::string& label, plot::Color color) {
    for (int i = 0; i < 3; ++i) {
      plot::Series s;
      s.label = i == 0 ? label : "";
      s.color = color;
      s.line_width = 1.5;
      for (const ns::AllanPoint& p : results[first + i].curve) {
        s.x.push_back(p.tau_s);
        s.y.push_back(p.deviation * scale);
      }
      panel.series.push_back(s);
    }
  };
  measured(white, "white noise only (x, y, z)", plot::palette(0));
  measured(full, "full model (x, y, z)", plot::palette(1));
  // Whole decades, one more on top when the highest curve comes within a tenth of a decade of it (a
  // floor just under a decade boundary would otherwise run along the frame).
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const plot::Series& s : panel.series) {
    for (double y : s.y) {
      if (y > 0.0 && std::isfinite(y)) {
        lo = std::min(lo, y);
        hi = std::max(hi, y);
      }
    }
  }
  if (hi > 0.0) {
    panel.y.min = std::pow(10.0, std::floor(std::log10(lo)));
    const double top = std::ceil(std::log10(hi));
    panel.y.max = std::pow(10.0, top - std::log10(hi) < 0.1 ? top + 1.0 : top);
  }
  return panel;
}

}  // namespace

int main(int argc, char** argv) {
  double hours = 3.0;
  double rate = 100.0;
  bool write_record = true;
  std::string out_dir = ".";
  std::string scenario = HADAL_SOURCE_DIR "/tools/validation/scenarios/imu_static.yaml";
  std::string preset_id;
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--hours", &hours, NumberRange::left_open(0.0, 100.0))
      .number("--rate", &rate, NumberRange::left_open(0.0, 10000.0))
      .text("--out", &out_dir)
      .text("--scenario", &scenario)
      .text("--preset", &preset_id)
      .flag("--no-record", [&] { write_record = false; });
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  const hadal::config::Preset<ns::ImuDatasheet>* preset = nullptr;
  if (!preset_id.empty()) {
    preset = hadal::config::find_preset(ns::imu_presets(), preset_id);
    if (!preset) return command_line.usage_error("unknown --preset '" + preset_id + "'");
  }
  const auto sample_count = static_cast<std::size_t>(std::llround(hours * 3600.0 * rate));
  if (sample_count < 100) {
    return command_line.usage_error("--hours x --rate gives " + std::to_string(sample_count) +
                                    " samples; at least 100 are needed");
  }

  std::optional<Model> loaded = prepare_run(out_dir, scenario, kTool);
  if (!loaded) return 1;
  Model model = std::move(*loaded);
  const std::optional<SensorRef> found = find_sensor<ns::ImuSensor>(model);
  if (!found) {
    std::fprintf(stderr, "%s: %s: no IMU sensor in the scenario\n", kTool, scenario.c_str());
    return 1;
  }
  const int vehicle = found->vehicle, sensor = found->sensor;
  SensorSpec& imu_sensor = model.vehicles[vehicle].sensors[sensor];
  imu_sensor.rate_hz = rate;
  model.world.physics_rate_hz = rate;
  ns::ImuSensor::Spec& imu = std::get<ns::ImuSensor::Spec>(imu_sensor.kind);
  if (preset) {
    const ns::ImuNoiseParams p = ns::imu_noise_params(preset->figures);
    ns::NoiseTriadParams gyro = p.gyro, accel = p.accel;
    gyro.min = imu.gyro.min;
    gyro.max = imu.gyro.max;
    gyro.lsb = imu.gyro.lsb;
    if (!std::isfinite(accel.max)) {
      accel.min = imu.accel.min;
      accel.max = imu.accel.max;
    }
    accel.lsb = imu.accel.lsb;
    imu.gyro = gyro;
    imu.accel = accel;
  } else {
    preset = identify_preset(imu);
  }
  Model white_model = model;
  ns::ImuSensor::Spec& white_imu = std::get<ns::ImuSensor::Spec>(white_model.vehicles[vehicle].sensors[sensor].kind);
  keep_white_noise_only(white_imu.gyro);
  keep_white_noise_only(white_imu.accel);

  const double period = 1.0 / rate;
  const auto wall_start = std::chrono::steady_clock::now();
  Record full, white;
  std::array<AxisResult, 6> full_results, white_results;
  double analysis_wall = 0.0;
  try {
    full = record_imu(model, vehicle, sensor, sample_count, "full model");
    white = record_imu(white_model, vehicle, sensor, sample_count, "white noise only");
    const auto analysis_start = std::chrono::steady_clock::now();
    full_results = analyse(full, period, imu);
    white_results = analyse(white, period, white_imu);
    analysis_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - analysis_start).count();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }
  const std::string vehicle_name = model.vehicles[vehicle].name;
  const std::string imu_name = imu_sensor.name;
  const std::string preset_text = preset ? std::string(preset->id) : std::string("custom");

  // Figure.
  plot::Figure figure;
  char title[200];
  std::snprintf(title, sizeof(title), "Overlapping Allan deviation of a static IMU: %s, %.3g h at %.4g Hz",
                preset ? std::string(preset->product).c_str() : "custom figures", hours, rate);
  figure.title = title;
  figure.panel_width = 720;
  figure.panel_height = 580;
  figure.panels = {allan_panel("Gyroscope", "deg/h", kDegPerHourPerRadPerSecond, full_results, white_results, 0,
                               imu.gyro.axes[0], "ARW"),
                   allan_panel("Accelerometer", "m/s^2", 1.0, full_results, white_results, 3, imu.accel.axes[0],
                               "VRW")};

  const std::string png = join_path(out_dir, "allan_deviation.png");
  const std::string csv = join_path(out_dir, "allan_record.csv");
  const std::string parameters = join_path(out_dir, "allan_parameters.json");

  // Sensor parameters.
  JsonObject params;
  params.text("tool", kTool)
      .text("scenario", scenario)
      .text("vehicle", vehicle_name)
      .text("sensor", imu_name)
      .text("preset", preset_text);
  if (preset) params.text("preset_name", std::string(preset->product)).text("preset_source", std::string(preset->source));
  params.raw("seed", std::to_string(model.world.seed))
      .raw("sample_rate_hz", json_number(rate))
      .raw("physics_rate_hz", json_number(model.world.physics_rate_hz))
      .raw("hours", json_number(hours))
      .raw("samples", std::to_string(sample_count))
      .raw("gyro", triad_parameters_json(imu.gyro, true))
      .raw("accel", triad_parameters_json(imu.accel, false))
      .text("white_noise_only_run",
            "the same parameters without bias instability (Gauss-Markov bank), rate random walk, scale-factor "
            "and misalignment draws; the white-noise stream is shared with the full run")
      .text("record", write_record ? "allan_record.csv: the full-model run" : "not written (--no-record)")
      .text("record_columns",
            "time_s [s], gyro_x, gyro_y, gyro_z [rad/s], accel_x, accel_y, accel_z [m/s^2] in the sensor frame; "
            "at rest the accelerometer reads the specific force -g, +9.80665 m/s^2 on z when level")
      .text("allan_estimator",
            "overlapping Allan deviation (IEEE Std 952; NIST SP 1065 eq. 11), cluster sizes round(10^(i/10)) "
            "up to N/10 samples");

  const auto output_start = std::chrono::steady_clock::now();
  std::string error = plot::write_png(figure, png);
  if (error.empty()) error = write_text(parameters, params.str() + "\n");
  if (error.empty() && write_record) error = write_record_csv(full, csv);
  if (!error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }
  const double output_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - output_start).count();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  // Criteria.
  Criterion noise[2], floor[2], floor_fit[2], rrw[2], white_slope;
  for (int c = 0; c < 6; ++c) {
    const int triad = c < 3 ? 0 : 1;
    const ns::AxisNoiseParams& axis = triad == 0 ? imu.gyro.axes[c] : imu.accel.axes[c - 3];
    const ns::AxisNoiseParams& white_axis = triad == 0 ? white_imu.gyro.axes[c] : white_imu.accel.axes[c - 3];
    const double N = axis.white_noise_density;
    const double B = bias_instability_of(axis);
    const double K = axis.bias_random_walk_density;
    if (N > 0.0) {
      const std::pair<const AxisResult*, const ns::AxisNoiseParams*> runs[2] = {{&full_results[c], &axis},
                                                                                {&white_results[c], &white_axis}};
      for (const auto& [result, configured] : runs) {
        if (closed_form_deviation(*configured, 1.0) <= kWhiteDominated * N) {
          noise[triad].check(std::fabs(result->readout.deviation_at_1s / N - 1.0) <= kArwTolerance);
        }
      }
      white_slope.check(std::fabs(white_results[c].white_slope + 0.5) <= kWhiteSlopeTolerance);
    }
    if (B > 0.0) {
      floor[triad].check(std::fabs(full_results[c].readout.floor.deviation /
                                       (ns::kBiasInstabilityAllanFactor * B) - 1.0) <= kFloorTolerance);
      floor_fit[triad].check(std::fabs(full_results[c].fit.bias_instability / B - 1.0) <= kFloorTolerance);
    }
    if (K > 0.0) {
      const AxisResult& r = full_results[c];
      rrw[triad].check(r.closed_form_last_decade_slope >= kRrwVisibleSlope &&
                       std::fabs(r.fit.rate_random_walk_density / K - 1.0) <= kRrwTolerance);
    }
  }
  bool all = true;
  for (const Criterion* c : {&noise[0], &floor[0], &floor_fit[0], &rrw[0], &noise[1], &floor[1], &floor_fit[1], &rrw[1],
                             &white_slope}) {
    all = all && c->value().value_or(true);
  }
  JsonObject pass(2);
  pass.raw("gyro_noise_at_1s", noise[0].json())
      .raw("gyro_bias_instability_floor", floor[0].json())
      .raw("gyro_bias_instability_fit", floor_fit[0].json())
      .raw("gyro_rate_random_walk", rrw[0].json())
      .raw("accel_noise_at_1s", noise[1].json())
      .raw("accel_bias_instability_floor", floor[1].json())
      .raw("accel_bias_instability_fit", floor_fit[1].json())
      .raw("accel_rate_random_walk", rrw[1].json())
      .raw("white_noise_only_slope", white_slope.json())
      .boolean("all", all);

  const ns::AxisNoiseParams& g = imu.gyro.axes[0];
  const ns::AxisNoiseParams& a = imu.accel.axes[0];
  JsonObject configured(2);
  configured.number("gyro_arw_deg_per_sqrt_h", g.white_noise_density / ns::arw_to_noise_density(1.0))
      .number("gyro_N_rad_s_per_sqrt_hz", g.white_noise_density)
      .number("gyro_bias_instability_deg_per_h", bias_instability_of(g) / ns::deg_per_h_to_rad_per_s(1.0))
      .number("gyro_floor_0664B_rad_s", ns::kBiasInstabilityAllanFactor * bias_instability_of(g))
      .number("gyro_rrw_deg_per_h_per_sqrt_h", g.bias_random_walk_density / ns::rrw_to_random_walk_density(1.0))
      .number("gyro_K_rad_s2_per_sqrt_hz", g.bias_random_walk_density)
      .number("accel_vrw_m_per_s_per_sqrt_h", a.white_noise_density / ns::vrw_to_noise_density(1.0))
      .number("accel_N_m_s2_per_sqrt_hz", a.white_noise_density)
      .number("accel_bias_instability_mg", bias_instability_of(a) / ns::milli_g_to_mps2(1.0))
      .number("accel_floor_0664B_m_s2", ns::kBiasInstabilityAllanFactor * bias_instability_of(a))
      .number("accel_K_m_s3_per_sqrt_hz", a.bias_random_walk_density);

  const std::size_t steps = static_cast<std::size_t>(std::llround(static_cast<double>(sample_count) *
                                                                  model.world.physics_rate_hz / rate));
  JsonObject json;
  json.text("scenario", scenario)
      .text("vehicle", vehicle_name)
      .text("sensor", imu_name)
      .text("preset", preset_text)
      .number("hours", hours)
      .number("rate_hz", rate)
      .raw("samples", std::to_string(sample_count))
      .raw("seed", std::to_string(model.world.seed))
      .raw("configured", configured.str())
      .raw("full_model", run_json(full_results, imu, full, steps))
      .raw("white_noise_only", run_json(white_results, white_imu, white, steps))
      .raw("pass", pass.str())
      .number("analysis_wall_time_s", analysis_wall, 3)
      .number("output_wall_time_s", output_wall, 3)
      .number("wall_time_s", wall, 3)
      .text("png", png)
      .raw("csv", write_record ? json_string(csv) : "null")
      .text("parameters", parameters);
  std::printf("%s\n", json.str().c_str());
  return 0;
}
