// hadal-validate-heading: the paper's figure "magnetometer heading" (Magnetometer Disturbance Modeling):
// magnetometer-only, tilt-compensated heading along a 3-D AUV track at 45 deg N, comparing the
// simplified fixed-reference magnetometer model with the full model (WMM2025 + hard and soft iron).
//
//   hadal-validate-heading [--seconds 600] [--rate 10] [--out DIR]
//
// No scenario and no physics: the track is kinematic, sampled at the magnetometer rate, and the
// sensor models are the library's (server/include/hadal/sensors/magnetometer.h, geomagnetic.h).
//
// Track (W = ENU at 45 N 30 W, height -500 m, date 2026-06-01; the North Atlantic, where WMM2025's
// declination is about -10 deg, so the fixed reference's "north is +y" is visibly wrong):
//   yaw(t)   = 2 pi t / 150 s + 0.35 sin(2 pi t / 47 s)     (a full turn every 150 s, swaying)
//   pitch(t) = 20 deg sin(2 pi t / 120 s)                    (REP-103: positive nose down)
//   roll(t)  = 10 deg sin(2 pi t / 37 s + 0.5)
//   p_WB' = R_WB (1.5 m/s, 0, 0)                              (forward at 1.5 m/s: a sawtooth helix
//                                                              of ~36 m radius, +-10 m in depth)
// Sensor S mounted at p_BS = (0.30, 0, 0.05) m, R_BS = I (so S's yaw is the vehicle's).
//
// Sensor models (deterministic: noise keyed by channel_key(kSeed, "auv", "magnetometer", model)):
//   full model   measure_magnetic_field: WMM2025 at the sensor's geodetic position (R_WN exact), one
//                hard-iron dipole in the vehicle (0.5 A m^2 at 0.38 m from the sensor: ~1.5 uT, a
//                thruster motor or battery pack), soft iron S_S (symmetric, +-4 % scale, 1-3 %
//                cross-coupling), white noise 30 nT/sqrt(Hz) per axis (95 nT per 10 Hz sample).
//   fixed ref.   measure_fixed_reference_field_S: B_ref_W = (0, 20 uT, 0), same white noise.
//
// Heading estimators (tilt_compensated_yaw with the true roll and pitch, as from an ideal AHRS):
//   "naive"      alpha = pi/2 (the field points to W's +y), the raw measurement: what a navigator
//                does whose magnetic model is the fixed-reference one (no declination correction,
//                no hard/soft-iron calibration).
//   "calibrated" B_cal = S_S^-1 (B_meas - S_S R_SB B_hard_B) (the hard-iron offset is constant in S and
//                is what an ellipsoid fit identifies), alpha = the azimuth of WMM2025's field at the
//                sensor's position (declination and meridian convergence): the navigator whose model
//                is the full one.
//
// Curves (README "hadal-validate-heading" explains the choice):
//   A  full-model measurements, naive estimator        -> the simplified model's error on a real vehicle
//   B  full-model measurements, calibrated estimator   -> the proposed model's error
//   C  fixed-reference measurements, naive estimator   -> what a fixed-reference simulator predicts
//                                                         (noise only: it cannot show A's errors)
// Heading is compass heading, pi/2 - yaw, in [0, 360) deg; error = estimated - true, wrapped to
// (-180, 180], positive clockwise.
//
// Writes into --out (default "."):
//   magnetometer_heading.png  left: true and estimated heading vs time (first 300 s); middle: heading
//                             error vs time; right: heading error vs true heading
//   magnetometer_heading.csv  t_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,true_heading_deg,
//                             heading_A_deg,error_A_deg,heading_B_deg,error_B_deg,heading_C_deg,error_C_deg
// and prints one JSON object (stdout): the site's field elements, and per curve mean, RMS, std and max
// |error| and the first- and second-harmonic amplitudes of the error against true heading (least
// squares e = c0 + a1 cos h + b1 sin h + a2 cos 2h + b2 sin 2h).
//
// Exit status: 0 success; 1 the WMM coefficient file does not load or an output cannot be written;
// 2 usage error.
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "hadal/sensors/geomagnetic.h"
#include "hadal/sensors/magnetometer.h"
#include "hadal/sensors/noise.h"
#include "plot.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using namespace hadal::validation;
namespace sensors = hadal::sensors;

