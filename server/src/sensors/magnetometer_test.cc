#include "hadal/sensors/magnetometer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace hadal::sensors {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kNanoTesla = 1e-9;
const std::string kCofPath = std::string(HADAL_SOURCE_DIR) + "/server/data/WMM2025.COF";

const GeomagneticModel& wmm() {
  static const GeomagneticModel model = GeomagneticModel::load_cof(kCofPath);
  return model;
}

Eigen::Isometry3d pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = p;
  return X;
}

Eigen::Matrix3d rpy(double roll_deg, double pitch_deg, double yaw_deg) {
  return rotation_from_roll_pitch_yaw({roll_deg * kDeg, pitch_deg * kDeg, yaw_deg * kDeg});
}

std::uint64_t bits(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// Scenario origin for the Earth-field tests: 45 N (the paper's heading test), 10 E, sea level.
const GeodeticPosition kOrigin{45.0 * kDeg, 10.0 * kDeg, 0.0};
constexpr double kYear = 2026.5;

// ----- dipoles -------------------------------------------------------------------------------------

// Tolerances for the dipole closed forms: a dozen roundings of the same quantities, so 16 eps relative.
TEST(MagneticDipoleTest, AxialFieldIsMu0MOver2PiR3) {
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, -2, 0.5).normalized()}) {
    for (double r : {0.1, 1.0, 37.0}) {
      for (double side : {1.0, -1.0}) {  // both ends of the axis: the field points along m on both
        const double m = 12.5;
        const Eigen::Vector3d B = dipole_field_T(m * axis, side * r * axis);
        const double expected = kVacuumPermeability * m / (2.0 * kPi * r * r * r);
        EXPECT_NEAR((B - expected * axis).norm(), 0.0, 16 * kEps * expected) << "r=" << r << " side=" << side;
      }
    }
  }
}

TEST(MagneticDipoleTest, EquatorialFieldIsMinusMu0MOver4PiR3) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 0.4, -1.0).normalized();
  const Eigen::Vector3d perp = axis.unitOrthogonal();
  for (double r : {0.1, 1.0, 37.0}) {
    const double m = 3.0;
    const Eigen::Vector3d B = dipole_field_T(m * axis, r * perp);
    const double expected = -kVacuumPermeability * m / (4.0 * kPi * r * r * r);
    EXPECT_NEAR((B - expected * axis).norm(), 0.0, 16 * kEps * std::abs(expected)) << "r=" << r;
  }
}

// Off-axis: B = -mu0 grad(phi_m), phi_m = (m . r) / (4 pi |r|^3) (scalar potential of a dipole), by central
// differences of step h = 1e-4 |r|: truncation (h^2 / 6) phi''' / phi' ~ 2 (h / |r|)^2 = 2e-8 relative for
// phi ~ |r|^-2, rounding eps / 1e-4 ~ 2e-12; tolerance 1e-7.
TEST(MagneticDipoleTest, GeneralDirectionIsMinusMu0GradientOfScalarPotential) {
  const Eigen::Vector3d m(1.0, -2.0, 0.7);
  const auto phi = [&](const Eigen::Vector3d& r) { return m.dot(r) / (4.0 * kPi * std::pow(r.norm(), 3)); };
  for (const Eigen::Vector3d& r : {Eigen::Vector3d(0.5, 0.2, -0.3), Eigen::Vector3d(-3.0, 1.0, 2.0)}) {
    const double h = 1e-4 * r.norm();
    Eigen::Vector3d grad;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d dk = h * Eigen::Vector3d::Unit(k);
      grad[k] = (phi(r + dk) - phi(r - dk)) / (2.0 * h);
    }
    const Eigen::Vector3d expected = -kVacuumPermeability * grad;
    EXPECT_NEAR((dipole_field_T(m, r) - expected).norm(), 0.0, 1e-7 * expected.norm());
  }
}

