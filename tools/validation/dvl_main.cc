// hadal-validate-dvl: the DVL drift validation (issue "DVL", acceptance; the paper's figure "DVL
// validation", section "DVL Drift and Bias"): a stationary DVL in bottom lock records --hours of pings
// through hadal::Simulation, twice with the same seed: with the full model (per-beam white noise and the
// paper's bias b(t + dt) = b(t) + xi dt: drawn turn-on bias b0, drawn drift rate xi0, random walk K) and
// with white noise only (the same per-beam noise, every bias term zero). Each record is dead-reckoned and
// the position error compared with its closed form.
//
//   hadal-validate-dvl [--hours 3] [--interval 10] [--seed N] [--out DIR] [--scenario PATH] [--no-record]
//
// Default scenario tools/validation/scenarios/dvl_static.yaml: a neutrally buoyant body hovering 20 m
// above a flat seabed, 1000 m deep (buoyancy at the centre of mass balances gravity exactly, so it is
// truly at rest; the JSON reports its largest speed and displacement), carrying the default AUV's DVL
// (Workhorse Navigator 600 preset at 5 Hz, bias 2 mm/s turn-on, 3e-8 m/s^2 drift rate, 1e-5 m/s/sqrt(s)
// walk). The first DVL of the scenario is used, at the scenario's rate (its per-ping noise figure was
// converted to a density at that rate on load, so the rate is not an option here).
// The white-noise-only run zeroes, on a copy of the Model, the bias's initial value and sigma, drift rate
// and sigma and random walk. Both runs draw their per-beam noise from the same channel keys, so the
// runs differ exactly by the bias: v_full - v_white = b(t_k) for every ping (the 4-beam least squares is
// linear and recovers b exactly from b . d_i), which the tool checks.
//
// Dead reckoning: p_DR(t_n) = p_WS(0) + sum_{k<=n} R_WS(t_k) v_k T_k, v_k the ping's velocity in S,
// R_WS(t_k) the true attitude of S (constant here), T_k the time since the previous ping (the first ping
// comes at t = T). Error e(t_n) = p_DR(t_n) - p_WS(t_n) in W [m]; the drift is |e| [m]. A ping without a
// velocity (no lock) would contribute nothing (it is counted; none occur over the flat seabed).
//
// Closed forms (n pings of period T, t = n T; Cov_S = sigma_beam^2 (D^T D)^-1 the 4-beam least-squares
// covariance of dvl.h, sigma_beam^2 = N^2 / T + lsb^2 / 12, Cov_W = R_WS Cov_S R_WS^T, sigma_i^2 its
// diagonal):
//   white noise only  e(t) = R_WS T sum_k eta_k, a random walk: std sigma_i sqrt(T t) per W axis, RMS
//                     magnitude sqrt(T t tr Cov_W);
//   full model        b_k = b0 + xi0 k T + K sqrt(T) sum_{j<=k} w_j, so
//                     e(t) = R_WS (b0 t + xi0 T^2 n (n + 1) / 2) + [white part] + [walk part],
//                     the deterministic term b0 t + xi0 t^2 / 2 + xi0 T t / 2 (b0, xi0 read from the DVL
//                     state before the first ping), the white part as above and the walk part
//                     K T^(3/2) sum_j (n - j + 1) w_j of variance K^2 T^3 n (n + 1)(2n + 1) / 6 (= K^2 t^3 / 3
//                     for n >> 1) per axis: the spread about the deterministic term is
//                     s_i = sqrt(sigma_i^2 T t + K^2 T^3 n (n + 1)(2n + 1) / 6).
//
// Criteria ("pass" in the JSON; README.md gives the tolerances' statistics):
//   stationary              the body moved less than 1 micrometre and turned less than 1 nanoradian.
//   bottom_lock             every ping of both runs is a 4-beam bottom-track solution.
//   white_noise_velocity_std  white-only run: sample std of each S axis within 5 % of sqrt(Cov_S(i, i))
//                           (relative scatter 1 / sqrt(2 n): 0.3 % at 3 h, 1.05 % at 15 min).
//   white_noise_drift       white-only run: |e_i| <= 4 sigma_i sqrt(T t) at every --interval sample, every
//                           W axis (two-sided 4 sigma: 6e-5 per sample).
//   bias_model_closed_form  full run: |e_i - deterministic_i| <= 4 s_i at every --interval sample, axis.
//   bias_model_monotonic    full run: |e| at t = 0, --interval, 2 --interval, ... strictly increasing.
//   runs_differ_by_integrated_bias  max over pings of |e_full - e_white - R_WS T sum_k b_k| <= 1e-8 m
//                           (b_k read from the DVL state each ping; rounding of sums of 10^4-10^5 terms of
//                           metre-sized positions, ~1e-10 m).
//
// Writes into --out (default "."):
//   dvl_drift.png        left: the zero-velocity time series of both models (x_S of every ping); middle:
//                        window means (1/36 of the record, at least a minute) of every S axis of both runs
//                        and the full model's true bias b(t); right: the dead-reckoned drift |e| against
//                        time for both, with the closed forms and the monotonicity samples
//   dvl_record.csv       both records: time_s, model (full / white), vx, vy, vz [m/s, S], mode (1 bottom
//                        track), num_good_beams, dr_x, dr_y, dr_z [m, W: the dead-reckoning error e],
//                        bias_x, bias_y, bias_z [m/s, S: the DVL state's b(t_k)] (not with --no-record)
//   dvl_parameters.json  the DVL parameters used, the drawn bias values, the mounting and the record layout
// and prints one JSON object (stdout): configuration, closed forms, per-run figures, pass flags, wall time.
//
// Exit status: 0 success (whatever the criteria say); 1 the scenario does not load or has no DVL, the
// simulation throws or an output cannot be written; 2 usage error.
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "hadal/core/simulation.h"
#include "hadal/sensors/dvl.h"
#include "hadal/sensors/noise.h"
#include "plot.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using namespace hadal::validation;
namespace ns = hadal::sensors;
namespace plot = hadal::validation::plot;