constexpr const char* kTool = "hadal-validate-heading";
constexpr const char* kUsage =
    "usage: hadal-validate-heading [--seconds T] [--rate HZ] [--out DIR]\n"
    "  --seconds T  length of the track [s] (default 600, in [1, 86400])\n"
    "  --rate HZ    magnetometer sample rate [Hz] (default 10, in [0.1, 1000])\n"
    "  --out DIR    output directory for magnetometer_heading.{png,csv} (default .)\n"
    "Magnetometer-only tilt-compensated heading at 45 N: fixed-reference vs full model; prints JSON.\n";

constexpr std::uint64_t kSeed = 20260601;
constexpr double kLatitudeDeg = 45.0;
constexpr double kLongitudeDeg = -30.0;
constexpr double kHeight = -500.0;  // [m] (the track's z is relative to it)
constexpr double kSpeed = 1.5;      // [m/s]
constexpr double kWhiteNoiseDensity = 30e-9;  // [T/sqrt(Hz)]
constexpr double kPlotHeadingSeconds = 300.0;


double compass_deg(double yaw) {
  double h = (0.5 * kPi - yaw) * kDegPerRad;
  h = std::fmod(h, 360.0);
  if (h < 0.0) h += 360.0;
  return h;
}
double heading_error_deg(double yaw_est, double yaw_true) {
  return -sensors::wrap_angle(yaw_est - yaw_true) * kDegPerRad;
}

struct Sample {
  double t = 0.0;
  Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();
  sensors::RollPitchYaw rpy;
  double heading = 0.0;              // true compass heading [deg]
  double est[3] = {0.0, 0.0, 0.0};   // A, B, C compass heading [deg]
  double err[3] = {0.0, 0.0, 0.0};   // [deg]
};

struct Stats {
  double mean = 0.0, rms = 0.0, std = 0.0, max_abs = 0.0;
  double offset = 0.0, harmonic1 = 0.0, harmonic2 = 0.0;  // least-squares fit against true heading
};

Stats statistics(const std::vector<Sample>& samples, int k) {
  Stats s;
  const double n = static_cast<double>(samples.size());
  double sum = 0.0, sum2 = 0.0;
  Eigen::MatrixXd A(samples.size(), 5);
  Eigen::VectorXd b(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double e = samples[i].err[k];
    sum += e;
    sum2 += e * e;
    s.max_abs = std::max(s.max_abs, std::fabs(e));
    const double h = samples[i].heading / kDegPerRad;
    A.row(static_cast<Eigen::Index>(i)) << 1.0, std::cos(h), std::sin(h), std::cos(2.0 * h), std::sin(2.0 * h);
    b(static_cast<Eigen::Index>(i)) = e;
  }
  s.mean = sum / n;
  s.rms = std::sqrt(sum2 / n);
  s.std = std::sqrt(std::max(0.0, sum2 / n - s.mean * s.mean));
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
  s.offset = c(0);
  s.harmonic1 = std::hypot(c(1), c(2));
  s.harmonic2 = std::hypot(c(3), c(4));
  return s;
}

std::string stats_json(const Stats& s) {
  JsonObject o(2);
  o.number("mean_error_deg", s.mean, 4)
      .number("rms_error_deg", s.rms, 4)
      .number("std_error_deg", s.std, 4)
      .number("max_abs_error_deg", s.max_abs, 4)
      .number("fit_offset_deg", s.offset, 4)
      .number("fit_first_harmonic_amplitude_deg", s.harmonic1, 4)
      .number("fit_second_harmonic_amplitude_deg", s.harmonic2, 4);
  return o.str();
}

std::string write_csv(const std::vector<Sample>& samples, const std::string& path) {
  std::ofstream out(path);
  if (!out) return path + ": cannot open for writing";
  out << "t_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,true_heading_deg,heading_A_deg,error_A_deg,"
         "heading_B_deg,error_B_deg,heading_C_deg,error_C_deg\n";
  char line[512];
  for (const Sample& s : samples) {
    std::snprintf(line, sizeof(line),
                  "%.3f,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f\n", s.t, s.p_WB.x(),
                  s.p_WB.y(), s.p_WB.z(), s.rpy.roll * kDegPerRad, s.rpy.pitch * kDegPerRad,
                  s.rpy.yaw * kDegPerRad, s.heading, s.est[0], s.err[0], s.est[1], s.err[1], s.est[2], s.err[2]);
    out << line;
  }
  out.close();
  if (!out) return path + ": write failed";
  return {};
}