TEST(MagneticDipoleTest, SphereRadiusGivesUniformInteriorFieldContinuousAlongTheAxis) {
  MagneticDipole d;
  d.p_FD = Eigen::Vector3d(10.0, -5.0, 2.0);
  d.m_F = Eigen::Vector3d(0.0, 0.0, 1e4);  // a wreck-sized moment [A m^2]
  d.radius = 2.0;
  const Eigen::Vector3d inside = kMu0Over4Pi * 2.0 * d.m_F / 8.0;  // (2/3) mu0 M
  for (const Eigen::Vector3d& q : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 0.5, -1.2)}) {
    EXPECT_EQ(dipole_field_T(d, d.p_FD + q), inside);
  }
  // Outside: exactly the point dipole. On the axis at |r| = a, the outside field 2 mu0/(4 pi) m / a^3
  // equals the inside one (normal B continuous).
  const Eigen::Vector3d r_out(3.0, 1.0, -1.0);
  EXPECT_EQ(dipole_field_T(d, d.p_FD + r_out), dipole_field_T(d.m_F, r_out));
  const Eigen::Vector3d on_axis = dipole_field_T(d.m_F, Eigen::Vector3d(0.0, 0.0, 2.0));
  EXPECT_NEAR((on_axis - inside).norm(), 0.0, 16 * kEps * inside.norm());
  // A point dipole at its own position is singular.
  d.radius = 0.0;
  EXPECT_FALSE(dipole_field_T(d, d.p_FD).allFinite());
}

TEST(MagneticDipoleTest, FieldsOfSeveralDipolesAdd) {
  const std::vector<MagneticDipole> dipoles = {{Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, 5), 0.0},
                                               {Eigen::Vector3d(0, 2, 0), Eigen::Vector3d(1, 1, 0), 0.0}};
  const Eigen::Vector3d q(0.3, -0.2, 0.4);
  const Eigen::Vector3d sum = dipole_field_T(dipoles[0].m_F, q - dipoles[0].p_FD) +
                              dipole_field_T(dipoles[1].m_F, q - dipoles[1].p_FD);
  EXPECT_EQ(dipoles_field_T(dipoles, q), sum);
  EXPECT_EQ(dipoles_field_T({}, q), Eigen::Vector3d::Zero());
}

// ----- Earth field in W ----------------------------------------------------------------------------

// At the origin W and N coincide: the field is WMM's B_ENU_T (1e-6 nT: rounding only).
TEST(MagnetometerEarthFieldTest, AtTheOriginEqualsWmm) {
  for (const GeodeticPosition& origin : {kOrigin, GeodeticPosition{-33.0 * kDeg, 151.0 * kDeg, -4000.0},
                                         GeodeticPosition{89.0 * kDeg, -120.0 * kDeg, 0.0}}) {
    const LocalEnuFrame frame(origin);
    const Eigen::Vector3d B_W = earth_field_W_T(wmm(), frame, Eigen::Vector3d::Zero(), kYear);
    const Eigen::Vector3d expected =
        wmm().field(origin.latitude_rad, origin.longitude_rad, origin.height_m, kYear).B_ENU_T();
    EXPECT_NEAR((B_W - expected).norm(), 0.0, 1e-6 * kNanoTesla);
  }
}