constexpr const char* kTool = "hadal-validate-dvl";
constexpr const char* kUsage =
    "usage: hadal-validate-dvl [--hours H] [--interval MIN] [--seed N] [--out DIR] [--scenario PATH] [--no-record]\n"
    "  --hours H        length of each record [h] (default 3, in (0, 100])\n"
    "  --interval MIN   spacing of the drift samples for the monotonicity and closed-form checks [min]\n"
    "                   (default 10, in (0, 60 --hours])\n"
    "  --seed N         scenario seed (default: the scenario's world.seed)\n"
    "  --out DIR        output directory for dvl_drift.png, dvl_record.csv, dvl_parameters.json (default .)\n"
    "  --scenario PATH  scenario with a stationary DVL in bottom lock (default\n"
    "                   tools/validation/scenarios/dvl_static.yaml)\n"
    "  --no-record      do not write dvl_record.csv (17 MB for 3 h at 5 Hz)\n"
    "Records the DVL at rest with the full bias model and with white noise only, dead-reckons both; prints JSON.\n";

constexpr double kStationaryDisplacement = 1e-6;  // [m]: 1e-6 of the drifts measured
constexpr double kStationaryRotation = 1e-9;      // [rad]
constexpr double kVelocityStdTolerance = 0.05;    // relative; 4.7 sigma at 15 min, 17 sigma at 3 h
constexpr double kSigmas = 4.0;                   // drift checks: two-sided 4 sigma per sample and axis
constexpr double kDecompositionTolerance = 1e-8;  // [m] rounding of the position sums (header text)
constexpr double kMeanWindows = 36.0;             // the figure's window means per record (5 min at 3 h)

// --- the record ----------------------------------------------------------------------------------------

struct Record {
  std::vector<double> time;                 // ping stamps [s]
  std::vector<Eigen::Vector3d> velocity_S;  // measured [m/s]; NaN without a solution
  std::vector<Eigen::Vector3d> bias_S;      // the DVL state's b(t_k) after the ping [m/s]
  std::vector<Eigen::Vector3d> error_W;     // dead-reckoning error e(t_k) [m]
  std::vector<Eigen::Vector3d> bias_integral_W;  // R_WS T sum b_k [m]
  std::vector<std::uint8_t> mode;
  std::vector<int> good_beams;
  Eigen::Vector3d b0_S = Eigen::Vector3d::Zero();   // drawn turn-on bias b(0) [m/s]
  Eigen::Vector3d xi0_S = Eigen::Vector3d::Zero();  // drawn drift rate [m/s^2]
  Eigen::Matrix3d R_WS = Eigen::Matrix3d::Identity();  // at the start
  Eigen::Vector3d p_WS0 = Eigen::Vector3d::Zero();
  Eigen::Matrix3d reported_covariance = Eigen::Matrix3d::Constant(-1.0);  // the first ping's
  std::size_t bottom_track_four_beams = 0;
  std::size_t without_velocity = 0;
  double max_speed = 0.0;          // of the vehicle [m/s]
  double max_angular_rate = 0.0;   // [rad/s]
  double max_displacement = 0.0;   // of S from its start [m]
  double max_rotation = 0.0;       // angle of R_WS(0)^T R_WS(t) [rad]
  double max_stamp_error = 0.0;    // |stamp spacing - T| [s]
  double wall_s = 0.0;
};

Eigen::Isometry3d sensor_pose_W(const Simulation& sim, int vehicle, int sensor) {
  const VehicleSpec& spec = sim.model().vehicles[vehicle];
  const SensorSpec& s = spec.sensors[sensor];
  return sim.state().vehicles[vehicle].body.X_WB * spec.links[s.link_index].X_BL * s.X_LS;
}

double rotation_angle(const Eigen::Matrix3d& R) {
  return std::acos(std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0));
}

