// Three-axis magnetometer model (sensor_msgs/MagneticField, tesla): the paper's "Magnetometer
// Disturbance Modeling" chain as a pure library the magnetometer sensor calls once per sample.
//
//   B_earth_W = R_WN WMM(lat, lon, h, t)                       Earth's main field at the sensor, in W
//   B_world_W = sum_D dipole(m_W, p_WS - p_WD)                  static world dipoles (wrecks, pipelines)
//   B_hard_B  = sum_D dipole(m_B, p_BS - p_BD)                  hard iron: dipoles fixed in the vehicle
//   B_ideal_S = S_S (R_SW (B_earth_W + B_world_W) + R_SB B_hard_B)       soft iron S_S in sensor axes
//   B_meas_S  = clip(quantize(M (I + diag(s)) B_ideal_S + b + n))        sensors/noise.h, per sensor axis
//   R_SW = (R_WB R_BS)^T,  p_WS = p_WB + R_WB p_BS.
//
// Frames (docs/ARCHITECTURE.md, "Model and state"): W world (ENU at the scenario origin), B body, S
// sensor, N the local geodetic East-North-Up frame at the sensor's position (WMM's frame there).
//
// Dipole field. A point dipole of moment m [A m^2] at offset r [m] from it (r = field point - dipole):
//   B(r) = mu0 / (4 pi) (3 (m . r_hat) r_hat - m) / |r|^3   [T],
// on the axis (r || m) mu0 m / (2 pi r^3), in the equatorial plane (r perp m) -mu0 m / (4 pi r^3).
// A point dipole is singular at r = 0; a dipole may instead be given a radius a > 0 and is then a
// uniformly magnetised sphere: exactly the dipole field outside (|r| >= a) and the uniform field
// (2/3) mu0 M = mu0 / (4 pi) 2 m / a^3 inside (M = m / (4/3 pi a^3)), so a vehicle passing through a
// wreck's dipole reads a large but finite field (the normal component is continuous at |r| = a). A point
// dipole (a = 0) evaluated at its own position gives a non-finite field (the simulation's NaN check
// then reports it): the loader should reject a vehicle dipole of radius 0 at a magnetometer's position.
// mu0 = 1.25663706212e-6 N/A^2 (CODATA 2018; 4 pi 1e-7 up to 5.5e-10 relative, no longer exact).
//
// Earth field at a point Q of W. WMM gives the field in N, the local ENU frame at Q, which is W's frame
// only at the origin: B_earth_W = R_WN B_N, with Q's geodetic position and R_WN from the one geodesy of W
// (sensors/geodesy.h, GeographicLib's LocalCartesian, which GPS fixes use too),
// and B_earth_W = R_WN B_N is evaluated exactly. No small-area approximation (using B_N as if it were in
// W) is good to 0.1 nT over a scenario: at 45 N the tilt moves the ~42 uT vertical field by 1.57e-4 rad/km
// (7.5 nT per km north-south; with the convergence 10 nT per km east-west), so the approximation holds to
// 0.1 nT only within ~10 m of the origin and misses by ~1 uT at 100 km (magnetometer_test.cc).
// A property of the tangent-plane mapping to know about: W's horizontal plane leaves the ellipsoid as
// d^2 / (2 R) (0.08 m at 1 km, 7.8 m at 10 km, 785 m at 100 km), so a point at constant z far from the
// origin maps to a greater ellipsoidal height; the field's vertical gradient (~3 F / r = 0.02 nT/m)
// turns that into ~18 nT at 100 km (0.18 nT at 10 km) -- small beside WMM's own O(100 nT) error; GPS
// uses the same mapping, so both sensors agree on where the vehicle is.
//
// Soft iron. S_S acts in the sensor's axes, the frame a magnetometer calibration (ellipsoid fit)
// identifies it in; soft iron is the vehicle's induced magnetisation, fixed in the vehicle like S, so a
// constant S_S is physical. A matrix S_B known in body axes becomes S_S = R_SB S_B R_BS. As the paper's
// B_dist = S (B_earth + B_HI), S acts on the hard-iron field too (and on the world dipoles' field, which
// is external field like the Earth's). S = I leaves the field unchanged.
//
// Noise and order of operations. The paper adds noise, clips, then rotates into the sensor frame; here
// the field is first expressed in S and noise and clipping act per sensor axis, which is where a sensor's
// range and its noise figures are defined (rotation does not change isotropic white noise, and clipping
// only makes sense per physical axis). The noise triad (sensors/noise.h, unit tesla) also models the
// sensor's own axis misalignment and scale factor, biases (a residual hard iron after calibration is a
// turn-on bias), Gauss-Markov drift, quantisation (LSB) and range.
//
// Heading. tilt_compensated_yaw is the standard eCompass de-rotation (e.g. Freescale AN4248, there in NED)
// written for REP-103 frames: with R_WS = Rz(yaw) Ry(pitch) Rx(roll), levelling the measurement,
//   B_h = Ry(pitch) Rx(roll) B_S = Rz(yaw)^T B_W,
//   B_h,x = cos(pitch) B_x + sin(pitch) (sin(roll) B_y + cos(roll) B_z),
//   B_h,y = cos(roll) B_y - sin(roll) B_z,
//   yaw = alpha - atan2(B_h,y, B_h,x),
// alpha the azimuth of the horizontal field in W (atan2(B_W,y, B_W,x), counter-clockwise from east:
// pi/2 - D for declination D, pi/2 for the fixed-reference model). Exact for noise-free data at any roll
// and |pitch| < 90 deg (undefined where the horizontal field vanishes, at the magnetic dip poles); the
// result is yaw in W (ENU: 0 = facing east, compass heading = pi/2 - yaw).
// The paper's comparison model is the fixed-reference magnetometer (HoloOcean's): a constant horizontal
// reference field toward W's +y (north at the origin), no inclination, no hard or soft iron:
//   B_S = R_SW B_ref_W + noise,  B_ref_W = (0, B_ref, 0).
//
// Model / state split (docs/ARCHITECTURE.md, "Model and state"): MagnetometerParams is loaded once; MagnetometerState (the noise
// triad's draws and generator states) is a copyable value in SimState. YAML keys belong to the loader
// (the magnetometer's sensor spec); everything here is SI: m, A m^2, T.
//
// Cost: one sample is one WMM synthesis (~0.7 us, geomagnetic.h), one local-cartesian -> geodetic
// conversion with its rotation (GeographicLib) and ~20 flops per dipole.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