// Away from the origin B_W is WMM at Q rotated by R_WN: same magnitude as WMM's F at Q, and the
// difference to the unrotated B_N is the header's figure: 7.5 (north) to 10 (east) nT per km of offset,
// 0.1 nT at ~10 m, ~1 uT at 100 km -- which is why no small-area approximation is used.
TEST(MagnetometerEarthFieldTest, AwayFromTheOriginIsWmmAtThePointRotatedIntoW) {
  const LocalEnuFrame frame(kOrigin);
  struct Case {
    Eigen::Vector3d p_WQ;
    double min_nT, max_nT;  // bounds on |B_N - B_W|
  };
  for (const Case& c :
       {Case{Eigen::Vector3d(7.0, 0.0, -5.0), 0.0, 0.1}, Case{Eigen::Vector3d(1e3, 0.0, -3000.0), 9.0, 11.0},
        Case{Eigen::Vector3d(0.0, 1e3, -3000.0), 7.0, 8.0},
        Case{Eigen::Vector3d(100e3, 0.0, -3000.0), 900.0, 1100.0},
        Case{Eigen::Vector3d(0.0, -100e3, -3000.0), 700.0, 800.0}}) {
    const GeodeticPosition q = frame.to_geodetic(c.p_WQ);
    const GeomagneticElements e = wmm().field(q.latitude_rad, q.longitude_rad, q.height_m, kYear);
    const Eigen::Vector3d B_W = earth_field_W_T(wmm(), frame, c.p_WQ, kYear);
    EXPECT_NEAR((B_W - frame.R_WN(q) * e.B_ENU_T()).norm(), 0.0, 1e-6 * kNanoTesla);
    EXPECT_NEAR(B_W.norm(), e.f_total_nT * kNanoTesla, 1e-6 * kNanoTesla);
    const double approximation_error_nT = (e.B_ENU_T() - B_W).norm() / kNanoTesla;
    EXPECT_GE(approximation_error_nT, c.min_nT) << c.p_WQ.transpose();
    EXPECT_LE(approximation_error_nT, c.max_nT) << c.p_WQ.transpose();
  }
}

// ----- the magnetometer ----------------------------------------------------------------------------

TEST(MagnetometerTest, HardIronDipoleInTheVehicleGivesTheClosedFormDipoleField) {
  MagnetometerParams params;
  // A thruster magnet 0.5 m ahead of the sensor with its moment along the body x axis: the sensor is on the
  // dipole's axis, B = mu0 m / (2 pi r^3) along m, whatever the vehicle's pose.
  params.dipoles_B = {{Eigen::Vector3d(0.7, 0.0, 0.1), Eigen::Vector3d(2.0, 0.0, 0.0), 0.0}};
  const Eigen::Isometry3d X_BS = pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.2, 0.0, 0.1));
  const double expected = kVacuumPermeability * 2.0 / (2.0 * kPi * 0.125);
  for (const Eigen::Isometry3d& X_WB : {pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()),
                                        pose(rpy(30, -20, 140), Eigen::Vector3d(1e3, -2e3, -3e3))}) {
    const MagneticFieldSample s = ideal_magnetic_field(params, Eigen::Vector3d::Zero(), X_WB, X_BS);
    EXPECT_NEAR((s.B_hard_B - Eigen::Vector3d(expected, 0, 0)).norm(), 0.0, 16 * kEps * expected);
    EXPECT_NEAR((s.B_ideal_S - Eigen::Vector3d(expected, 0, 0)).norm(), 0.0, 16 * kEps * expected);
  }
  // Sensor beside the magnet (equatorial plane): -mu0 m / (4 pi r^3) along m.
  const Eigen::Isometry3d X_BS_side = pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.7, -0.5, 0.1));
  const MagneticFieldSample side =
      ideal_magnetic_field(params, Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity(), X_BS_side);
  EXPECT_NEAR((side.B_hard_B - Eigen::Vector3d(-expected / 2, 0, 0)).norm(), 0.0, 16 * kEps * expected);
}

