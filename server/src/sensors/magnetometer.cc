#include "hadal/sensors/magnetometer.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace hadal::sensors {
namespace {

[[noreturn]] void invalid(const std::string& field, const std::string& requirement, double got) {
  std::ostringstream message;
  message << field << ": " << requirement << " (got " << got << ")";
  throw std::invalid_argument(message.str());
}

void validate_dipoles(const std::vector<MagneticDipole>& dipoles, const std::string& name) {
  for (std::size_t i = 0; i < dipoles.size(); ++i) {
    const std::string prefix = name + "[" + std::to_string(i) + "].";
    const MagneticDipole& d = dipoles[i];
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(d.p_FD[k])) invalid(prefix + "position", "must be finite", d.p_FD[k]);
      if (!std::isfinite(d.m_F[k])) invalid(prefix + "moment", "must be finite", d.m_F[k]);
    }
    if (!(d.radius_m >= 0.0) || std::isinf(d.radius_m))
      invalid(prefix + "radius_m", "must be >= 0", d.radius_m);
  }
}

const GeodeticPosition& checked_origin(const GeodeticPosition& g) {
  if (!std::isfinite(g.latitude_rad) || !std::isfinite(g.longitude_rad) || !std::isfinite(g.height_m)) {
    throw std::domain_error("LocalEnuFrame: non-finite origin");
  }
  if (std::abs(g.latitude_rad) > kPi / 2) throw std::domain_error("LocalEnuFrame: origin |latitude| > pi/2");
  return g;
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
  const double a = dipole_F.radius_m;
  if (a > 0.0 && r.squaredNorm() < a * a) return kMu0Over4Pi * 2.0 * dipole_F.m_F / (a * a * a);
  return dipole_field_T(dipole_F.m_F, r);
}

Eigen::Vector3d dipoles_field_T(const std::vector<MagneticDipole>& dipoles_F, const Eigen::Vector3d& p_FQ) {
  Eigen::Vector3d B = Eigen::Vector3d::Zero();
  for (const MagneticDipole& d : dipoles_F) B += dipole_field_T(d, p_FQ);
  return B;
}

// ----- geodesy -------------------------------------------------------------------------------------

Eigen::Vector3d geodetic_to_ecef(const GeodeticPosition& g) {
  const double e2 = kWgs84EccentricitySquared;
  const double sin_lat = std::sin(g.latitude_rad), cos_lat = std::cos(g.latitude_rad);
  const double n = kWgs84SemiMajorAxis_m / std::sqrt(1.0 - e2 * sin_lat * sin_lat);
  return {(n + g.height_m) * cos_lat * std::cos(g.longitude_rad),
          (n + g.height_m) * cos_lat * std::sin(g.longitude_rad), (n * (1.0 - e2) + g.height_m) * sin_lat};
}

GeodeticPosition ecef_to_geodetic(const Eigen::Vector3d& p_ECEF) {
  if (!p_ECEF.allFinite()) throw std::domain_error("ecef_to_geodetic: non-finite point");
  // Vermeille (2002); p, q, r, s, t, u, v, w, k, D as in the paper (lengths scaled by a_e).
  const double a = kWgs84SemiMajorAxis_m;
  const double e2 = kWgs84EccentricitySquared;
  const double e4 = e2 * e2;
  const double x = p_ECEF.x(), y = p_ECEF.y(), z = p_ECEF.z();
  const double rho = std::hypot(x, y);  // distance from the polar axis
  const double p = (rho / a) * (rho / a);
  const double q = (1.0 - e2) * (z / a) * (z / a);
  const double r = (p + q - e4) / 6.0;
  if (!(r > 0.0)) throw std::domain_error("ecef_to_geodetic: point within 43 km of the Earth's centre");
  const double s = e4 * p * q / (4.0 * r * r * r);
  const double t = std::cbrt(1.0 + s + std::sqrt(s * (2.0 + s)));
  const double u = r * (1.0 + t + 1.0 / t);
  const double v = std::sqrt(u * u + e4 * q);
  const double w = e2 * (u + v - q) / (2.0 * v);
  const double k = std::sqrt(u + v + w * w) - w;
  const double d = k * rho / (k + e2);
  const double hyp = std::hypot(d, z);
  GeodeticPosition g;
  // The paper's half-angle form of atan2(z, d).
  g.latitude_rad = 2.0 * std::atan(z / (d + hyp));
  g.longitude_rad = std::atan2(y, x);  // 0 on the polar axis (atan2(0, 0) = 0)
  g.height_m = (k + e2 - 1.0) / k * hyp;
  return g;
}

Eigen::Matrix3d R_ECEF_ENU(double latitude_rad, double longitude_rad) {
  const double sl = std::sin(latitude_rad), cl = std::cos(latitude_rad);
  const double so = std::sin(longitude_rad), co = std::cos(longitude_rad);
  Eigen::Matrix3d R;
  R.col(0) << -so, co, 0.0;            // east
  R.col(1) << -sl * co, -sl * so, cl;  // north
  R.col(2) << cl * co, cl * so, sl;    // up
  return R;
}

LocalEnuFrame::LocalEnuFrame(const GeodeticPosition& origin)
    : origin_(checked_origin(origin)),
      p_ECEF_O_(geodetic_to_ecef(origin_)),
      R_ECEF_W_(R_ECEF_ENU(origin.latitude_rad, origin.longitude_rad)) {}

Eigen::Vector3d LocalEnuFrame::to_ecef(const Eigen::Vector3d& p_WQ) const {
  return p_ECEF_O_ + R_ECEF_W_ * p_WQ;
}

Eigen::Vector3d LocalEnuFrame::from_ecef(const Eigen::Vector3d& p_ECEF) const {
  return R_ECEF_W_.transpose() * (p_ECEF - p_ECEF_O_);
}

GeodeticPosition LocalEnuFrame::to_geodetic(const Eigen::Vector3d& p_WQ) const {
  return ecef_to_geodetic(to_ecef(p_WQ));
}

Eigen::Vector3d LocalEnuFrame::from_geodetic(const GeodeticPosition& position) const {
  return from_ecef(geodetic_to_ecef(position));
}

Eigen::Matrix3d LocalEnuFrame::R_WN(const GeodeticPosition& at) const {
  return R_ECEF_W_.transpose() * R_ECEF_ENU(at.latitude_rad, at.longitude_rad);
}

double LocalEnuFrame::meridian_convergence_rad(const GeodeticPosition& at) const {
  const Eigen::Vector3d north_W = R_WN(at).col(1);
  return std::atan2(-north_W.x(), north_W.y());
}

Eigen::Vector3d earth_field_W_T(const GeomagneticModel& model, const LocalEnuFrame& frame_W,
                                const Eigen::Vector3d& p_WQ, double decimal_year) {
  const GeodeticPosition g = frame_W.to_geodetic(p_WQ);
  const Eigen::Vector3d B_N =
      model.field(g.latitude_rad, g.longitude_rad, g.height_m, decimal_year).B_ENU_T();
  return frame_W.R_WN(g) * B_N;
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