// Compass headings as a polyline broken (NaN) where they wrap through 0/360.
void add_heading_points(plot::Series& series, double t, double heading, double previous) {
  if (!series.x.empty() && std::fabs(heading - previous) > 180.0) {
    series.x.push_back(std::numeric_limits<double>::quiet_NaN());
    series.y.push_back(std::numeric_limits<double>::quiet_NaN());
  }
  series.x.push_back(t);
  series.y.push_back(heading);
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 600.0;
  double rate = 10.0;
  std::string out_dir = ".";
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--seconds", &seconds, NumberRange::closed(1.0, 86400.0))
      .number("--rate", &rate, NumberRange::closed(0.1, 1000.0))
      .text("--out", &out_dir);
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (const std::string error = ensure_directory(out_dir); !error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }
  const std::string cof = HADAL_SOURCE_DIR "/server/data/WMM2025.COF";
  const auto wall_start = std::chrono::steady_clock::now();

  std::vector<Sample> samples;
  sensors::GeomagneticElements site;
  double decimal_year = 0.0;
  double hard_iron_T = 0.0;
  Eigen::Vector3d p_min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d p_max = -p_min;
  try {
    const sensors::GeomagneticModel wmm = sensors::GeomagneticModel::load_cof(cof);
    decimal_year = sensors::decimal_year_from_date(2026, 6, 1);
    sensors::GeodeticPosition origin;
    origin.latitude_rad = kLatitudeDeg / kDegPerRad;
    origin.longitude_rad = kLongitudeDeg / kDegPerRad;
    origin.height_m = kHeight;
    const sensors::LocalEnuFrame frame_W(origin);
    site = wmm.field(origin.latitude_rad, origin.longitude_rad, origin.height_m, decimal_year);

    sensors::NoiseTriadParams noise;
    for (sensors::AxisNoiseParams& axis : noise.axes) axis.white_noise_density = kWhiteNoiseDensity;

    sensors::MagnetometerParams full;
    sensors::MagneticDipole hard;
    hard.p_FD = Eigen::Vector3d(-0.05, 0.10, -0.05);
    hard.m_F = Eigen::Vector3d(0.30, -0.20, -0.35);
    hard.radius = 0.05;
    full.dipoles_B.push_back(hard);
    full.soft_iron_S << 1.04, 0.03, 0.01,  //
        0.03, 0.97, -0.02,                  //
        0.01, -0.02, 1.01;
    full.noise = noise;
    sensors::FixedReferenceMagnetometerParams fixed;
    fixed.noise = noise;

    Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();
    X_BS.translation() = Eigen::Vector3d(0.30, 0.0, 0.05);
    const Eigen::Matrix3d R_BS = X_BS.linear();
    // The calibration a navigator identifies (ellipsoid fit): hard-iron offset in S and S_S.
    const Eigen::Vector3d B_hard_B = sensors::dipoles_field_T(full.dipoles_B, X_BS.translation());
    hard_iron_T = B_hard_B.norm();
    const Eigen::Vector3d hard_offset_S = full.soft_iron_S * (R_BS.transpose() * B_hard_B);
    const Eigen::Matrix3d soft_inverse = full.soft_iron_S.inverse();

    sensors::MagnetometerState full_state = sensors::make_magnetometer_state(
        full, sensors::channel_key(kSeed, "auv", "magnetometer", "full_model"));
    sensors::NoiseTriadState fixed_state = sensors::make_noise_state(
        fixed.noise, sensors::channel_key(kSeed, "auv", "magnetometer", "fixed_reference"));

    const double dt = 1.0 / rate;
    const auto n = static_cast<std::size_t>(std::floor(seconds * rate + 1e-9)) + 1;
    samples.reserve(n);
    Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) * dt;
      sensors::RollPitchYaw rpy;
      rpy.yaw = sensors::wrap_angle(2.0 * kPi * t / 150.0 + 0.35 * std::sin(2.0 * kPi * t / 47.0));
      rpy.pitch = 20.0 / kDegPerRad * std::sin(2.0 * kPi * t / 120.0);
      rpy.roll = 10.0 / kDegPerRad * std::sin(2.0 * kPi * t / 37.0 + 0.5);
      Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
      X_WB.linear() = sensors::rotation_from_roll_pitch_yaw(rpy);
      X_WB.translation() = p_WB;
      const Eigen::Matrix3d R_WS = X_WB.linear() * R_BS;
      const sensors::RollPitchYaw rpy_S = sensors::roll_pitch_yaw(R_WS);
      const Eigen::Vector3d p_WS = X_WB * X_BS.translation();

      const sensors::MagneticFieldSample m = sensors::measure_magnetic_field(
          full, full_state, wmm, frame_W, decimal_year, X_WB, X_BS, dt);
      const Eigen::Vector3d B_fixed = sensors::measure_fixed_reference_field_S(fixed, fixed_state, R_WS, dt);
      const Eigen::Vector3d B_cal = soft_inverse * (m.B_measured_S - hard_offset_S);
      const double alpha_wmm = sensors::field_azimuth_W(sensors::earth_field_W_T(wmm, frame_W, p_WS, decimal_year));

      const double yaw_est[3] = {
          sensors::tilt_compensated_yaw(m.B_measured_S, rpy_S.roll, rpy_S.pitch, 0.5 * kPi),
          sensors::tilt_compensated_yaw(B_cal, rpy_S.roll, rpy_S.pitch, alpha_wmm),
          sensors::tilt_compensated_yaw(B_fixed, rpy_S.roll, rpy_S.pitch, 0.5 * kPi)};
      Sample s;
      s.t = t;
      s.p_WB = p_WB;
      s.rpy = rpy_S;
      s.heading = compass_deg(rpy_S.yaw);
      for (int k = 0; k < 3; ++k) {
        s.est[k] = compass_deg(yaw_est[k]);
        s.err[k] = heading_error_deg(yaw_est[k], rpy_S.yaw);
      }
      samples.push_back(s);
      p_min = p_min.cwiseMin(p_WB);
      p_max = p_max.cwiseMax(p_WB);
      p_WB += X_WB.linear() * Eigen::Vector3d(kSpeed, 0.0, 0.0) * dt;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }
  std::fprintf(stderr, "%s: %zu samples over %.0f s\n", kTool, samples.size(), seconds);
  const Stats stats[3] = {statistics(samples, 0), statistics(samples, 1), statistics(samples, 2)};

  // Figure.
  namespace plot = hadal::validation::plot;
  const char* labels[3] = {"fixed-reference model (naive estimator, full-model data)",
                           "proposed model (calibrated, WMM azimuth)",
                           "fixed-reference simulator (its own data)"};
  const char* short_labels[3] = {"fixed-reference model", "proposed model", "fixed-ref. simulator"};
  const plot::Color colors[3] = {plot::palette(1), plot::palette(0), plot::palette(2)};
  plot::Figure figure;
  char title[200];
  std::snprintf(title, sizeof(title),
                "Magnetometer-only tilt-compensated heading at %.0f N %.0f W (D = %.1f deg, I = %.1f deg), "
                "roll +-10, pitch +-20 deg",
                kLatitudeDeg, -kLongitudeDeg, site.declination_rad * kDegPerRad, site.inclination_rad * kDegPerRad);
  figure.title = title;
  figure.panel_width = 560;
  figure.panel_height = 480;

  plot::Panel p_heading;
  p_heading.title = "Heading estimates";
  p_heading.x.label = "time [s]";
  p_heading.y.label = "compass heading [deg]";
  p_heading.y.min = 0.0;
  p_heading.y.max = 360.0;
  p_heading.x.min = 0.0;
  p_heading.x.max = std::min(seconds, kPlotHeadingSeconds);
  p_heading.legend = plot::LegendPosition::kTopLeft;
  plot::Series truth;
  truth.label = "true";
  truth.color = plot::palette(7);
  truth.line_width = 3.0;
  plot::Series est[2];
  for (int k = 0; k < 2; ++k) {
    est[k].label = short_labels[k];
    est[k].color = colors[k];
    est[k].line_width = 1.5;
    est[k].dashed = k == 0;
  }
  plot::Panel p_time;
  p_time.title = "Heading error vs time";
  p_time.x.label = "time [s]";
  p_time.y.label = "heading error (estimated - true) [deg]";
  p_time.x.min = 0.0;
  p_time.x.max = seconds;
  p_time.legend = plot::LegendPosition::kBottomRight;
  p_time.y.min = -10.0;  // room for the legend below the curves
  plot::Panel p_vs;
  p_vs.title = "Heading error vs true heading";
  p_vs.x.label = "true compass heading [deg]";
  p_vs.y.label = "heading error [deg]";
  p_vs.x.min = 0.0;
  p_vs.x.max = 360.0;
  p_vs.legend = plot::LegendPosition::kBottomRight;
  p_vs.y.min = -10.0;
  plot::Series err_t[3], err_h[3];
  for (int k = 0; k < 3; ++k) {
    err_t[k].label = labels[k];
    err_t[k].color = err_h[k].color = colors[k];
    err_t[k].line_width = k == 2 ? 1.0 : 1.5;
    err_h[k].label = short_labels[k];
    err_h[k].line_width = 0.0;
    err_h[k].marker = plot::Marker::kCircle;
    err_h[k].marker_size = 1;
  }
  double prev_truth = 0.0, prev_est[2] = {0.0, 0.0};
  const std::size_t stride = std::max<std::size_t>(1, samples.size() / 3000);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i];
    if (s.t <= kPlotHeadingSeconds) {
      add_heading_points(truth, s.t, s.heading, prev_truth);
      prev_truth = s.heading;
      for (int k = 0; k < 2; ++k) {
        add_heading_points(est[k], s.t, s.est[k], prev_est[k]);
        prev_est[k] = s.est[k];
      }
    }
    for (int k = 0; k < 3; ++k) {
      err_t[k].x.push_back(s.t);
      err_t[k].y.push_back(s.err[k]);
      if (i % stride == 0) {
        err_h[k].x.push_back(s.heading);
        err_h[k].y.push_back(s.err[k]);
      }
    }
  }
  p_heading.series = {truth, est[0], est[1]};
  p_time.series = {err_t[0], err_t[1], err_t[2]};
  p_vs.series = {err_h[0], err_h[1], err_h[2]};
  figure.panels = {p_heading, p_time, p_vs};

  const std::string png = join_path(out_dir, "magnetometer_heading.png");
  const std::string csv = join_path(out_dir, "magnetometer_heading.csv");
  std::string error = plot::write_png(figure, png);
  if (error.empty()) error = write_csv(samples, csv);
  if (!error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  double max_roll = 0.0, max_pitch = 0.0;
  for (const Sample& s : samples) {
    max_roll = std::max(max_roll, std::fabs(s.rpy.roll));
    max_pitch = std::max(max_pitch, std::fabs(s.rpy.pitch));
  }
  JsonObject field(2);
  field.text("model", "WMM2025")
      .number("decimal_year", decimal_year, 7)
      .number("declination_deg", site.declination_rad * kDegPerRad, 5)
      .number("inclination_deg", site.inclination_rad * kDegPerRad, 5)
      .number("horizontal_intensity_nT", site.h_horizontal_nT, 6)
      .number("total_intensity_nT", site.f_total_nT, 6)
      .number("hard_iron_at_sensor_nT", hard_iron_T * 1e9, 5)
      .number("white_noise_density_nT_sqrt_hz", kWhiteNoiseDensity * 1e9, 4);
  JsonObject track(2);
  track.number("max_roll_deg", max_roll * kDegPerRad, 4)
      .number("max_pitch_deg", max_pitch * kDegPerRad, 4)
      .number("depth_range_m", p_max.z() - p_min.z(), 4)
      .number("horizontal_extent_m", (p_max - p_min).head<2>().norm(), 4)
      .number("speed_m_s", kSpeed);
  JsonObject json;
  json.number("latitude_deg", kLatitudeDeg)
      .number("longitude_deg", kLongitudeDeg)
      .number("height_m", kHeight)
      .number("seconds", seconds)
      .number("rate_hz", rate)
      .number("samples", static_cast<double>(samples.size()), 10)
      .raw("field", field.str())
      .raw("track", track.str())
      .raw("fixed_reference_model_naive_estimator_on_full_model_data", stats_json(stats[0]))
      .raw("proposed_model_calibrated_estimator", stats_json(stats[1]))
      .raw("fixed_reference_simulator_naive_estimator", stats_json(stats[2]))
      .number("wall_time_s", wall, 3)
      .text("png", png)
      .text("csv", csv);
  std::printf("%s\n", json.str().c_str());
  return 0;
}