// Rotating the vehicle leaves the hard-iron part of B_S unchanged (the magnet turns with the sensor) and
// turns the Earth part as R_SW: B_S - R_SW B_earth_W is the same for every attitude (1e-15 relative).
TEST(MagnetometerTest, HardIronRotatesWithTheBodyEarthFieldDoesNot) {
  MagnetometerParams params;
  params.dipoles_B = {{Eigen::Vector3d(0.4, -0.3, 0.2), Eigen::Vector3d(0.5, 1.0, -2.0), 0.0}};
  const Eigen::Isometry3d X_BS = pose(rpy(0, 0, 90), Eigen::Vector3d(-0.1, 0.05, 0.0));
  const Eigen::Vector3d B_earth_W =
      wmm().field(kOrigin.latitude_rad, kOrigin.longitude_rad, 0.0, kYear).B_ENU_T();
  const Eigen::Vector3d hard_S =
      X_BS.linear().transpose() *
      dipole_field_T(params.dipoles_B[0].m_F, X_BS.translation() - params.dipoles_B[0].p_FD);
  for (const Eigen::Matrix3d& R_WB : {rpy(0, 0, 0), rpy(0, 0, 90), rpy(40, -30, 200), rpy(-170, 60, -45)}) {
    const Eigen::Isometry3d X_WB = pose(R_WB, Eigen::Vector3d(50.0, 20.0, -800.0));
    const MagneticFieldSample s = ideal_magnetic_field(params, B_earth_W, X_WB, X_BS);
    const Eigen::Matrix3d R_SW = (R_WB * X_BS.linear()).transpose();
    EXPECT_NEAR((s.B_ideal_S - R_SW * B_earth_W - hard_S).norm(), 0.0, 1e-15 * B_earth_W.norm());
    EXPECT_NEAR((s.B_earth_W - B_earth_W).norm(), 0.0, 0.0);
  }
  // Without the magnet the body's attitude shows as the rotated Earth field alone, which does change.
  params.dipoles_B.clear();
  const auto earth_S = [&](const Eigen::Matrix3d& R_WB) {
    return ideal_magnetic_field(params, B_earth_W, pose(R_WB, Eigen::Vector3d::Zero()), X_BS).B_ideal_S;
  };
  EXPECT_GT((earth_S(rpy(0, 0, 0)) - earth_S(rpy(0, 0, 90))).norm(), 0.5 * B_earth_W.norm());
}