#include "hadal/sensors/geodesy.h"
#include "hadal/sensors/magnetic_dipole.h"
#include "hadal/sensors/magnetometer_spec.h"
#include "hadal/sensors/geomagnetic.h"
#include "hadal/sensors/noise.h"

namespace hadal::sensors {

// ---------------------------------------------------------------------------------------------------
// Magnetic dipoles
// ---------------------------------------------------------------------------------------------------

// Vacuum permeability mu0 [N/A^2] (CODATA 2018) and mu0 / (4 pi) [T m/A].
inline constexpr double kVacuumPermeability = 1.25663706212e-6;
inline constexpr double kMu0Over4Pi = kVacuumPermeability / (4.0 * kPi);

// Field [T] at offset r_m [m] from a point dipole of moment m_Am2 [A m^2] (both in one frame; the result
// is in that frame). Non-finite at r = 0.
Eigen::Vector3d dipole_field_T(const Eigen::Vector3d& m_Am2, const Eigen::Vector3d& r_m);

// A dipole D fixed in a frame F (sensors/magnetic_dipole.h).
// Field [T] of one dipole at the point Q (p_FQ in F), expressed in F.
Eigen::Vector3d dipole_field_T(const MagneticDipole& dipole_F, const Eigen::Vector3d& p_FQ);
// Sum over dipoles, expressed in F.
Eigen::Vector3d dipoles_field_T(const std::vector<MagneticDipole>& dipoles_F, const Eigen::Vector3d& p_FQ);

// Earth's main field [T] at Q, in W's axes: R_WN * model.field(geodetic of Q, decimal_year).B_ENU_T().
// Throws as GeomagneticModel::field (year outside the model's validity) and ecef_to_geodetic.
Eigen::Vector3d earth_field_W_T(const GeomagneticModel& model, const LocalEnuFrame& frame_W,
                                const Eigen::Vector3d& p_WQ, double decimal_year);

// ---------------------------------------------------------------------------------------------------
// The magnetometer
// ---------------------------------------------------------------------------------------------------

struct MagnetometerState {
  NoiseTriadState noise;

