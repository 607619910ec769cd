#include "hadal/sensors/dvl.h"

#include <Eigen/LU>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include "hadal/core/validation_error.h"

namespace hadal::sensors {

namespace {

[[noreturn]] void invalid(const std::string& field, const std::string& requirement, double got) {
  validation::invalid("dvl: " + field, requirement, got);
}

void validate_non_negative(const char* field, double value) {
  if (!(value >= 0.0) || std::isinf(value)) invalid(field, "must be finite and >= 0", value);
}

void validate_channel(const char* field, const NoiseChannelParams& channel) {
  try {
    validate(channel);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("dvl: ") + field + ": " + e.what());
  }
}

// Per-ping variance of a channel's independent error: white noise N^2 / dt plus quantization lsb^2 / 12.
double ping_variance(const NoiseChannelParams& channel, double dt) {
  const double sigma = white_noise_sigma(channel.noise.white_noise_density, dt);
  return sigma * sigma + channel.lsb * channel.lsb / 12.0;
}

bool has_return(double slant_range) { return std::isfinite(slant_range) && slant_range > 0.0; }

std::string beam_channel(int beam, const char* what) { return "beam" + std::to_string(beam + 1) + "_" + what; }

}  // namespace

std::array<Eigen::Vector3d, kDvlBeams> dvl_beam_unit_vectors(double beam_tilt, double first_beam_azimuth) {
  const double s = std::sin(beam_tilt);
  const double c = std::cos(beam_tilt);
  const double ca = std::cos(first_beam_azimuth);
  const double sa = std::sin(first_beam_azimuth);
  // Exact quarter turns of (ca, sa) about z: (x, y) -> (-y, x).
  return {Eigen::Vector3d(s * ca, s * sa, c), Eigen::Vector3d(-(s * sa), s * ca, c),
          Eigen::Vector3d(-(s * ca), -(s * sa), c), Eigen::Vector3d(s * sa, -(s * ca), c)};
}

std::array<Eigen::Vector3d, kDvlBeams> dvl_beam_unit_vectors(const DvlParams& params) {
  return dvl_beam_unit_vectors(params.beam_tilt, params.first_beam_azimuth);
}

double dvl_sound_speed_scale(double assumed_sound_speed, double sound_speed) {
  return assumed_sound_speed > 0.0 ? assumed_sound_speed / sound_speed : 1.0;
}

DvlBeamSolution solve_dvl_beams(const std::array<Eigen::Vector3d, kDvlBeams>& beam_unit_vec,
                                const std::array<double, kDvlBeams>& beam_velocity,
                                const std::array<bool, kDvlBeams>& use,
                                const std::array<double, kDvlBeams>& beam_variance) {
  DvlBeamSolution solution;
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();      // D^T D
  Eigen::Matrix3d noise = Eigen::Matrix3d::Zero();  // D^T Sigma D
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();    // D^T v_beams
  int used = 0;
  for (int i = 0; i < kDvlBeams; ++i) {
    if (!use[i]) continue;
    const Eigen::Vector3d& d = beam_unit_vec[i];
    A += d * d.transpose();
    noise += beam_variance[i] * d * d.transpose();
    rhs += beam_velocity[i] * d;
    ++used;
  }
  if (used < 3) return solution;
  // Three beams in one plane (only possible for a degenerate geometry) leave A singular.
  const double scale = A.trace() / 3.0;
  if (!(std::abs(A.determinant()) > 1e-12 * scale * scale * scale)) return solution;
  const Eigen::Matrix3d A_inv = A.inverse();
  solution.valid = true;
  if (used == 3) {
    // Square D: solve D v = v_beams directly (cond(D), not cond(D)^2 as the normal equations).
    Eigen::Matrix3d D;
    Eigen::Vector3d y;
    for (int i = 0, row = 0; i < kDvlBeams; ++i) {
      if (!use[i]) continue;
      D.row(row) = beam_unit_vec[i].transpose();
      y[row++] = beam_velocity[i];
    }
    solution.velocity = D.partialPivLu().solve(y);
  } else {
    solution.velocity = A_inv * rhs;
  }
  const Eigen::Matrix3d covariance = A_inv * noise * A_inv;
  solution.covariance = 0.5 * (covariance + covariance.transpose());
  return solution;
}

std::vector<Eigen::Vector3d> water_track_layer_points(const DvlParams& params, int beam, int n) {
  if (beam < 0 || beam >= kDvlBeams) invalid("water_track_layer_points: beam", "must be in [0, 3]", beam);
  if (n < 1) invalid("water_track_layer_points: n", "must be >= 1", n);
  const Eigen::Vector3d d = dvl_beam_unit_vectors(params)[beam];
  std::vector<Eigen::Vector3d> points;
  points.reserve(n);
  for (int j = 0; j < n; ++j) points.push_back(water_track_layer_point(params, d, j, n));
  return points;
}