Record record_dvl(const Model& model, int vehicle, int sensor, std::size_t count, const std::string& name) {
  const auto start = std::chrono::steady_clock::now();
  Record r;
  r.time.reserve(count);
  r.velocity_S.reserve(count);
  r.bias_S.reserve(count);
  r.error_W.reserve(count);
  r.bias_integral_W.reserve(count);
  r.mode.reserve(count);
  r.good_beams.reserve(count);
  Simulation sim(model);
  const SensorState& initial = sim.state().vehicles[vehicle].sensors[sensor];
  r.b0_S = state_of<ns::DvlSensor>(initial).dvl.bias;
  r.xi0_S = state_of<ns::DvlSensor>(initial).dvl.drift_rate;
  const Eigen::Isometry3d X_WS0 = sensor_pose_W(sim, vehicle, sensor);
  r.R_WS = X_WS0.linear();
  r.p_WS0 = X_WS0.translation();
  const double period = 1.0 / model.vehicles[vehicle].sensors[sensor].rate_hz;
  const double steps_per_ping = model.world.physics_rate_hz * period;
  const auto max_steps = static_cast<std::uint64_t>(std::ceil(static_cast<double>(count) * steps_per_ping)) + 10;
  std::uint64_t seen = initial.samples;
  Eigen::Vector3d p_DR = r.p_WS0;
  Eigen::Vector3d bias_integral = Eigen::Vector3d::Zero();
  double last_stamp = 0.0;
  const double hours = static_cast<double>(count) * period / 3600.0;
  HourlyProgress progress(kTool, name, hours);
  while (r.time.size() < count && sim.state().step_count < max_steps) {
    sim.step();
    const VehicleState& state = sim.state().vehicles[vehicle];
    r.max_speed = std::max(r.max_speed, state.body.v_WB.norm());
    r.max_angular_rate = std::max(r.max_angular_rate, state.body.w_WB.norm());
    const SensorState& s = state.sensors[sensor];
    if (s.samples == seen) continue;
    seen = s.samples;
    const Eigen::Isometry3d X_WS = sensor_pose_W(sim, vehicle, sensor);
    r.max_displacement = std::max(r.max_displacement, (X_WS.translation() - r.p_WS0).norm());
    r.max_rotation = std::max(r.max_rotation, rotation_angle(r.R_WS.transpose() * X_WS.linear()));
    const double dt = s.stamp - last_stamp;
    r.max_stamp_error = std::max(r.max_stamp_error, std::fabs(dt - period));
    last_stamp = s.stamp;
    const ns::DvlSensor::State& dvl = state_of<ns::DvlSensor>(s);
    const ns::DvlPing& ping = dvl.ping;
    if (r.time.empty()) r.reported_covariance = ping.velocity_covariance;
    if (ping.mode == ns::DvlMode::kNone) {
      ++r.without_velocity;
    } else {
      p_DR += X_WS.linear() * ping.velocity * dt;
    }
    if (ping.mode == ns::DvlMode::kBottomTrack && ping.num_good_beams == ns::kDvlBeams) ++r.bottom_track_four_beams;
    bias_integral += X_WS.linear() * dvl.dvl.bias * dt;
    r.time.push_back(s.stamp);
    r.velocity_S.push_back(ping.velocity);
    r.bias_S.push_back(dvl.dvl.bias);
    r.error_W.push_back(p_DR - X_WS.translation());
    r.bias_integral_W.push_back(bias_integral);
    r.mode.push_back(static_cast<std::uint8_t>(ping.mode));
    r.good_beams.push_back(ping.num_good_beams);
    progress.update(s.stamp);
  }
  if (r.time.size() < count) {
    throw std::runtime_error(name + ": the DVL gave " + std::to_string(r.time.size()) + " pings in " +
                             std::to_string(max_steps) + " steps, expected " + std::to_string(count));
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

// --- closed forms --------------------------------------------------------------------------------------

struct ClosedForm {
  double period = 0.0;                              // T [s]
  double beam_sigma = 0.0;                          // per beam per ping [m/s]
  Eigen::Matrix3d cov_S = Eigen::Matrix3d::Zero();  // sigma_beam^2 (D^T D)^-1 [m^2/s^2]
  Eigen::Matrix3d cov_W = Eigen::Matrix3d::Zero();
  double K = 0.0;                                   // bias random walk [m/s/sqrt(s)]

  Eigen::Vector3d sigma_S() const { return cov_S.diagonal().cwiseSqrt(); }
  Eigen::Vector3d sigma_W() const { return cov_W.diagonal().cwiseSqrt(); }
  // White-noise random walk after n pings: per-axis std sigma_i sqrt(T t) [m].
  Eigen::Vector3d white_std(std::size_t n) const { return sigma_W() * std::sqrt(period * period * double(n)); }
  double white_rms(std::size_t n) const { return std::sqrt(period * period * double(n) * cov_W.trace()); }
  // Std of the bias walk's integral after n pings, per axis [m].
  double walk_std(std::size_t n) const {
    const double m = static_cast<double>(n);
    return K * std::sqrt(period * period * period * m * (m + 1.0) * (2.0 * m + 1.0) / 6.0);
  }
  // Spread of the full model's error about its deterministic term, per axis [m].
  Eigen::Vector3d full_spread(std::size_t n) const {
    const Eigen::Vector3d w = white_std(n);
    const double k = walk_std(n);
    return (w.array().square() + k * k).sqrt().matrix();
  }
};

ClosedForm closed_form(const ns::DvlParams& p, double period, const Eigen::Matrix3d& R_WS) {
  ClosedForm c;
  c.period = period;
  const double white = ns::white_noise_sigma(p.beam_velocity_noise.noise.white_noise_density, period);
  c.beam_sigma = std::sqrt(white * white + p.beam_velocity_noise.lsb * p.beam_velocity_noise.lsb / 12.0);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& d : ns::dvl_beam_unit_vectors(p)) A += d * d.transpose();
  c.cov_S = c.beam_sigma * c.beam_sigma * A.inverse();
  c.cov_W = R_WS * c.cov_S * R_WS.transpose();
  c.K = p.bias.random_walk_density;
  return c;
}

// The full model's deterministic drift after n pings: R_WS (b0 n T + xi0 T^2 n (n + 1) / 2) [m].
Eigen::Vector3d deterministic_drift(const Record& r, double period, std::size_t n) {
  const double m = static_cast<double>(n);
  return r.R_WS * (r.b0_S * m * period + r.xi0_S * period * period * m * (m + 1.0) / 2.0);
}

// --- analysis ------------------------------------------------------------------------------------------

struct Sample {
  double time = 0.0;      // [s]
  std::size_t pings = 0;  // n: pings up to this time
  Eigen::Vector3d error = Eigen::Vector3d::Zero();
};

// e at t = 0, interval, 2 interval, ... up to the record's end (t = 0: no ping yet, e = 0).
std::vector<Sample> samples_every(const Record& r, double period, double interval_s) {
  std::vector<Sample> out{Sample{}};
  const double end = r.time.back();
  for (int j = 1;; ++j) {
    const double t = j * interval_s;
    if (t > end * (1.0 + 1e-12)) break;
    const auto n = static_cast<std::size_t>(std::llround(t / period));
    if (n < 1 || n > r.time.size()) break;
    out.push_back(Sample{r.time[n - 1], n, r.error_W[n - 1]});
  }
  return out;
}

struct RunFigures {
  Eigen::Vector3d mean_S = Eigen::Vector3d::Zero();  // velocity mean per S axis [m/s]
  Eigen::Vector3d std_S = Eigen::Vector3d::Zero();   // sample std (n - 1) [m/s]
  std::vector<Sample> samples;                       // every --interval
  bool monotonic = false;
  double max_normalized = 0.0;  // max over samples (t > 0) and axes of the normalized error
  Eigen::Vector3d normalized_end = Eigen::Vector3d::Zero();
};

RunFigures analyse(const Record& r, const ClosedForm& c, double interval_s, bool full) {
  RunFigures f;
  std::size_t n = 0;
  for (const Eigen::Vector3d& v : r.velocity_S) {
    if (!v.allFinite()) continue;
    f.mean_S += v;
    ++n;
  }
  if (n > 0) f.mean_S /= static_cast<double>(n);
  for (const Eigen::Vector3d& v : r.velocity_S) {
    if (v.allFinite()) f.std_S += (v - f.mean_S).cwiseAbs2();
  }
  if (n > 1) f.std_S = (f.std_S / static_cast<double>(n - 1)).cwiseSqrt();
  f.samples = samples_every(r, c.period, interval_s);
  f.monotonic = f.samples.size() >= 2;
  for (std::size_t j = 1; j < f.samples.size(); ++j) {
    f.monotonic = f.monotonic && f.samples[j].error.norm() > f.samples[j - 1].error.norm();
  }
  auto normalized = [&](std::size_t pings, const Eigen::Vector3d& e) -> Eigen::Vector3d {
    if (full) return ((e - deterministic_drift(r, c.period, pings)).array() / c.full_spread(pings).array()).matrix();
    return (e.array() / c.white_std(pings).array()).matrix();
  };
  for (std::size_t j = 1; j < f.samples.size(); ++j) {
    const Eigen::Vector3d z = normalized(f.samples[j].pings, f.samples[j].error);
    f.max_normalized = std::max(f.max_normalized, z.cwiseAbs().maxCoeff());
  }
  f.normalized_end = normalized(r.time.size(), r.error_W.back());
  return f;
}

// |e| at t (the last ping at or before t), or NaN beyond the record.
double drift_at(const Record& r, double period, double t) {
  const auto n = static_cast<std::size_t>(std::llround(t / period));
  if (n < 1 || n > r.time.size()) return std::numeric_limits<double>::quiet_NaN();
  return r.error_W[n - 1].norm();
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

std::string vec_json(const Eigen::Vector3d& v, int digits = 6) {
  return "[" + json_rounded(v.x(), digits) + ", " + json_rounded(v.y(), digits) + ", " + json_rounded(v.z(), digits) +
         "]";
}
std::string vec_exact(const Eigen::Vector3d& v) {
  return "[" + json_number(v.x()) + ", " + json_number(v.y()) + ", " + json_number(v.z()) + "]";
}
std::string matrix_exact(const Eigen::Matrix3d& m) {
  std::string out = "[";
  for (int i = 0; i < 3; ++i) out += (i ? ", " : "") + vec_exact(m.row(i).transpose());
  return out + "]";
}

std::string run_json(const Record& r, const RunFigures& f, double period, double hours, std::size_t steps) {
  JsonObject run(2);
  run.raw("mean_velocity_S_m_s", vec_json(f.mean_S))
      .raw("std_velocity_S_m_s", vec_json(f.std_S));
  for (int h = 1; h <= 3; ++h) run.number("drift_at_" + std::to_string(h) + "h_m", drift_at(r, period, h * 3600.0));
  const double end = r.error_W.back().norm();
  run.number("drift_at_end_m", end)
      .raw("drift_at_end_W_m", vec_json(r.error_W.back()))
      .number("drift_rate_m_per_h", end / hours)
      .raw("normalized_error_at_end", vec_json(f.normalized_end, 4))
      .number("max_abs_normalized_error", f.max_normalized, 4);
  std::string samples = "[";
  for (std::size_t j = 0; j < f.samples.size(); ++j) {
    samples += (j ? ", " : "") + json_rounded(f.samples[j].error.norm(), 6);
  }
  run.raw("drift_samples_m", samples + "]")
      .boolean("monotonic", f.monotonic)
      .raw("pings", std::to_string(r.time.size()))
      .raw("bottom_track_four_beam_pings", std::to_string(r.bottom_track_four_beams))
      .raw("pings_without_velocity", std::to_string(r.without_velocity))
      .number("max_speed_m_s", r.max_speed, 3)
      .number("max_angular_rate_rad_s", r.max_angular_rate, 3)
      .number("max_displacement_m", r.max_displacement, 3)
      .number("max_rotation_rad", r.max_rotation, 3)
      .number("max_stamp_spacing_error_s", r.max_stamp_error, 3)
      .number("wall_time_s", r.wall_s, 3)
      .number("physics_steps_per_wall_second", r.wall_s > 0.0 ? static_cast<double>(steps) / r.wall_s : 0.0, 4);
  return run.str();
}

std::string write_text(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return path + ": cannot write";
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  return std::fclose(f) == 0 && ok ? std::string() : path + ": write failed";
}

// Both records, one row per ping, %.9e (10 significant digits: far below the noise), 4 MB buffer.
std::string write_record_csv(const Record& full, const Record& white, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return path + ": cannot write the CSV";
  std::vector<char> buffer(1 << 22);
  std::setvbuf(f, buffer.data(), _IOFBF, buffer.size());
  bool ok = std::fputs("time_s,model,vx,vy,vz,mode,num_good_beams,dr_x,dr_y,dr_z,bias_x,bias_y,bias_z\n", f) >= 0;
  for (const auto& [r, name] : {std::pair<const Record*, const char*>{&full, "full"}, {&white, "white"}}) {
    for (std::size_t i = 0; ok && i < r->time.size(); ++i) {
      const Eigen::Vector3d& v = r->velocity_S[i];
      const Eigen::Vector3d& e = r->error_W[i];
      const Eigen::Vector3d& b = r->bias_S[i];
      ok = std::fprintf(f, "%.6f,%s,%.9e,%.9e,%.9e,%d,%d,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e\n", r->time[i], name, v.x(),
                        v.y(), v.z(), static_cast<int>(r->mode[i]), r->good_beams[i], e.x(), e.y(), e.z(), b.x(), b.y(),
                        b.z()) > 0;
    }
  }
  const bool closed = std::fclose(f) == 0;
  return ok && closed ? std::string() : path + ": write failed";
}

// --- figure ----------------------------------------------------------------------------------------------

// Means of axis `axis` of `values` over non-overlapping windows of `per` pings, stamped at the windows'
// centres [h, mm/s].
plot::Series window_means(const Record& r, const std::vector<Eigen::Vector3d>& values, int axis, std::size_t per,
                          const std::string& label, plot::Color color) {
  plot::Series s;
  s.label = label;
  s.color = color;
  s.line_width = 2.0;
  for (std::size_t i = 0; i + per <= r.time.size(); i += per) {
    double sum = 0.0;
    for (std::size_t k = i; k < i + per; ++k) sum += values[k][axis];
    s.x.push_back(0.5 * (r.time[i] + r.time[i + per - 1]) / 3600.0);
    s.y.push_back(1e3 * sum / static_cast<double>(per));
  }
  return s;
}

// The paper's left panel: every ping's x_S velocity of both runs (the same noise; the runs differ by the
// bias, under a millimetre per second, which the middle panel shows).
plot::Panel velocity_panel(const Record& full, const Record& white) {
  plot::Panel panel;
  panel.title = "Zero-velocity time series (x_S, every ping)";
  panel.x.label = "time [h]";
  panel.y.label = "measured velocity x_S [mm/s]";
  panel.legend = plot::LegendPosition::kTopRight;
  auto raw = [&](const Record& r, const std::string& label, plot::Color color) {
    plot::Series s;
    s.label = label;
    s.color = color;
    s.line_width = 1.0;
    for (std::size_t i = 0; i < r.time.size(); ++i) {
      s.x.push_back(r.time[i] / 3600.0);
      s.y.push_back(1e3 * r.velocity_S[i].x());
    }
    return s;
  };
  panel.series.push_back(raw(full, "full model (bias)", plot::palette(1)));
  panel.series.push_back(raw(white, "white noise only", plot::palette(0)));
  return panel;
}

// Window means of every S axis: the full model's follow its true bias b(t) (dashed), the white-only
// run's scatter about zero (grey).
plot::Panel mean_panel(const Record& full, const Record& white, std::size_t per, double period) {
  plot::Panel panel;
  char title[120];
  std::snprintf(title, sizeof(title), "%.3g-min means of the velocity and the true bias", per * period / 60.0);
  panel.title = title;
  panel.x.label = "time [h]";
  panel.y.label = "velocity [mm/s]";
  panel.legend = plot::LegendPosition::kTopLeft;
  static const char* kAxes[3] = {"x_S", "y_S", "z_S"};
  const plot::Color grey{160, 160, 160};
  for (int a = 0; a < 3; ++a) {
    panel.series.push_back(window_means(white, white.velocity_S, a, per, a == 0 ? "white noise only (x, y, z)" : "",
                                        grey));
  }
  const int colors[3] = {1, 2, 4};
  for (int a = 0; a < 3; ++a) {
    panel.series.push_back(window_means(full, full.velocity_S, a, per, std::string("full model ") + kAxes[a],
                                        plot::palette(colors[a])));
    plot::Series bias;
    bias.label = std::string("true bias b ") + kAxes[a];
    bias.color = plot::palette(colors[a]);
    bias.dashed = true;
    bias.line_width = 1.5;
    for (std::size_t i = 0; i < full.time.size(); i += std::max<std::size_t>(1, per / 10)) {
      bias.x.push_back(full.time[i] / 3600.0);
      bias.y.push_back(1e3 * full.bias_S[i][a]);
    }
    panel.series.push_back(bias);
  }
  return panel;
}

plot::Panel drift_panel(const Record& full, const Record& white, const ClosedForm& c, const RunFigures& full_figures) {
  plot::Panel panel;
  panel.title = "Dead-reckoned drift |p_DR - p_true|";
  panel.x.label = "time [h]";
  panel.y.label = "drift [m]";
  panel.legend = plot::LegendPosition::kTopLeft;
  // At most ~20 000 points per curve: plenty at figure resolution for curves this smooth.
  const std::size_t stride = std::max<std::size_t>(1, full.time.size() / 20000);
  auto curve = [&](const std::string& label, plot::Color color, bool dashed, double width, auto value) {
    plot::Series s;
    s.label = label;
    s.color = color;
    s.dashed = dashed;
    s.line_width = width;
    s.x.push_back(0.0);
    s.y.push_back(0.0);
    for (std::size_t i = 0; i < full.time.size(); i += stride) {
      s.x.push_back(full.time[i] / 3600.0);
      s.y.push_back(value(i));
    }
    return s;
  };
  panel.series.push_back(curve("closed form b0 t + xi0 t^2/2", plot::palette(7), true, 1.5, [&](std::size_t i) {
    return deterministic_drift(full, c.period, i + 1).norm();
  }));
  panel.series.push_back(curve("white-noise RMS sqrt(T t tr Cov)", plot::palette(2), true, 1.5,
                               [&](std::size_t i) { return c.white_rms(i + 1); }));
  panel.series.push_back(
      curve("white noise only", plot::palette(0), false, 2.0, [&](std::size_t i) { return white.error_W[i].norm(); }));
  panel.series.push_back(
      curve("full model (bias)", plot::palette(1), false, 2.0, [&](std::size_t i) { return full.error_W[i].norm(); }));
  plot::Series marks;
  marks.label = "monotonicity samples";
  marks.color = plot::palette(1);
  marks.line_width = 0.0;
  marks.marker = plot::Marker::kCircle;
  for (const Sample& s : full_figures.samples) {
    marks.x.push_back(s.time / 3600.0);
    marks.y.push_back(s.error.norm());
  }
  panel.series.push_back(marks);
  return panel;
}

}  // namespace

int main(int argc, char** argv) {
  double hours = 3.0;
  double interval_min = 10.0;
  std::optional<std::uint64_t> seed;
  bool write_record = true;
  std::string out_dir = ".";
  std::string scenario = HADAL_SOURCE_DIR "/tools/validation/scenarios/dvl_static.yaml";
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--hours", &hours, NumberRange::left_open(0.0, 100.0))
      .number("--interval", &interval_min, NumberRange::greater_than(0.0))
      .option("--seed",
              [&](const std::string& value) -> std::string {
                double x = 0.0;
                if (!parse_number(value, &x) || x < 0.0 || x != std::floor(x) || x > 9007199254740992.0) {
                  return "--seed must be a non-negative integer (got '" + value + "')";
                }
                seed = static_cast<std::uint64_t>(x);
                return "";
              })
      .text("--out", &out_dir)
      .text("--scenario", &scenario)
      .flag("--no-record", [&] { write_record = false; });
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (interval_min > 60.0 * hours) {
    return command_line.usage_error("--interval (" + json_rounded(interval_min) +
                                    " min) must not exceed the record (" + json_rounded(60.0 * hours) + " min)");
  }

  std::optional<Model> loaded = prepare_run(out_dir, scenario, kTool);
  if (!loaded) return 1;
  Model model = std::move(*loaded);
  if (seed) model.world.seed = *seed;
  const std::optional<SensorRef> found = find_sensor<ns::DvlSensor>(model);
  if (!found) {
    std::fprintf(stderr, "%s: %s: no DVL sensor in the scenario\n", kTool, scenario.c_str());
    return 1;
  }
  const int vehicle = found->vehicle, sensor = found->sensor;
  const SensorSpec& dvl_sensor = model.vehicles[vehicle].sensors[sensor];
  const ns::DvlParams& params = std::get<ns::DvlSensor::Spec>(dvl_sensor.kind).params;
  const double rate = dvl_sensor.rate_hz;
  const double period = 1.0 / rate;
  const auto ping_count = static_cast<std::size_t>(std::llround(hours * 3600.0 * rate));
  if (ping_count < 100) {
    return command_line.usage_error("--hours gives " + std::to_string(ping_count) + " pings at " +
                                    json_rounded(rate) + " Hz; at least 100 are needed");
  }
  // What remains without the bias: the same per-beam channels (white noise, quantization, any per-beam
  // processes the scenario gives them), the same everything else.
  Model white_model = model;
  std::get<ns::DvlSensor::Spec>(white_model.vehicles[vehicle].sensors[sensor].kind).params.bias = ns::DvlBiasParams{};

  const auto wall_start = std::chrono::steady_clock::now();
  Record full, white;
  try {
    full = record_dvl(model, vehicle, sensor, ping_count, "full model");
    white = record_dvl(white_model, vehicle, sensor, ping_count, "white noise only");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }
  const double interval_s = 60.0 * interval_min;
  const ClosedForm closed = closed_form(params, period, full.R_WS);
  const RunFigures full_figures = analyse(full, closed, interval_s, true);
  const RunFigures white_figures = analyse(white, closed, interval_s, false);
  double decomposition_error = 0.0;
  for (std::size_t i = 0; i < full.time.size(); ++i) {
    decomposition_error = std::max(
        decomposition_error, (full.error_W[i] - white.error_W[i] - full.bias_integral_W[i]).cwiseAbs().maxCoeff());
  }
  const std::string vehicle_name = model.vehicles[vehicle].name;
  const std::string sensor_name = dvl_sensor.name;
  const hadal::config::Preset<ns::DvlDatasheet>* preset = nullptr;
  for (const hadal::config::Preset<ns::DvlDatasheet>& sheet : ns::dvl_presets()) {
    const ns::DvlParams p = ns::dvl_params(sheet.figures, period);
    if (p.type == params.type && p.beam_tilt == params.beam_tilt && p.min_altitude == params.min_altitude &&
        p.max_altitude == params.max_altitude &&
        p.beam_velocity_noise.noise.white_noise_density == params.beam_velocity_noise.noise.white_noise_density) {
      preset = &sheet;
    }
  }
  const std::string preset_text = preset ? std::string(preset->id) : std::string("custom");

  // Figure.
  plot::Figure figure;
  char title[240];
  std::snprintf(title, sizeof(title),
                "Stationary DVL in bottom lock, %.3g h at %.3g Hz: %s, full bias model vs white noise only", hours, rate,
                preset ? std::string(preset->product).c_str() : "custom figures");
  figure.title = title;
  figure.panel_width = 640;
  figure.panel_height = 540;
  // Window means over 1/36 of the record, at least a minute.
  const auto per = static_cast<std::size_t>(
      std::llround(std::max(60.0, hours * 3600.0 / kMeanWindows) / period));
  figure.panels = {velocity_panel(full, white), mean_panel(full, white, std::min(per, ping_count), period),
                   drift_panel(full, white, closed, full_figures)};

  const std::string png = join_path(out_dir, "dvl_drift.png");
  const std::string csv = join_path(out_dir, "dvl_record.csv");
  const std::string parameters = join_path(out_dir, "dvl_parameters.json");

  // Parameters.
  const double rad_to_deg = kDegPerRad;
  JsonObject bias_json(2);
  bias_json.raw("initial_m_s", vec_exact(params.bias.initial))
      .raw("initial_stddev_m_s", json_number(params.bias.initial_sigma))
      .raw("drift_rate_m_s2", vec_exact(params.bias.drift_rate))
      .raw("drift_rate_stddev_m_s2", json_number(params.bias.drift_rate_sigma))
      .raw("random_walk_m_s_per_sqrt_s", json_number(params.bias.random_walk_density))
      .raw("drawn_turn_on_bias_S_m_s", vec_exact(full.b0_S))
      .raw("drawn_drift_rate_S_m_s2", vec_exact(full.xi0_S));
  JsonObject params_json;
  params_json.text("tool", kTool)
      .text("scenario", scenario)
      .text("vehicle", vehicle_name)
      .text("sensor", sensor_name)
      .text("preset", preset_text);
  if (preset) {
    params_json.text("preset_name", std::string(preset->product)).text("preset_source", std::string(preset->source));
  }
  params_json.raw("seed", std::to_string(model.world.seed))
      .raw("rate_hz", json_number(rate))
      .raw("physics_rate_hz", json_number(model.world.physics_rate_hz))
      .raw("hours", json_number(hours))
      .raw("pings", std::to_string(ping_count))
      .raw("beam_tilt_deg", json_rounded(params.beam_tilt * rad_to_deg, 12))
      .raw("first_beam_azimuth_deg", json_rounded(params.first_beam_azimuth * rad_to_deg, 12))
      .raw("min_altitude_m", json_number(params.min_altitude))
      .raw("max_altitude_m", json_number(params.max_altitude))
      .raw("beam_velocity_noise_density_m_s_per_sqrt_hz",
           json_number(params.beam_velocity_noise.noise.white_noise_density))
      .raw("beam_velocity_sigma_per_ping_m_s", json_number(closed.beam_sigma))
      .raw("velocity_resolution_m_s", json_number(params.beam_velocity_noise.lsb))
      .raw("bias", bias_json.str())
      .raw("R_WS", matrix_exact(full.R_WS))
      .raw("p_WS_m", vec_exact(full.p_WS0))
      .text("white_noise_only_run",
            "the same parameters with every bias term zero (initial, its stddev, drift rate, its stddev, random "
            "walk); the per-beam noise streams are shared with the full run")
      .text("record", write_record ? "dvl_record.csv: both runs, model = full / white" : "not written (--no-record)")
      .text("record_columns",
            "time_s [s], model, vx, vy, vz [m/s, sensor frame S: z along the DVL axis (down), x forward], mode "
            "(0 none, 1 bottom track, 2 water track), num_good_beams, dr_x, dr_y, dr_z [m, world ENU: dead-reckoned "
            "position minus true position], bias_x, bias_y, bias_z [m/s, S: the DVL state's bias at the ping]");

  const auto output_start = std::chrono::steady_clock::now();
  std::string error = plot::write_png(figure, png);
  if (error.empty()) error = write_text(parameters, params_json.str() + "\n");
  if (error.empty() && write_record) error = write_record_csv(full, white, csv);
  if (!error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }
  const double output_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - output_start).count();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  // Criteria.
  Criterion stationary, lock, velocity_std, white_drift, bias_closed_form, monotonic, decomposition;
  for (const Record* r : {&full, &white}) {
    stationary.check(r->max_displacement <= kStationaryDisplacement && r->max_rotation <= kStationaryRotation);
    lock.check(r->bottom_track_four_beams == r->time.size());
  }
  const Eigen::Vector3d sigma_S = closed.sigma_S();
  for (int a = 0; a < 3; ++a) {
    velocity_std.check(std::fabs(white_figures.std_S[a] / sigma_S[a] - 1.0) <= kVelocityStdTolerance);
  }
  white_drift.check(white_figures.max_normalized <= kSigmas);
  bias_closed_form.check(full_figures.max_normalized <= kSigmas);
  monotonic.check(full_figures.monotonic);
  decomposition.check(decomposition_error <= kDecompositionTolerance);
  bool all = true;
  for (const Criterion* c : {&stationary, &lock, &velocity_std, &white_drift, &bias_closed_form, &monotonic,
                             &decomposition}) {
    all = all && c->value().value_or(true);
  }
  JsonObject pass(2);
  pass.raw("stationary", stationary.json())
      .raw("bottom_lock", lock.json())
      .raw("white_noise_velocity_std", velocity_std.json())
      .raw("white_noise_drift", white_drift.json())
      .raw("bias_model_closed_form", bias_closed_form.json())
      .raw("bias_model_monotonic", monotonic.json())
      .raw("runs_differ_by_integrated_bias", decomposition.json())
      .boolean("all", all);

  const std::size_t n = full.time.size();
  JsonObject closed_json(2);
  closed_json.number("ping_period_s", period, 12)
      .number("beam_sigma_m_s", closed.beam_sigma, 12)
      .raw("sigma_v_S_m_s", vec_json(sigma_S, 9))
      .raw("sigma_v_reported_by_dvl_S_m_s", vec_json(full.reported_covariance.diagonal().cwiseSqrt(), 9))
      .raw("sigma_v_W_m_s", vec_json(closed.sigma_W(), 9))
      .raw("white_drift_std_at_end_W_m", vec_json(closed.white_std(n)))
      .number("white_drift_rms_at_end_m", closed.white_rms(n))
      .number("white_drift_rms_rate_m_per_h", closed.white_rms(n) / hours)
      .raw("drawn_turn_on_bias_S_m_s", vec_json(full.b0_S, 9))
      .raw("drawn_drift_rate_S_m_s2", vec_json(full.xi0_S, 9))
      .raw("bias_deterministic_drift_at_end_W_m", vec_json(deterministic_drift(full, period, n)))
      .number("bias_deterministic_drift_at_end_m", deterministic_drift(full, period, n).norm())
      .number("bias_random_walk_term_std_at_end_m", closed.walk_std(n))
      .raw("bias_spread_at_end_W_m", vec_json(closed.full_spread(n)));
  for (int h = 1; h <= 3; ++h) {
    const auto pings = static_cast<std::size_t>(std::llround(h * 3600.0 / period));
    const std::string key = "bias_deterministic_drift_at_" + std::to_string(h) + "h_m";
    closed_json.number(key, pings <= n ? deterministic_drift(full, period, pings).norm()
                                       : std::numeric_limits<double>::quiet_NaN());
  }

  JsonObject configured(2);
  configured.number("beam_tilt_deg", params.beam_tilt * rad_to_deg)
      .number("beam_velocity_sigma_m_s", closed.beam_sigma)
      .number("bias_initial_stddev_m_s", params.bias.initial_sigma)
      .number("bias_drift_rate_stddev_m_s2", params.bias.drift_rate_sigma)
      .number("bias_random_walk_m_s_per_sqrt_s", params.bias.random_walk_density);

  const auto steps =
      static_cast<std::size_t>(std::llround(static_cast<double>(n) * model.world.physics_rate_hz * period));
  JsonObject json;
  json.text("scenario", scenario)
      .text("vehicle", vehicle_name)
      .text("sensor", sensor_name)
      .text("preset", preset_text)
      .number("hours", hours)
      .number("rate_hz", rate)
      .raw("pings", std::to_string(n))
      .raw("seed", std::to_string(model.world.seed))
      .number("interval_min", interval_min)
      .raw("configured", configured.str())
      .raw("closed_form", closed_json.str())
      .raw("full_model", run_json(full, full_figures, period, hours, steps))
      .raw("white_noise_only", run_json(white, white_figures, period, hours, steps))
      .number("full_over_white_drift_at_end", full.error_W.back().norm() / white.error_W.back().norm(), 4)
      .number("runs_difference_minus_integrated_bias_max_m", decomposition_error, 3)
      .raw("pass", pass.str())
      .number("output_wall_time_s", output_wall, 3)
      .number("wall_time_s", wall, 3)
      .text("png", png)
      .raw("csv", write_record ? json_string(csv) : "null")
      .text("parameters", parameters);
  std::printf("%s\n", json.str().c_str());
  return 0;
}
