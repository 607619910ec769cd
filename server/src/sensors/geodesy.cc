#include "hadal/sensors/geodesy.h"

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "hadal/config/key_table.h"
#include "hadal/core/units.h"

namespace hadal::sensors {

namespace {

const GeodeticPosition& checked_origin(const GeodeticPosition& g) {
  if (!std::isfinite(g.latitude_rad) || !std::isfinite(g.longitude_rad) || !std::isfinite(g.height_m)) {
    throw std::domain_error("LocalEnuFrame: non-finite origin");
  }
  if (std::abs(g.latitude_rad) > kPi / 2) throw std::domain_error("LocalEnuFrame: origin |latitude| > pi/2");
  return g;
}

// GeographicLib works in degrees (to_degrees: core/units.h).
GeodeticPosition from_degrees(double lat, double lon, double h) { return {lat * kDegToRad, lon * kDegToRad, h}; }

Eigen::Matrix3d row_major(const std::vector<double>& M) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(M.data());
}

}  // namespace

Eigen::Vector3d geodetic_to_ecef(const GeodeticPosition& g) {
  Eigen::Vector3d p;
  GeographicLib::Geocentric::WGS84().Forward(to_degrees(g.latitude_rad), to_degrees(g.longitude_rad), g.height_m,
                                             p.x(), p.y(), p.z());
  return p;
}

GeodeticPosition ecef_to_geodetic(const Eigen::Vector3d& p_ECEF) {
  if (!p_ECEF.allFinite()) throw std::domain_error("ecef_to_geodetic: non-finite point");
  double lat = 0.0, lon = 0.0, h = 0.0;
  GeographicLib::Geocentric::WGS84().Reverse(p_ECEF.x(), p_ECEF.y(), p_ECEF.z(), lat, lon, h);
  return from_degrees(lat, lon, h);
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
      cartesian_(std::make_unique<GeographicLib::LocalCartesian>(
          to_degrees(origin.latitude_rad), to_degrees(origin.longitude_rad), origin.height_m)) {}

LocalEnuFrame::~LocalEnuFrame() = default;

LocalEnuFrame::LocalEnuFrame(const LocalEnuFrame& other)
    : origin_(other.origin_), cartesian_(std::make_unique<GeographicLib::LocalCartesian>(*other.cartesian_)) {}

GeodeticPosition LocalEnuFrame::to_geodetic(const Eigen::Vector3d& p_WQ) const {
  double lat = 0.0, lon = 0.0, h = 0.0;
  cartesian_->Reverse(p_WQ.x(), p_WQ.y(), p_WQ.z(), lat, lon, h);
  return from_degrees(lat, lon, h);
}

GeodeticPosition LocalEnuFrame::to_geodetic(const Eigen::Vector3d& p_WQ, Eigen::Matrix3d* R_WN) const {
  double lat = 0.0, lon = 0.0, h = 0.0;
  std::vector<double> M(9);
  cartesian_->Reverse(p_WQ.x(), p_WQ.y(), p_WQ.z(), lat, lon, h, M);
  *R_WN = row_major(M);
  return from_degrees(lat, lon, h);
}

Eigen::Vector3d LocalEnuFrame::from_geodetic(const GeodeticPosition& position) const {
  Eigen::Vector3d p_WQ;
  cartesian_->Forward(to_degrees(position.latitude_rad), to_degrees(position.longitude_rad), position.height_m,
                      p_WQ.x(), p_WQ.y(), p_WQ.z());
  return p_WQ;
}

Eigen::Matrix3d LocalEnuFrame::R_WN(const GeodeticPosition& at) const {
  double x = 0.0, y = 0.0, z = 0.0;
  std::vector<double> M(9);
  cartesian_->Forward(to_degrees(at.latitude_rad), to_degrees(at.longitude_rad), at.height_m, x, y, z, M);
  return row_major(M);
}

double LocalEnuFrame::meridian_convergence_rad(const GeodeticPosition& at) const {
  const Eigen::Vector3d north_W = R_WN(at).col(1);
  return std::atan2(-north_W.x(), north_W.y());
}

const config::KeyTable<GeodeticPosition>& origin_keys() {
  return config::declare_keys<GeodeticPosition>([](config::KeyTable<GeodeticPosition>& t) {
    t.describe("world.origin", "geodetic position (WGS84) of W's origin");
    t.number("latitude_deg", &GeodeticPosition::latitude_rad).degrees().range(config::Range::closed(-90.0, 90.0))
        .doc("geodetic latitude");
    t.number("longitude_deg", &GeodeticPosition::longitude_rad).degrees()
        .range(config::Range::closed(-180.0, 180.0)).doc("longitude");
    t.number("altitude", &GeodeticPosition::height_m).unit("m").doc("height above the ellipsoid");
  });
}

}  // namespace hadal::sensors
