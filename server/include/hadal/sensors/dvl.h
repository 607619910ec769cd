// Doppler velocity log (DVL): one ping of a four-beam Janus DVL, from the ideal inputs the caller
// computed (the DVL's velocity, the beams' ray-cast slant ranges, the water velocity in the water-track
// layer, the sound speed) to the content of a marine_acoustic_msgs/Dvl message. A pure library: it
// reads no simulation state; parameters (DvlParams, loaded once) and state (DvlState: bias, noise and
// dropout generators; a copyable value) are separate, as everywhere in Hadal. The paper's model
// ("DVL Drift and Bias"), with the choices it leaves open made explicit:
//
// Frame S (as the message's frame): z along the DVL's axis, pointing where the transducers look (down
// for a downward-looking DVL), x forward; y = z x x (starboard when looking down). A downward DVL on a
// body B (x forward, y left, z up) has R_BS = diag(1, -1, -1).
//
// Beams (i = 1..4; index i - 1 in the arrays): unit vectors from the transducer towards the seabed,
//   d_i = (sin(theta) cos(phi_i), sin(theta) sin(phi_i), cos(theta))_S,  phi_i = phi_1 + (i - 1) 90 deg,
// theta the tilt from the DVL axis (default 30 deg), phi_1 the first beam's azimuth from x_S towards
// y_S. Default phi_1 = 45 deg: the "X" layout, no beam along the vehicle axis, the usual AUV installation
// (Teledyne RDI's instrument frame is the "+" layout, phi_1 = 0 with beam 3 forward, commonly mounted
// rotated by 45 deg). Beams are numbered by azimuth, not by a vendor's beam numbers. The four azimuths
// are built from one (cos, sin) pair by quarter turns (x, y) -> (-y, x), which round nothing, so the
// beams are exactly symmetric and, to rounding, sum_i d_i = (0, 0, 4 c) and
// D^T D = diag(2 s^2, 2 s^2, 4 c^2) (s = sin theta, c = cos theta).
//
// Bias (the paper's b(t + dt) = b(t) + xi dt, S axes [m/s]): xi is read as a drift rate xi_0 plus a
// zero-mean white rate of density K, whose exact integral over dt is K sqrt(dt) w (w ~ N(0, 1)), so
//   b(0) = b_0 + sigma_b0 w,   xi_0 = xi_fixed + sigma_xi w  (both drawn once per run, per axis),
//   b(t + dt) = b(t) + xi_0 dt + K sqrt(dt) w,
// i.e. b(t) = b(0) + xi_0 t + K W(t): a deterministic ramp when K = 0 (the closed-form test), a random
// walk of variance K^2 t (the paper's zero-mean xi; independent of how time is cut into pings) when
// xi_0 = 0. The bias steps every ping, locked or not (it lives in the instrument), before it is read.
//
// Per-beam measurement, k = c_assumed / c (sound-speed scale, below):
//   bottom track  v_i = k (v_WS_S . d_i) + b . d_i + eta_i,
//   water track   v_i = k ((v_WS_S - u_i) . d_i) + b . d_i + eta_i,
// u_i the water velocity averaged over the water-track layer along beam i (S axes), eta_i from the beam's
// noise channel (noise.h: white noise, optional per-beam bias processes, quantization, clipping), so with
// k = 1 this is the paper's (v + b) . d_i + eta_i. Each beam has its own channel states ("beamN_velocity",
// "beamN_water_velocity", "beamN_range"); every channel steps every ping whether or not its beam is used,
// so which beams return never shifts another stream.
//
// Velocity from the beams (least squares over the set G of used beams, D_G rows d_i^T):
//   v = (D_G^T D_G)^-1 D_G^T v_G,  |G| = 4: over-determined; |G| = 3: the exact 3-beam solution
//   (computed as D_G^-1 v_G, LU with partial pivoting, which does not square the conditioning);
//   |G| < 3: no solution (loss of lock). With zero noise and k = 1 this returns v + b (v - u + b in water
// track) to rounding, so aggregate and beams are consistent as the paper requires. Covariance of that
// estimator for independent beam errors of variance sigma_i^2:
//   Cov(v) = A^-1 (sum_{i in G} sigma_i^2 d_i d_i^T) A^-1,  A = D_G^T D_G,  = sigma^2 A^-1 for equal sigma,
// sigma_i^2 = N^2 / dt (the channel's white noise at this ping; noise.h) + lsb^2 / 12 (quantization, as
// uniform error). The instrument's bias and any correlated per-beam terms are not in it: the DVL reports
// its ping-to-ping precision, not its unknown bias.
//
// Bottom lock: beam i returns when the caller's slant range r_i (true distance along d_i to the seabed)
// is finite and > 0, its altitude r_i cos(theta) lies in [min_altitude, max_altitude] (the acoustic
// limits act on the physical path, so the true range decides) and the beam is not dropped (probability
// p per beam per ping, from the "dropout" stream; one uniform per beam per ping when p > 0). Bottom lock
// iff >= 3 beams return; then bottom-track mode over the returning beams.
// Water track: without bottom lock (and water_track on), beam i is usable when it is not dropped and the
// seabed does not cut the layer (no return, or r_i cos(theta) > the layer's far edge); >= 3 usable beams
// give a water-track solution (v_water_track = v_WS_S - u with a uniform current u, plus bias and noise).
// The caller averages the current over the layer: water_track_layer_points() gives where to sample it.
//
// Sound speed: a piston DVL converts the Doppler shift f_D = 2 f_0 (v . d) / c with the sound speed it
// assumes, v_meas . d = c_assumed f_D / (2 f_0) = (c_assumed / c) v . d, and a range from the two-way
// time t = 2 r / c as r_meas = c_assumed t / 2 = (c_assumed / c) r: both scale by k = c_assumed / c
// (c: the true sound speed at the transducer, which also sets the Doppler scale by Snell's law; for
// ranges it stands in for the mean along the path). assumed_sound_speed = 0 means the DVL measures c
// (sound-velocity sensor): k = 1. A phased array's beam angle follows c and cancels the error in the
// horizontal components; that is not modelled (dvl_type is reported only).
//
// Ranges and altitude: range_i = measure(k r_i) through the beam's range channel for returning beams,
// NaN otherwise; altitude along the DVL axis = mean over returning beams of range_i cos(theta) (NaN when
// none return; reported also with 1 or 2 beams, without lock).
//
// YAML keys: DvlSensor::keys() (server/src/sensors/dvl_sensor.cc).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <string_view>
#include <vector>