// B_S = R_SW B_W with R_SW = (R_WB R_BS)^T, checked on a hand-worked case: field 20 uT north, 40 uT down;
// vehicle yawed 90 deg (facing north: body x = W y, body y = W -x), sensor mounted upside down (rolled
// 180 deg: S y = -B y, S z = -B z). Then B_B = (20, 0, -40) uT and B_S = (20, 0, 40) uT.
TEST(MagnetometerTest, SensorFrameRotationIsTransposeOfRwbRbs) {
  MagnetometerParams params;
  const Eigen::Vector3d B_W(0.0, 20e-6, -40e-6);
  const MagneticFieldSample s =
      ideal_magnetic_field(params, B_W, pose(rpy(0, 0, 90), Eigen::Vector3d(3, 4, -5)),
                           pose(rpy(180, 0, 0), Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_NEAR((s.B_ideal_S - Eigen::Vector3d(20e-6, 0.0, 40e-6)).norm(), 0.0, 1e-15 * B_W.norm());
  // A sensor yawed 90 deg in a level, east-facing vehicle: S x = W y (north), S y = W -x.
  const MagneticFieldSample t =
      ideal_magnetic_field(params, Eigen::Vector3d(5e-6, 20e-6, -40e-6), Eigen::Isometry3d::Identity(),
                           pose(rpy(0, 0, 90), Eigen::Vector3d::Zero()));
  EXPECT_NEAR((t.B_ideal_S - Eigen::Vector3d(20e-6, -5e-6, -40e-6)).norm(), 0.0, 1e-15 * B_W.norm());
}

TEST(MagnetometerTest, SoftIronIdentityLeavesTheFieldUnchangedAndActsInSensorAxes) {
  MagnetometerParams params;
  params.dipoles_B = {{Eigen::Vector3d(0.4, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 1.0), 0.0}};
  params.dipoles_W = {{Eigen::Vector3d(10.0, 0.0, -100.0), Eigen::Vector3d(0.0, 5e3, 0.0), 1.0}};
  const Eigen::Vector3d B_earth_W(1e-6, 22e-6, -43e-6);
  const Eigen::Isometry3d X_WB = pose(rpy(10, 20, 30), Eigen::Vector3d(5.0, 3.0, -98.0));
  const Eigen::Isometry3d X_BS = pose(rpy(0, 0, 45), Eigen::Vector3d(0.1, 0.0, 0.0));
  const Eigen::Matrix3d R_WS = X_WB.linear() * X_BS.linear();
  const MagneticFieldSample identity = ideal_magnetic_field(params, B_earth_W, X_WB, X_BS);
  const Eigen::Vector3d unchanged = R_WS.transpose() * (identity.B_earth_W + identity.B_world_W) +
                                    X_BS.linear().transpose() * identity.B_hard_B;
  EXPECT_EQ(identity.B_ideal_S, unchanged);
  params.soft_iron_S << 1.05, 0.02, -0.01, 0.02, 0.97, 0.03, -0.01, 0.03, 1.10;
  const MagneticFieldSample distorted = ideal_magnetic_field(params, B_earth_W, X_WB, X_BS);
  EXPECT_EQ(distorted.B_ideal_S, params.soft_iron_S * unchanged);
}

// A wreck in the world: its field at the sensor is the dipole's in W whatever the vehicle's attitude,
// and reaches the sensor as R_SW B_world_W.
TEST(MagnetometerTest, WorldDipoleFieldIsFixedInTheWorld) {
  MagnetometerParams params;
  params.dipoles_W = {{Eigen::Vector3d(100.0, 200.0, -1000.0), Eigen::Vector3d(0.0, 0.0, 1e5), 3.0}};
  const Eigen::Isometry3d X_BS = pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1.0, 0.0, 0.0));
  const Eigen::Vector3d p_WS(100.0, 190.0,
                             -1000.0);  // sensor 10 m south of the wreck, in its equatorial plane
  const double expected = -kVacuumPermeability * 1e5 / (4.0 * kPi * 1000.0);
  for (const Eigen::Matrix3d& R_WB : {rpy(0, 0, 0), rpy(0, 0, 180), rpy(15, 5, -70)}) {
    const Eigen::Isometry3d X_WB = pose(R_WB, p_WS - R_WB * X_BS.translation());
    const MagneticFieldSample s = ideal_magnetic_field(params, Eigen::Vector3d::Zero(), X_WB, X_BS);
    EXPECT_NEAR((s.B_world_W - Eigen::Vector3d(0, 0, expected)).norm(), 0.0, 16 * kEps * std::abs(expected));
    EXPECT_NEAR((s.B_ideal_S - R_WB.transpose() * s.B_world_W).norm(), 0.0, 16 * kEps * std::abs(expected));
  }
}

// The whole sample with noise off: the Earth term is earth_field_W_T at the sensor's position p_WS.
TEST(MagnetometerTest, FullSampleUsesWmmAtTheSensorPosition) {
  const LocalEnuFrame frame(kOrigin);
  MagnetometerParams params;
  params.dipoles_B = {{Eigen::Vector3d(-0.5, 0.0, 0.0), Eigen::Vector3d(0.3, 0.0, 0.0), 0.0}};
  MagnetometerState state = make_magnetometer_state(params, 1);
  const Eigen::Isometry3d X_WB = pose(rpy(5, -10, 60), Eigen::Vector3d(20e3, -35e3, -4000.0));
  const Eigen::Isometry3d X_BS = pose(rpy(0, 0, -90), Eigen::Vector3d(0.8, 0.0, 0.2));
  const MagneticFieldSample s = measure_magnetic_field(params, state, wmm(), frame, kYear, X_WB, X_BS, 0.01);
  const Eigen::Vector3d B_earth_W = earth_field_W_T(wmm(), frame, X_WB * X_BS.translation(), kYear);
  EXPECT_EQ(s.B_earth_W, B_earth_W);
  EXPECT_EQ(s.B_ideal_S, ideal_magnetic_field(params, B_earth_W, X_WB, X_BS).B_ideal_S);
  EXPECT_EQ(s.B_measured_S, s.B_ideal_S);  // no noise configured
}