  friend bool operator==(const MagnetometerState& a, const MagnetometerState& b) {
    return a.noise == b.noise;
  }
  friend bool operator!=(const MagnetometerState& a, const MagnetometerState& b) { return !(a == b); }
};

// Finite dipole positions and moments, radius >= 0 and finite, finite S, valid noise (noise.h);
// throws std::invalid_argument naming the field, e.g. "dipoles_B[1].radius: must be >= 0 (got -1)".
void validate(const MagnetometerParams& params);
// Validates, then draws the noise triad's turn-on errors for the channel key (noise.h channel_key).
MagnetometerState make_magnetometer_state(const MagnetometerParams& params, std::uint64_t key);

// The ideal terms of one sample [T] (for diagnostics and figures) and the measurement.
struct MagneticFieldSample {
  Eigen::Vector3d B_earth_W = Eigen::Vector3d::Zero();  // Earth's field at the sensor
  Eigen::Vector3d B_world_W = Eigen::Vector3d::Zero();  // world dipoles at the sensor
  Eigen::Vector3d B_hard_B = Eigen::Vector3d::Zero();   // vehicle dipoles at the sensor
  Eigen::Vector3d B_ideal_S = Eigen::Vector3d::Zero();  // S_S (R_SW (B_earth_W + B_world_W) + R_SB B_hard_B)
  Eigen::Vector3d B_measured_S = Eigen::Vector3d::Zero();  // after noise, quantisation and clipping
};

// B_ideal_S for a given Earth field at the sensor (B_earth_W, e.g. from earth_field_W_T at p_WS, or
// zero to see the disturbances alone), vehicle pose X_WB and mounting X_BS. Fills every field of the
// sample but B_measured_S.
MagneticFieldSample ideal_magnetic_field(const MagnetometerParams& params, const Eigen::Vector3d& B_earth_W,
                                         const Eigen::Isometry3d& X_WB, const Eigen::Isometry3d& X_BS);
// ideal_magnetic_field, then the noise chain over dt > 0 [s] (steps `state`).
MagneticFieldSample measure_magnetic_field(const MagnetometerParams& params, MagnetometerState& state,
                                           const Eigen::Vector3d& B_earth_W, const Eigen::Isometry3d& X_WB,
                                           const Eigen::Isometry3d& X_BS, double dt);
// The whole sample: Earth field from the model at p_WS and decimal_year, then measure_magnetic_field.
MagneticFieldSample measure_magnetic_field(const MagnetometerParams& params, MagnetometerState& state,
                                           const GeomagneticModel& model, const LocalEnuFrame& frame_W,
                                           double decimal_year, const Eigen::Isometry3d& X_WB,
                                           const Eigen::Isometry3d& X_BS, double dt);

// ---------------------------------------------------------------------------------------------------
// Heading test (the paper's Fig. "magnetometer heading"): fixed-reference model and eCompass yaw
// ---------------------------------------------------------------------------------------------------

// The fixed-reference magnetometer: B_ref_W = (0, horizontal_intensity_T, 0), no disturbances.
struct FixedReferenceMagnetometerParams {
  double horizontal_intensity_T = 2.0e-5;  // a round mid-latitude figure (WMM2025 H at 45 N 0 E: 23.1 uT)
  NoiseTriadParams noise;                  // [T]
};
// R_SW B_ref_W.
Eigen::Vector3d fixed_reference_field_S(const FixedReferenceMagnetometerParams& params,
                                        const Eigen::Matrix3d& R_WS);
// fixed_reference_field_S, then the noise chain over dt > 0 (a NoiseTriadState from make_noise_state).
Eigen::Vector3d measure_fixed_reference_field_S(const FixedReferenceMagnetometerParams& params,
                                                NoiseTriadState& state, const Eigen::Matrix3d& R_WS,
                                                double dt);

// Z-Y-X (yaw, pitch, roll) angles of R = Rz(yaw) Ry(pitch) Rx(roll) (REP-103: roll about x forward,
// pitch about y left -- positive nose down --, yaw about z up, counter-clockwise from W's x = east).
struct RollPitchYaw {
  double roll = 0.0;   // (-pi, pi]
  double pitch = 0.0;  // [-pi/2, pi/2]
  double yaw = 0.0;    // (-pi, pi]
};
RollPitchYaw roll_pitch_yaw(const Eigen::Matrix3d& R);
Eigen::Matrix3d rotation_from_roll_pitch_yaw(const RollPitchYaw& angles);

// atan2(B_W.y, B_W.x): azimuth of the horizontal field in W, counter-clockwise from east [rad].
double field_azimuth_W(const Eigen::Vector3d& B_W);
// eCompass yaw of S in W [rad], (-pi, pi], from the measured field B_S, the sensor's roll and pitch
// (R_WS = Rz(yaw) Ry(pitch) Rx(roll)) and the azimuth of the reference field in W (header).
double tilt_compensated_yaw(const Eigen::Vector3d& B_S, double roll, double pitch, double field_azimuth_W);
// Angle wrapped to (-pi, pi] (for heading errors).
double wrap_angle(double angle_rad);

}  // namespace hadal::sensors