Eigen::Vector3d water_track_layer_point(const DvlParams& params, const Eigen::Vector3d& d_S, int j, int n) {
  const double cell = (params.water_track_layer_far - params.water_track_layer_near) / n;
  const double h = params.water_track_layer_near + (j + 0.5) * cell;
  return d_S * (h / std::cos(params.beam_tilt));
}

void validate(const DvlParams& params) {
  if (!(params.beam_tilt > 0.0 && params.beam_tilt < kPi / 2.0)) {
    invalid("beam_tilt", "must be in (0, pi/2) rad", params.beam_tilt);
  }
  if (!std::isfinite(params.first_beam_azimuth)) {
    invalid("first_beam_azimuth", "must be finite", params.first_beam_azimuth);
  }
  validate_non_negative("min_altitude", params.min_altitude);
  if (!(params.max_altitude > params.min_altitude) || std::isinf(params.max_altitude)) {
    invalid("max_altitude", "must be finite and > min_altitude", params.max_altitude);
  }
  if (!(params.dropout_probability >= 0.0 && params.dropout_probability <= 1.0)) {
    invalid("dropout_probability", "must be in [0, 1]", params.dropout_probability);
  }
  validate_non_negative("assumed_sound_speed", params.assumed_sound_speed);
  validate_non_negative("water_track_layer_near", params.water_track_layer_near);
  if (!(params.water_track_layer_far > params.water_track_layer_near) || std::isinf(params.water_track_layer_far)) {
    invalid("water_track_layer_far", "must be finite and > water_track_layer_near", params.water_track_layer_far);
  }
  validate_channel("beam_velocity_noise", params.beam_velocity_noise);
  validate_channel("water_track_velocity_noise", params.water_track_velocity_noise);
  validate_channel("range_noise", params.range_noise);
  if (!params.bias.initial.allFinite()) invalid("bias.initial", "must be finite", params.bias.initial.sum());
  validate_non_negative("bias.initial_sigma", params.bias.initial_sigma);
  if (!params.bias.drift_rate.allFinite()) {
    invalid("bias.drift_rate", "must be finite", params.bias.drift_rate.sum());
  }
  validate_non_negative("bias.drift_rate_sigma", params.bias.drift_rate_sigma);
  validate_non_negative("bias.random_walk_density", params.bias.random_walk_density);
}

DvlState make_dvl_state(const DvlParams& params, std::uint64_t scenario_seed, std::string_view vehicle,
                        std::string_view sensor) {
  validate(params);
  DvlState state;
  const std::uint64_t bias_key = channel_key(scenario_seed, vehicle, sensor, "bias");
  state.bias = params.bias.initial;
  if (params.bias.initial_sigma > 0.0) {
    RandomStream stream(derive_key(bias_key, "turn_on_bias"));
    for (int a = 0; a < 3; ++a) state.bias[a] += params.bias.initial_sigma * stream.normal();
  }
  state.drift_rate = params.bias.drift_rate;
  if (params.bias.drift_rate_sigma > 0.0) {
    RandomStream stream(derive_key(bias_key, "drift_rate"));
    for (int a = 0; a < 3; ++a) state.drift_rate[a] += params.bias.drift_rate_sigma * stream.normal();
  }
  state.bias_random_walk = RandomStream(derive_key(bias_key, "bias_random_walk"));
  state.dropout = RandomStream(channel_key(scenario_seed, vehicle, sensor, "dropout"));
  for (int i = 0; i < kDvlBeams; ++i) {
    state.beam_velocity[i] = make_noise_state(params.beam_velocity_noise,
                                              channel_key(scenario_seed, vehicle, sensor, beam_channel(i, "velocity")));
    state.water_track_velocity[i] =
        make_noise_state(params.water_track_velocity_noise,
                         channel_key(scenario_seed, vehicle, sensor, beam_channel(i, "water_velocity")));
    state.range[i] =
        make_noise_state(params.range_noise, channel_key(scenario_seed, vehicle, sensor, beam_channel(i, "range")));
  }
  return state;
}