MagnetometerParams noisy_params() {
  MagnetometerParams params;
  for (AxisNoiseParams& axis : params.noise.axes) {
    axis.white_noise_density = 10e-9;  // 10 nT/sqrt(Hz)
    axis.gauss_markov = {{20e-9, 100.0}};
    axis.turn_on_bias_sigma = 50e-9;
  }
  params.noise.lsb = 1e-9;
  params.noise.min = -100e-6;
  params.noise.max = 100e-6;
  return params;
}

// Same key -> bit-identical stream; another key -> a different one (docs/ARCHITECTURE.md, "Noise and random streams").
TEST(MagnetometerTest, SameSeedSameNoiseDifferentSeedDifferentNoise) {
  const MagnetometerParams params = noisy_params();
  const Eigen::Vector3d B_earth_W(1e-6, 22e-6, -43e-6);
  const auto run = [&](std::uint64_t key) {
    MagnetometerState state = make_magnetometer_state(params, key);
    std::vector<std::uint64_t> out;
    for (int i = 0; i < 500; ++i) {
      const Eigen::Isometry3d X_WB = pose(rpy(0, 0, i), Eigen::Vector3d(i, 0, -10));
      const Eigen::Vector3d B =
          measure_magnetic_field(params, state, B_earth_W, X_WB, Eigen::Isometry3d::Identity(), 0.01)
              .B_measured_S;
      for (int k = 0; k < 3; ++k) out.push_back(bits(B[k]));
    }
    return out;
  };
  const std::uint64_t key = channel_key(42, "auv", "magnetometer", "field");
  EXPECT_EQ(run(key), run(key));
  EXPECT_NE(run(key), run(channel_key(43, "auv", "magnetometer", "field")));
  EXPECT_EQ(make_magnetometer_state(params, key), make_magnetometer_state(params, key));
}

// Noise is zero-mean around the ideal value (5-sigma with the fixed seed), values sit on the LSB grid, and
// the range clips per sensor axis.
TEST(MagnetometerTest, NoiseQuantisationAndClippingActInSensorAxes) {
  MagnetometerParams params = noisy_params();
  for (AxisNoiseParams& axis : params.noise.axes) {
    axis.gauss_markov.clear();
    axis.turn_on_bias_sigma = 0.0;
  }
  params.noise.min = -40e-6;
  params.noise.max = 30e-6;
  MagnetometerState state = make_magnetometer_state(params, channel_key(7, "auv", "mag", "field"));
  const Eigen::Vector3d B_W(0.0, 20e-6, -45e-6);  // S = W: x, y inside the range, z below the minimum
  const double dt = 0.01, sigma = 10e-9 / std::sqrt(dt);
  const int n = 4000;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d B = measure_magnetic_field(params, state, B_W, Eigen::Isometry3d::Identity(),
                                                     Eigen::Isometry3d::Identity(), dt)
                                  .B_measured_S;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(B[k] / 1e-9, std::round(B[k] / 1e-9), 1e-6);
    EXPECT_EQ(B.z(), -40e-6);
    sum += B;
  }
  EXPECT_NEAR(sum.x() / n, 0.0, 5.0 * sigma / std::sqrt(n) + 0.5e-9);
  EXPECT_NEAR(sum.y() / n, 20e-6, 5.0 * sigma / std::sqrt(n) + 0.5e-9);
  // The same field along S z with the sensor turned over is clipped at the maximum instead.
  const Eigen::Vector3d B = measure_magnetic_field(params, state, B_W, Eigen::Isometry3d::Identity(),
                                                   pose(rpy(180, 0, 0), Eigen::Vector3d::Zero()), dt)
                                .B_measured_S;
  EXPECT_EQ(B.z(), 30e-6);
}

