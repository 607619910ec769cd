#include "hadal/sensors/magnetometer.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include "hadal/core/validation_error.h"

namespace hadal::sensors {
namespace {

using validation::invalid;

void validate_dipoles(const std::vector<MagneticDipole>& dipoles, const std::string& name) {
  for (std::size_t i = 0; i < dipoles.size(); ++i) {
    const std::string prefix = name + "[" + std::to_string(i) + "].";
    const MagneticDipole& d = dipoles[i];
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(d.p_FD[k])) invalid(prefix + "position", "must be finite", d.p_FD[k]);
      if (!std::isfinite(d.m_F[k])) invalid(prefix + "moment", "must be finite", d.m_F[k]);
    }
    if (!(d.radius >= 0.0) || std::isinf(d.radius))
      invalid(prefix + "radius", "must be >= 0", d.radius);
  }
}

}  // namespace

// ----- dipoles -------------------------------------------------------------------------------------

Eigen::Vector3d dipole_field_T(const Eigen::Vector3d& m_Am2, const Eigen::Vector3d& r_m) {
  const double r2 = r_m.squaredNorm();
  const double r = std::sqrt(r2);
  // mu0/(4 pi) (3 (m . r) r / r^5 - m / r^3): no normalisation of r needed.
  return kMu0Over4Pi * (3.0 * m_Am2.dot(r_m) * r_m / (r2 * r2 * r) - m_Am2 / (r2 * r));
}

Eigen::Vector3d dipole_field_T(const MagneticDipole& dipole_F, const Eigen::Vector3d& p_FQ) {
  const Eigen::Vector3d r = p_FQ - dipole_F.p_FD;
  const double a = dipole_F.radius;
  if (a > 0.0 && r.squaredNorm() < a * a) return kMu0Over4Pi * 2.0 * dipole_F.m_F / (a * a * a);
  return dipole_field_T(dipole_F.m_F, r);
}

Eigen::Vector3d dipoles_field_T(const std::vector<MagneticDipole>& dipoles_F, const Eigen::Vector3d& p_FQ) {
  Eigen::Vector3d B = Eigen::Vector3d::Zero();
  for (const MagneticDipole& d : dipoles_F) B += dipole_field_T(d, p_FQ);
  return B;
}

Eigen::Vector3d earth_field_W_T(const GeomagneticModel& model, const LocalEnuFrame& frame_W,
                                const Eigen::Vector3d& p_WQ, double decimal_year) {
  Eigen::Matrix3d R_WN;
  const GeodeticPosition g = frame_W.to_geodetic(p_WQ, &R_WN);
  const Eigen::Vector3d B_N = model.field(g.latitude_rad, g.longitude_rad, g.height_m, decimal_year).B_ENU_T();
  return R_WN * B_N;
}

// ----- magnetometer --------------------------------------------------------------------------------

void validate(const MagnetometerParams& params) {
  validate_dipoles(params.dipoles_B, "dipoles_B");
  validate_dipoles(params.dipoles_W, "dipoles_W");
  for (int i = 0; i < 9; ++i) {
    if (!std::isfinite(params.soft_iron_S(i / 3, i % 3))) {
      invalid("soft_iron_S(" + std::to_string(i / 3) + "," + std::to_string(i % 3) + ")", "must be finite",
              params.soft_iron_S(i / 3, i % 3));
    }
  }
  validate(params.noise);
}

MagnetometerState make_magnetometer_state(const MagnetometerParams& params, std::uint64_t key) {
  validate(params);
  return MagnetometerState{make_noise_state(params.noise, key)};
}

MagneticFieldSample ideal_magnetic_field(const MagnetometerParams& params, const Eigen::Vector3d& B_earth_W,
                                         const Eigen::Isometry3d& X_WB, const Eigen::Isometry3d& X_BS) {
  const Eigen::Matrix3d R_BS = X_BS.linear();
  const Eigen::Matrix3d R_WS = X_WB.linear() * R_BS;
  const Eigen::Vector3d p_WS = X_WB * X_BS.translation();
  MagneticFieldSample sample;
  sample.B_earth_W = B_earth_W;
  sample.B_world_W = dipoles_field_T(params.dipoles_W, p_WS);
  sample.B_hard_B = dipoles_field_T(params.dipoles_B, X_BS.translation());
  sample.B_ideal_S = params.soft_iron_S * (R_WS.transpose() * (sample.B_earth_W + sample.B_world_W) +
                                           R_BS.transpose() * sample.B_hard_B);
  return sample;
}

MagneticFieldSample measure_magnetic_field(const MagnetometerParams& params, MagnetometerState& state,
                                           const Eigen::Vector3d& B_earth_W, const Eigen::Isometry3d& X_WB,
                                           const Eigen::Isometry3d& X_BS, double dt) {
  MagneticFieldSample sample = ideal_magnetic_field(params, B_earth_W, X_WB, X_BS);
  sample.B_measured_S = measure(params.noise, state.noise, sample.B_ideal_S, dt);
  return sample;
}

MagneticFieldSample measure_magnetic_field(const MagnetometerParams& params, MagnetometerState& state,
                                           const GeomagneticModel& model, const LocalEnuFrame& frame_W,
                                           double decimal_year, const Eigen::Isometry3d& X_WB,
                                           const Eigen::Isometry3d& X_BS, double dt) {
  const Eigen::Vector3d p_WS = X_WB * X_BS.translation();
  return measure_magnetic_field(params, state, earth_field_W_T(model, frame_W, p_WS, decimal_year), X_WB,
                                X_BS, dt);
}

// ----- heading test --------------------------------------------------------------------------------

Eigen::Vector3d fixed_reference_field_S(const FixedReferenceMagnetometerParams& params,
                                        const Eigen::Matrix3d& R_WS) {
  return R_WS.transpose() * Eigen::Vector3d(0.0, params.horizontal_intensity_T, 0.0);
}

Eigen::Vector3d measure_fixed_reference_field_S(const FixedReferenceMagnetometerParams& params,
                                                NoiseTriadState& state, const Eigen::Matrix3d& R_WS,
                                                double dt) {
  return measure(params.noise, state, fixed_reference_field_S(params, R_WS), dt);
}

RollPitchYaw roll_pitch_yaw(const Eigen::Matrix3d& R) {
  RollPitchYaw a;
  a.roll = std::atan2(R(2, 1), R(2, 2));
  a.pitch = std::atan2(-R(2, 0), std::hypot(R(2, 1), R(2, 2)));
  a.yaw = std::atan2(R(1, 0), R(0, 0));
  return a;
}

Eigen::Matrix3d rotation_from_roll_pitch_yaw(const RollPitchYaw& a) {
  return (Eigen::AngleAxisd(a.yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(a.pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a.roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

double field_azimuth_W(const Eigen::Vector3d& B_W) { return std::atan2(B_W.y(), B_W.x()); }

double tilt_compensated_yaw(const Eigen::Vector3d& B_S, double roll, double pitch, double field_azimuth_W) {
  const double sr = std::sin(roll), cr = std::cos(roll);
  const double sp = std::sin(pitch), cp = std::cos(pitch);
  const double bh_x = cp * B_S.x() + sp * (sr * B_S.y() + cr * B_S.z());
  const double bh_y = cr * B_S.y() - sr * B_S.z();
  return wrap_angle(field_azimuth_W - std::atan2(bh_y, bh_x));
}

double wrap_angle(double angle_rad) {
  double a = std::remainder(angle_rad, 2.0 * kPi);  // [-pi, pi]
  if (a <= -kPi) a += 2.0 * kPi;
  return a;
}

}  // namespace hadal::sensors
