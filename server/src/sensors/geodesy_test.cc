// The one WGS84 geodesy of W (sensors/geodesy.h, GeographicLib): geodetic <-> ECEF at known points and
// round trips, W <-> geodetic round trips, and the closed forms of the rotation R_WN between W and the
// local ENU frame at a point (tilt of the vertical, meridian convergence).
#include "hadal/sensors/geodesy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hadal/core/units.h"
#include "hadal/sensors/geomagnetic.h"
#include "hadal/sensors/magnetometer.h"

namespace hadal::sensors {
namespace {

constexpr double kDeg = kPi / 180.0;

// 45 N (the paper's heading test), 10 E, sea level.
const GeodeticPosition kOrigin{45.0 * kDeg, 10.0 * kDeg, 0.0};

// ----- geodesy -------------------------------------------------------------------------------------

TEST(GeodesyTest, GeodeticToEcefKnownPoints) {
  const double a = kWgs84SemiMajorAxis_m;
  const double b = a * (1.0 - kWgs84Flattening);
  EXPECT_NEAR((geodetic_to_ecef({0.0, 0.0, 0.0}) - Eigen::Vector3d(a, 0, 0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((geodetic_to_ecef({0.0, 90 * kDeg, 100.0}) - Eigen::Vector3d(0, a + 100, 0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((geodetic_to_ecef({90 * kDeg, 0.3, 0.0}) - Eigen::Vector3d(0, 0, b)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((geodetic_to_ecef({-90 * kDeg, 0.0, -500.0}) - Eigen::Vector3d(0, 0, -b + 500)).norm(), 0.0,
              1e-9);
}

// geodetic -> ECEF -> geodetic over the globe (poles, equator, a longitude sweep) and heights from the
// Mariana trench to the WMM's 850 km ceiling. Tolerances: rounding of ~20 operations on ~6.4e6 m values,
// 20 eps 6.4e6 m = 3e-8 m and that over the Earth's radius in angle (5e-15 rad); the issue asks for 1e-9 rad.
TEST(GeodesyTest, GeodeticEcefRoundTrip) {
  double worst_angle = 0.0, worst_height = 0.0;
  for (double lat_deg = -90.0; lat_deg <= 90.0; lat_deg += 2.5) {
    for (double lon_deg = -177.0; lon_deg <= 180.0; lon_deg += 11.0) {
      for (double h : {-11000.0, -4000.0, 0.0, 12.5, 30e3, 850e3}) {
        const GeodeticPosition g{lat_deg * kDeg, lon_deg * kDeg, h};
        const GeodeticPosition back = ecef_to_geodetic(geodetic_to_ecef(g));
        worst_angle = std::max(worst_angle, std::abs(back.latitude_rad - g.latitude_rad));
        if (std::abs(lat_deg) < 90.0) {  // the longitude of a pole is undefined (returned as 0)
          worst_angle = std::max(worst_angle, std::abs(wrap_angle(back.longitude_rad - g.longitude_rad)));
        }
        worst_height = std::max(worst_height, std::abs(back.height_m - g.height_m));
      }
    }
  }
  EXPECT_LT(worst_angle, 1e-14);  // measured 3.3e-16 rad
  EXPECT_LT(worst_height, 3e-8);  // measured 3.8e-9 m
}

TEST(GeodesyTest, RejectsNonFinitePointsAndOriginsOffTheGlobe) {
  EXPECT_THROW(ecef_to_geodetic(Eigen::Vector3d(NAN, 0, 0)), std::domain_error);
  EXPECT_THROW(LocalEnuFrame({100 * kDeg, 0.0, 0.0}), std::domain_error);
  EXPECT_THROW(LocalEnuFrame({0.0, INFINITY, 0.0}), std::domain_error);
}

// The conversion that also returns R_WN returns the same position and the rotation R_WN gives there.
TEST(GeodesyTest, RotationWithTheConversionIsRwnAtThePoint) {
  const LocalEnuFrame frame(kOrigin);
  for (const Eigen::Vector3d& p_WQ : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(42e3, -17e3, -3000.0)}) {
    Eigen::Matrix3d R_WN;
    const GeodeticPosition q = frame.to_geodetic(p_WQ, &R_WN);
    const GeodeticPosition plain = frame.to_geodetic(p_WQ);
    EXPECT_EQ(q.latitude_rad, plain.latitude_rad);
    EXPECT_EQ(q.longitude_rad, plain.longitude_rad);
    EXPECT_EQ(q.height_m, plain.height_m);
    EXPECT_TRUE(R_WN.isApprox(frame.R_WN(q), 1e-14));
    EXPECT_NEAR((R_WN.transpose() * R_WN - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-15);
  }
  const LocalEnuFrame copy = frame;
  EXPECT_EQ(copy.to_geodetic(Eigen::Vector3d(1e3, 2e3, -50.0)).latitude_rad,
            frame.to_geodetic(Eigen::Vector3d(1e3, 2e3, -50.0)).latitude_rad);
}

// W -> geodetic -> W for points up to 100 km from the origin, 11 km deep. Tolerance as above: 3e-8 m.
TEST(GeodesyTest, LocalEnuGeodeticRoundTrip) {
  const LocalEnuFrame frame(kOrigin);
  EXPECT_NEAR(frame.to_geodetic(Eigen::Vector3d::Zero()).latitude_rad, kOrigin.latitude_rad, 1e-15);
  EXPECT_NEAR(frame.to_geodetic(Eigen::Vector3d::Zero()).longitude_rad, kOrigin.longitude_rad, 1e-15);
  EXPECT_NEAR(frame.to_geodetic(Eigen::Vector3d::Zero()).height_m, 0.0, 3e-8);
  EXPECT_TRUE(frame.R_WN(kOrigin).isApprox(Eigen::Matrix3d::Identity(), 1e-15));
  for (double x : {-100e3, -3e3, 0.0, 0.7, 42e3, 100e3}) {
    for (double y : {-100e3, -0.2, 5e3, 100e3}) {
      for (double z : {-11e3, -1500.0, 0.0}) {
        const Eigen::Vector3d p_WQ(x, y, z);
        EXPECT_NEAR((frame.from_geodetic(frame.to_geodetic(p_WQ)) - p_WQ).norm(), 0.0, 3e-8)
            << p_WQ.transpose();
      }
    }
  }
}

// Two closed forms for the rotation R_WN between W and the local ENU frame at Q:
//  - Q on the origin's meridian at latitude lat: the normals differ by exactly lat - lat0 about east,
//    R_WN = Rx(-(lat - lat0)), and there is no meridian convergence;
//  - Q at the origin's latitude dlon east: tan gamma = sin(lat) sin(dlon) / (sin^2 lat cos dlon + cos^2 lat).
// Tolerance 1e-14: the rotation matrices are products of sines and cosines of O(1) arguments.
TEST(GeodesyTest, LocalFrameRotationTiltAndMeridianConvergence) {
  const LocalEnuFrame frame(kOrigin);
  for (double dlat_deg : {-1.0, 0.01, 0.9}) {
    const GeodeticPosition q{kOrigin.latitude_rad + dlat_deg * kDeg, kOrigin.longitude_rad, -2000.0};
    const Eigen::Matrix3d expected(Eigen::AngleAxisd(-dlat_deg * kDeg, Eigen::Vector3d::UnitX()));
    EXPECT_TRUE(frame.R_WN(q).isApprox(expected, 1e-14)) << dlat_deg;
    EXPECT_NEAR(frame.meridian_convergence_rad(q), 0.0, 1e-15);
  }
  const double lat = kOrigin.latitude_rad;
  for (double dlon_deg : {-1.3, 0.001, 0.5, 1.27}) {  // 1.27 deg east ~ 100 km at 45 N
    const double dlon = dlon_deg * kDeg;
    const GeodeticPosition q{lat, kOrigin.longitude_rad + dlon, 0.0};
    const double expected =
        std::atan2(std::sin(lat) * std::sin(dlon),
                   std::pow(std::sin(lat), 2) * std::cos(dlon) + std::pow(std::cos(lat), 2));
    EXPECT_NEAR(frame.meridian_convergence_rad(q), expected, 1e-14) << dlon_deg;
  }
  // 100 km east of 45 N: about 0.9 deg (the header's figure).
  const GeodeticPosition east = frame.to_geodetic(Eigen::Vector3d(100e3, 0.0, 0.0));
  EXPECT_NEAR(frame.meridian_convergence_rad(east) / kDeg, 0.9, 0.01);
}

}  // namespace
}  // namespace hadal::sensors