TEST(MagnetometerTest, ValidationNamesTheField) {
  MagnetometerParams params;
  params.dipoles_B = {MagneticDipole{}, MagneticDipole{}};
  params.dipoles_B[1].radius = -1.0;
  try {
    validate(params);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "dipoles_B[1].radius: must be >= 0 (got -1)");
  }
  params.dipoles_B.clear();
  params.dipoles_W = {MagneticDipole{}};
  params.dipoles_W[0].m_F.y() = NAN;
  EXPECT_THROW(validate(params), std::invalid_argument);
  params.dipoles_W.clear();
  params.soft_iron_S(1, 2) = INFINITY;
  EXPECT_THROW(make_magnetometer_state(params, 0), std::invalid_argument);
  params.soft_iron_S.setIdentity();
  params.noise.axes[0].white_noise_density = -1.0;
  EXPECT_THROW(validate(params), std::invalid_argument);
}

// ----- heading -------------------------------------------------------------------------------------

TEST(MagnetometerHeadingTest, RollPitchYawRoundTrip) {
  for (double roll : {-170.0, -40.0, 0.0, 25.0, 179.0}) {
    for (double pitch : {-89.0, -40.0, 0.0, 12.0, 80.0}) {
      for (double yaw : {-179.0, -90.0, 0.0, 33.0, 180.0}) {
        const RollPitchYaw a = roll_pitch_yaw(rpy(roll, pitch, yaw));
        EXPECT_NEAR(wrap_angle(a.roll - roll * kDeg), 0.0, 1e-12);
        EXPECT_NEAR(a.pitch, pitch * kDeg, 1e-12);
        EXPECT_NEAR(wrap_angle(a.yaw - yaw * kDeg), 0.0, 1e-12);
      }
    }
  }
  // REP-103: positive pitch puts the nose down.
  EXPECT_LT((rpy(0, 30, 0) * Eigen::Vector3d::UnitX()).z(), 0.0);
}