DvlPing dvl_ping(const DvlParams& params, DvlState& state, const DvlPingInput& input) {
  if (!(input.dt > 0.0) || std::isinf(input.dt)) invalid("dt", "must be finite and > 0", input.dt);
  if (!(input.sound_speed > 0.0) || std::isinf(input.sound_speed)) {
    invalid("sound_speed", "must be finite and > 0", input.sound_speed);
  }
  const double dt = input.dt;
  const double k = dvl_sound_speed_scale(params.assumed_sound_speed, input.sound_speed);
  const double cos_tilt = std::cos(params.beam_tilt);

  DvlPing ping;
  ping.type = params.type;
  ping.sound_speed = params.assumed_sound_speed > 0.0 ? params.assumed_sound_speed : input.sound_speed;
  ping.beam_unit_vec = dvl_beam_unit_vectors(params);

  // Bias: b += xi_0 dt + K sqrt(dt) w, stepped before it is read.
  state.bias += state.drift_rate * dt;
  if (params.bias.random_walk_density > 0.0) {
    for (int a = 0; a < 3; ++a) {
      state.bias[a] =
          bias_random_walk_step(params.bias.random_walk_density, state.bias[a], dt, state.bias_random_walk.normal());
    }
  }

  std::array<bool, kDvlBeams> dropped{};
  if (params.dropout_probability > 0.0) {
    for (int i = 0; i < kDvlBeams; ++i) dropped[i] = state.dropout.uniform() < params.dropout_probability;
  }

  // Every channel steps every ping; each beam's bottom- and water-track measurement and range.
  std::array<double, kDvlBeams> bottom_velocity{};
  std::array<double, kDvlBeams> water_velocity{};
  std::array<double, kDvlBeams> measured_range{};
  std::array<bool, kDvlBeams> bottom_return{};
  std::array<bool, kDvlBeams> water_usable{};
  int bottom_returns = 0;
  int water_beams = 0;
  for (int i = 0; i < kDvlBeams; ++i) {
    const Eigen::Vector3d& d = ping.beam_unit_vec[i];
    const double bias_along = state.bias.dot(d);
    bottom_velocity[i] =
        measure(params.beam_velocity_noise, state.beam_velocity[i], k * input.v_WS_S.dot(d) + bias_along, dt);
    water_velocity[i] = measure(params.water_track_velocity_noise, state.water_track_velocity[i],
                                k * (input.v_WS_S - input.v_water_S[i]).dot(d) + bias_along, dt);
    const double r = input.slant_range[i];
    const bool echo = has_return(r);
    measured_range[i] = measure(params.range_noise, state.range[i], echo ? k * r : 0.0, dt);
    const double altitude = echo ? r * cos_tilt : 0.0;
    bottom_return[i] = echo && altitude >= params.min_altitude && altitude <= params.max_altitude && !dropped[i];
    water_usable[i] = !dropped[i] && (!echo || altitude > params.water_track_layer_far);
    bottom_returns += bottom_return[i];
    water_beams += water_usable[i];
  }

  const double range_variance = ping_variance(params.range_noise, dt);
  double altitude_sum = 0.0;
  for (int i = 0; i < kDvlBeams; ++i) {
    ping.range_valid[i] = bottom_return[i];
    ping.range[i] = bottom_return[i] ? measured_range[i] : kDvlNaN;
    ping.range_covar[i] = bottom_return[i] ? range_variance : -1.0;
    if (bottom_return[i]) altitude_sum += measured_range[i] * cos_tilt;
  }
  if (bottom_returns > 0) ping.altitude = altitude_sum / bottom_returns;
  ping.beam_ranges_valid = bottom_returns >= 3;

  const std::array<double, kDvlBeams>* beam_velocity = nullptr;
  const std::array<bool, kDvlBeams>* use = nullptr;
  double beam_variance = 0.0;
  if (bottom_returns >= 3) {
    ping.mode = DvlMode::kBottomTrack;
    beam_velocity = &bottom_velocity;
    use = &bottom_return;
    beam_variance = ping_variance(params.beam_velocity_noise, dt);
  } else if (params.water_track && water_beams >= 3) {
    ping.mode = DvlMode::kWaterTrack;
    beam_velocity = &water_velocity;
    use = &water_usable;
    beam_variance = ping_variance(params.water_track_velocity_noise, dt);
  }

  ping.num_good_beams = bottom_returns;
  ping.beam_velocity.fill(kDvlNaN);
  ping.beam_velocity_covar.fill(-1.0);
  if (use != nullptr) {
    std::array<double, kDvlBeams> variances;
    variances.fill(beam_variance);
    const DvlBeamSolution solution = solve_dvl_beams(ping.beam_unit_vec, *beam_velocity, *use, variances);
    if (solution.valid) {
      ping.velocity = solution.velocity;
      ping.velocity_covariance = solution.covariance;
      ping.course_gnd = std::atan2(solution.velocity.y(), solution.velocity.x());
      ping.speed_gnd = std::hypot(solution.velocity.x(), solution.velocity.y());
      ping.beam_velocities_valid = true;
      ping.num_good_beams = 0;
      for (int i = 0; i < kDvlBeams; ++i) {
        if (!(*use)[i]) continue;
        ping.velocity_valid[i] = true;
        ping.beam_velocity[i] = (*beam_velocity)[i];
        ping.beam_velocity_covar[i] = beam_variance;
        ++ping.num_good_beams;
      }
    } else {
      ping.mode = DvlMode::kNone;
    }
  }
  for (int i = 0; i < kDvlBeams; ++i) {
    ping.beam_quality[i] = (ping.velocity_valid[i] || ping.range_valid[i]) ? 1.0 : 0.0;
  }
  return ping;
}