#include "hadal/config/preset.h"
#include "hadal/sensors/dvl_spec.h"
#include "hadal/sensors/noise.h"

namespace hadal::sensors {

inline constexpr int kDvlBeams = 4;
inline constexpr double kDvlNaN = std::numeric_limits<double>::quiet_NaN();

// marine_acoustic_msgs/Dvl constants (velocity_mode 0: no velocity this ping).
enum class DvlMode : std::uint8_t { kNone = 0, kBottomTrack = 1, kWaterTrack = 2 };


struct DvlState {
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();        // b(t), S axes [m/s]
  Eigen::Vector3d drift_rate = Eigen::Vector3d::Zero();  // xi_0 with its draw [m/s^2]
  RandomStream bias_random_walk;                         // w of K sqrt(dt) w, x, y, z in turn
  RandomStream dropout;                                  // one uniform per beam per ping (p > 0)
  std::array<NoiseChannelState, kDvlBeams> beam_velocity;
  std::array<NoiseChannelState, kDvlBeams> water_track_velocity;
  std::array<NoiseChannelState, kDvlBeams> range;

  friend bool operator==(const DvlState& a, const DvlState& b) {
    return a.bias == b.bias && a.drift_rate == b.drift_rate && a.bias_random_walk == b.bias_random_walk &&
           a.dropout == b.dropout && a.beam_velocity == b.beam_velocity &&
           a.water_track_velocity == b.water_track_velocity && a.range == b.range;
  }
  friend bool operator!=(const DvlState& a, const DvlState& b) { return !(a == b); }
};

// What the caller computed for one ping.
struct DvlPingInput {
  Eigen::Vector3d v_WS_S = Eigen::Vector3d::Zero();  // velocity of the DVL's origin over the seabed
                                                     // (world; lever arm included), S axes [m/s]
  // True slant range along beam i to the seabed (ray cast from the DVL's origin along R_WS d_i) [m];
  // NaN, inf or <= 0: no return.
  std::array<double, kDvlBeams> slant_range{};
  // Water velocity (world) averaged over the water-track layer along beam i, S axes [m/s]; .fill(u) for
  // one mean current. Read only in water track.
  std::array<Eigen::Vector3d, kDvlBeams> v_water_S{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                                   Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  double sound_speed = 1500.0;  // true sound speed at the transducer c [m/s], > 0
  double dt = 0.0;              // time since the previous ping [s], > 0 (the sample period)
};

// One ping: the content of marine_acoustic_msgs/Dvl, in S, SI units, double precision.
struct DvlPing {
  DvlMode mode = DvlMode::kNone;                                          // velocity_mode
  DvlType type = DvlType::kPiston;                                        // dvl_type
  Eigen::Vector3d velocity = Eigen::Vector3d::Constant(kDvlNaN);          // NaN without a solution
  Eigen::Matrix3d velocity_covariance = Eigen::Matrix3d::Constant(-1.0);  // -1 without a solution
  double altitude = kDvlNaN;           // mean of the returning beams' measured ranges times cos(theta)
  double course_gnd = kDvlNaN;         // atan2(v_y, v_x) [rad]
  double speed_gnd = kDvlNaN;          // hypot(v_x, v_y) [m/s]
  int num_good_beams = 0;              // beams in the solution; without one, beams with a bottom return
  double sound_speed = 0.0;            // the sound speed the DVL used, c_assumed (or c when measured)
  bool beam_ranges_valid = false;      // bottom lock
  bool beam_velocities_valid = false;  // mode != kNone
  std::array<Eigen::Vector3d, kDvlBeams> beam_unit_vec{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                                       Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};  // d_i
  std::array<double, kDvlBeams> range{};                // measured slant range [m]; NaN: no return
  std::array<double, kDvlBeams> range_covar{};          // its white variance [m^2]; -1: no return
  std::array<double, kDvlBeams> beam_quality{};         // 1 in the solution or returning, else 0
  std::array<double, kDvlBeams> beam_velocity{};        // v_i [m/s]; NaN when not in the solution
  std::array<double, kDvlBeams> beam_velocity_covar{};  // sigma_i^2 [m^2/s^2]; -1 when not in it
  std::array<bool, kDvlBeams> range_valid{};            // beam returned from the seabed
  std::array<bool, kDvlBeams> velocity_valid{};         // beam used in the velocity solution
};

// d_i for tilt theta and first azimuth phi_1 [rad] (header text).
std::array<Eigen::Vector3d, kDvlBeams> dvl_beam_unit_vectors(double beam_tilt, double first_beam_azimuth);
std::array<Eigen::Vector3d, kDvlBeams> dvl_beam_unit_vectors(const DvlParams& params);

// k = c_assumed / c, or 1 when c_assumed = 0 (measured sound speed).
double dvl_sound_speed_scale(double assumed_sound_speed, double sound_speed);

// Least-squares velocity from the beams in `use` with their variances (header text). valid = false and
// NaN / -1 fields when fewer than 3 beams are used.
struct DvlBeamSolution {
  bool valid = false;
  Eigen::Vector3d velocity = Eigen::Vector3d::Constant(kDvlNaN);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Constant(-1.0);
};
DvlBeamSolution solve_dvl_beams(const std::array<Eigen::Vector3d, kDvlBeams>& beam_unit_vec,
                                const std::array<double, kDvlBeams>& beam_velocity,
                                const std::array<bool, kDvlBeams>& use,
                                const std::array<double, kDvlBeams>& beam_variance);

// Points in S at which to sample the current for beam i (0..3): n cell centres along d_i between the
// layer's near and far edges (along the axis), p = d_i h_j / cos(theta),
// h_j = near + (j + 1/2) (far - near) / n. Average the current over them (in S axes) for v_water_S[i].
std::vector<Eigen::Vector3d> water_track_layer_points(const DvlParams& params, int beam, int n);
// Point j (0..n-1) of that list for the beam direction d_S = dvl_beam_unit_vectors(params)[beam]
// (allocation-free, for the per-ping loop).
Eigen::Vector3d water_track_layer_point(const DvlParams& params, const Eigen::Vector3d& d_S, int j, int n);

// Checks parameters (tilt in (0, pi/2), finite azimuth, 0 <= min_altitude < max_altitude, p in [0, 1],
// assumed sound speed 0 or > 0 finite, 0 <= layer near < far, finite bias figures, non-negative sigmas,
// valid noise channels); throws std::invalid_argument naming the field.
void validate(const DvlParams& params);

// The state at the start of a run for sensor `sensor` of vehicle `vehicle` (validates): channel keys
// channel_key(scenario_seed, vehicle, sensor, name) with name "bias", "dropout", "beamN_velocity",
// "beamN_water_velocity", "beamN_range" (N = 1..4); the bias draws b(0) from sub-stream "turn_on_bias",
// xi_0 from "drift_rate", its walk from "bias_random_walk" (derive_key of the "bias" key).
DvlState make_dvl_state(const DvlParams& params, std::uint64_t scenario_seed, std::string_view vehicle,
                        std::string_view sensor);

// One ping (header text): steps the bias and every channel over input.dt, decides bottom lock or water
// track, and solves the velocity. Throws std::invalid_argument for dt <= 0 or sound speed <= 0.
DvlPing dvl_ping(const DvlParams& params, DvlState& state, const DvlPingInput& input);

// ---------------------------------------------------------------------------------------------------
// Presets (docs/reference/sensors/dvl_specs.csv, the vendors' figures). Every row's fields used here (beam angle,
// altitude window, update rate, per-beam and water-track noise) carry no "unverified" mark; the rows'
// unverified long-term accuracy (a scale-factor figure) is not used.
// ---------------------------------------------------------------------------------------------------

// A data sheet's figures (a preset's, config/preset.h), in the sheet's units.
struct DvlDatasheet {
  DvlType type = DvlType::kPiston;
  double frequency_khz = 0.0;
  double beam_tilt_deg = 30.0;
  double min_altitude_m = 0.0;
  double max_altitude_m = 0.0;
  double update_hz = 0.0;
  double beam_velocity_sigma = 0.0;         // noise_beam_vel_m_s: 1-sigma per beam per ping [m/s]
  double water_track_velocity_sigma = 0.0;  // noise_water_track_m_s read per beam [m/s]; 0 = not listed
};

// Workhorse Navigator 600, Explorer 1000 (phased array), Nortek DVL1000-4000m, Nortek DVL500-300m,
// Sonardyne Syrinx 600, Water Linked A50.
const config::Presets<DvlDatasheet>& dvl_presets();

// A datasheet as parameters for a DVL sampled every sample_period_s (> 0; 1 / rate_hz of the sensor):
// per-ping sigma -> white-noise density N = sigma sqrt(T) (so each ping has std sigma at period T, as the
// pressure sensor does), tilt, altitude window, type; the water-track sigma falls back to the bottom-track
// one when the sheet lists none. Azimuth, dropout, sound speed, layer and bias keep DvlParams defaults.
DvlParams dvl_params(const DvlDatasheet& sheet, double sample_period_s);

}  // namespace hadal::sensors
