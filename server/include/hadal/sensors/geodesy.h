// WGS84 geodesy of the world frame W, one implementation for every geo-referenced sensor (GPS fixes,
// the magnetometer's field model). W is the East-North-Up tangent frame at a geodetic origin O; a point
// of W converts to geodetic latitude, longitude and ellipsoidal height, and back, with GeographicLib's
// LocalCartesian (exact on the ellipsoid, everywhere a vehicle can be). At a point Q the local ENU frame
// N is W rotated by R_WN (GeographicLib's rotation matrix M: v_W = M v_N), which is
//   - the tilt of the vertical, |Q - O| / R ~ 1.57e-4 rad per km (the ellipsoid normals diverge), and
//   - the meridian convergence gamma about the vertical (local north vs W's y axis), exactly
//     tan gamma = sin(lat) sin(dlon) / (sin^2(lat) cos(dlon) + cos^2(lat)) at the origin's latitude
//     dlon east of it (~ dlon sin lat: 0.9 deg at 100 km east of 45 N).
// W's horizontal plane leaves the ellipsoid as d^2 / (2 R) (0.08 m at 1 km, 7.8 m at 10 km): a point at
// constant z far from the origin has a greater ellipsoidal height. Angles in radians (SI), heights in m.
#pragma once

#include <Eigen/Core>

#include <memory>

#include "hadal/sensors/geodetic_position.h"

namespace GeographicLib {
class LocalCartesian;
}

namespace hadal::sensors {

// ECEF (Earth-centred, Earth-fixed, WGS84) position of a geodetic one, and back.
Eigen::Vector3d geodetic_to_ecef(const GeodeticPosition& position);
GeodeticPosition ecef_to_geodetic(const Eigen::Vector3d& p_ECEF);
// Columns: east, north, up at (latitude, longitude), in ECEF.
Eigen::Matrix3d R_ECEF_ENU(double latitude_rad, double longitude_rad);

// W: the ENU tangent frame at a geodetic origin. Immutable.
class LocalEnuFrame {
 public:
  // Throws std::domain_error for a non-finite origin or |latitude| > pi/2.
  explicit LocalEnuFrame(const GeodeticPosition& origin);
  ~LocalEnuFrame();
  LocalEnuFrame(const LocalEnuFrame& other);
  LocalEnuFrame& operator=(const LocalEnuFrame&) = delete;

  const GeodeticPosition& origin() const { return origin_; }

  GeodeticPosition to_geodetic(const Eigen::Vector3d& p_WQ) const;
  // The same, and R_WN at Q.
  GeodeticPosition to_geodetic(const Eigen::Vector3d& p_WQ, Eigen::Matrix3d* R_WN) const;
  Eigen::Vector3d from_geodetic(const GeodeticPosition& position) const;
  // R_WN: the local ENU frame N at `at` in W's axes (identity at the origin).
  Eigen::Matrix3d R_WN(const GeodeticPosition& at) const;
  // Meridian convergence at `at` [rad]: angle about W's z from W's +y to the horizontal projection of
  // local north, counter-clockwise positive (positive east of the origin in the northern hemisphere).
  double meridian_convergence_rad(const GeodeticPosition& at) const;

 private:
  GeodeticPosition origin_;
  std::unique_ptr<GeographicLib::LocalCartesian> cartesian_;
};

}  // namespace hadal::sensors