// --- presets --------------------------------------------------------------------------------------------

const config::Presets<DvlDatasheet>& dvl_presets() {
  // The rows' figures as written; dvl_test.cc recomputes every preset from the CSV.
  static const config::Presets<DvlDatasheet> presets = {
      {.id = "teledyne_workhorse_navigator_600",
       .product = "Teledyne RDI Workhorse Navigator 600",
       .source = "dvl_specs.csv (Janus piston 4-beam); no water-track figure. The row's 1200/300 kHz variants are "
                 "unverified and not presets",
       .figures = {.frequency_khz = 600.0,
                   .beam_tilt_deg = 30.0,
                   .min_altitude_m = 0.7,
                   .max_altitude_m = 90.0,
                   .update_hz = 7.0,
                   .beam_velocity_sigma = 0.005}},
      {.id = "teledyne_explorer_1000",
       .product = "Teledyne RDI Explorer 1000 (phased array)",
       .source = "dvl_specs.csv; ~614 kHz; 12 Hz (the row's note: the vendor publishes \"up to 25 Hz\"); no "
                 "water-track figure",
       .figures = {.type = DvlType::kPhasedArray,
                   .frequency_khz = 614.0,
                   .beam_tilt_deg = 30.0,
                   .min_altitude_m = 0.5,
                   .max_altitude_m = 81.0,
                   .update_hz = 12.0,
                   .beam_velocity_sigma = 0.018}},
      {.id = "nortek_dvl1000_4000m",
       .product = "Nortek DVL1000-4000m",
       .source = "dvl_specs.csv",
       .figures = {.frequency_khz = 1000.0,
                   .beam_tilt_deg = 25.0,
                   .min_altitude_m = 0.2,
                   .max_altitude_m = 75.0,
                   .update_hz = 8.0,
                   .beam_velocity_sigma = 0.005,
                   .water_track_velocity_sigma = 0.015}},
      {.id = "nortek_dvl500_300m",
       .product = "Nortek DVL500-300m",
       .source = "dvl_specs.csv",
       .figures = {.frequency_khz = 500.0,
                   .beam_tilt_deg = 25.0,
                   .min_altitude_m = 0.3,
                   .max_altitude_m = 200.0,
                   .update_hz = 8.0,
                   .beam_velocity_sigma = 0.005,
                   .water_track_velocity_sigma = 0.015}},
      {.id = "sonardyne_syrinx_600",
       .product = "Sonardyne Syrinx 600",
       .source = "dvl_specs.csv; 10 Hz (published ping rate up to 25 Hz)",
       .figures = {.frequency_khz = 600.0,
                   .beam_tilt_deg = 30.0,
                   .min_altitude_m = 0.4,
                   .max_altitude_m = 175.0,
                   .update_hz = 10.0,
                   .beam_velocity_sigma = 0.0022,
                   .water_track_velocity_sigma = 0.0044}},
      {.id = "water_linked_a50",
       .product = "Water Linked A50 (ROV-class reference)",
       .source = "dvl_specs.csv, from maximilian-nitsch/DVL-Simulator config/waterlinked_a50.yaml @5a6035ae (not a "
                 "vendor sheet)",
       .figures = {.frequency_khz = 1000.0,
                   .beam_tilt_deg = 22.5,
                   .min_altitude_m = 0.05,
                   .max_altitude_m = 50.0,
                   .update_hz = 5.0,
                   .beam_velocity_sigma = 0.01}},
  };
  return presets;
}

DvlParams dvl_params(const DvlDatasheet& sheet, double sample_period_s) {
  if (!(sample_period_s > 0.0) || std::isinf(sample_period_s)) {
    invalid("sample_period_s", "must be finite and > 0", sample_period_s);
  }
  DvlParams params;
  params.type = sheet.type;
  params.beam_tilt = sheet.beam_tilt_deg * kPi / 180.0;
  params.min_altitude = sheet.min_altitude_m;
  params.max_altitude = sheet.max_altitude_m;
  const double root_period = std::sqrt(sample_period_s);
  params.beam_velocity_noise.noise.white_noise_density = sheet.beam_velocity_sigma * root_period;
  const double water_sigma =
      sheet.water_track_velocity_sigma > 0.0 ? sheet.water_track_velocity_sigma : sheet.beam_velocity_sigma;
  params.water_track_velocity_noise.noise.white_noise_density = water_sigma * root_period;
  return params;
}

}  // namespace hadal::sensors