TEST(MagnetometerHeadingTest, WrapAngle) {
  EXPECT_DOUBLE_EQ(wrap_angle(3.0 * kPi / 2), -kPi / 2);
  EXPECT_DOUBLE_EQ(wrap_angle(-kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_angle(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_angle(0.25 - 4.0 * kPi), 0.25);
}

// Noise-free, undisturbed data: the eCompass yaw is exact at any heading for roll and pitch up to 40 deg,
// for the full WMM field at 45 N (inclination ~ 62 deg, declination ~ 4 deg) and for the fixed reference.
// Tolerance 1e-12 rad: a few roundings, amplified by F / H ~ 2.2 where the field is steep.
TEST(MagnetometerHeadingTest, TiltCompensatedYawRecoversAKnownYaw) {
  const LocalEnuFrame frame(kOrigin);
  const Eigen::Vector3d B_W = earth_field_W_T(wmm(), frame, Eigen::Vector3d::Zero(), kYear);
  const GeomagneticElements e = wmm().field(kOrigin.latitude_rad, kOrigin.longitude_rad, 0.0, kYear);
  EXPECT_GT(e.inclination_rad, 55 * kDeg);
  EXPECT_NEAR(field_azimuth_W(B_W), kPi / 2 - e.declination_rad, 1e-12);
  const FixedReferenceMagnetometerParams fixed;
  double worst = 0.0;
  for (double roll = -40.0; roll <= 40.0; roll += 10.0) {
    for (double pitch = -40.0; pitch <= 40.0; pitch += 10.0) {
      for (double yaw = -180.0; yaw < 180.0; yaw += 7.5) {
        const Eigen::Matrix3d R_WS = rpy(roll, pitch, yaw);
        const double full =
            tilt_compensated_yaw(R_WS.transpose() * B_W, roll * kDeg, pitch * kDeg, field_azimuth_W(B_W));
        const double simple =
            tilt_compensated_yaw(fixed_reference_field_S(fixed, R_WS), roll * kDeg, pitch * kDeg, kPi / 2);
        worst = std::max(
            {worst, std::abs(wrap_angle(full - yaw * kDeg)), std::abs(wrap_angle(simple - yaw * kDeg))});
      }
    }
  }
  EXPECT_LT(worst, 1e-12);
}

// What the paper's comparison shows, in closed form: an estimator that assumes the fixed reference (field
// to grid north, azimuth pi/2) reading the real field is off by the declination at every heading, and an
// uncompensated horizontal hard-iron field b (constant in the body) adds a heading-dependent error whose
// peak is asin(|b| / H) (level vehicle, |b| < H). Sampled every 0.01 deg: the peak is resolved to ~1e-8 rad.
TEST(MagnetometerHeadingTest, UnmodelledDeclinationAndHardIronGiveTheClosedFormHeadingErrors) {
  const LocalEnuFrame frame(kOrigin);
  const Eigen::Vector3d B_W = earth_field_W_T(wmm(), frame, Eigen::Vector3d::Zero(), kYear);
  const double declination = kPi / 2 - field_azimuth_W(B_W);
  for (double yaw : {-120.0, 0.0, 75.0}) {
    const Eigen::Matrix3d R_WS = rpy(20, -10, yaw);
    const double estimate = tilt_compensated_yaw(R_WS.transpose() * B_W, 20 * kDeg, -10 * kDeg, kPi / 2);
    EXPECT_NEAR(wrap_angle(estimate - yaw * kDeg), declination, 1e-12);
  }
  MagnetometerParams params;
  // Magnet 0.3 m behind the sensor, moment along body x: a horizontal body-frame field along x.
  params.dipoles_B = {{Eigen::Vector3d(-0.3, 0.0, 0.0), Eigen::Vector3d(0.1, 0.0, 0.0), 0.0}};
  const double b = kVacuumPermeability * 0.1 / (2.0 * kPi * 0.027);
  const double H = std::hypot(B_W.x(), B_W.y());
  ASSERT_LT(b, H);
  double peak = 0.0;
  for (double yaw = -180.0; yaw < 180.0; yaw += 0.01) {
    const Eigen::Isometry3d X_WB = pose(rpy(0, 0, yaw), Eigen::Vector3d::Zero());
    const Eigen::Vector3d B_S =
        ideal_magnetic_field(params, B_W, X_WB, Eigen::Isometry3d::Identity()).B_ideal_S;
    peak = std::max(
        peak, std::abs(wrap_angle(tilt_compensated_yaw(B_S, 0.0, 0.0, field_azimuth_W(B_W)) - yaw * kDeg)));
  }
  EXPECT_NEAR(peak, std::asin(b / H), 1e-6);
}

TEST(MagnetometerHeadingTest, FixedReferenceModelIsTheRotatedNorthVectorPlusNoise) {
  FixedReferenceMagnetometerParams params;
  params.horizontal_intensity_T = 25e-6;
  const Eigen::Matrix3d R_WS = rpy(10, 20, 30);
  EXPECT_EQ(fixed_reference_field_S(params, R_WS), R_WS.transpose() * Eigen::Vector3d(0.0, 25e-6, 0.0));
  for (AxisNoiseParams& axis : params.noise.axes) axis.white_noise_density = 1e-8;
  NoiseTriadState a = make_noise_state(params.noise, 5), b = make_noise_state(params.noise, 5);
  const Eigen::Vector3d m1 = measure_fixed_reference_field_S(params, a, R_WS, 0.01);
  EXPECT_EQ(m1, measure_fixed_reference_field_S(params, b, R_WS, 0.01));
  EXPECT_NE(m1, fixed_reference_field_S(params, R_WS));
  EXPECT_LT((m1 - fixed_reference_field_S(params, R_WS)).norm(), 6.0 * std::sqrt(3.0) * 1e-7);  // 6 sigma
}

}  // namespace
}  // namespace hadal::sensors
