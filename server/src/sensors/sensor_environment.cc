// SensorEnvironment (sensors/sensor_kind.h): the data geo-referenced sensors share, made on first use.
#include <GeographicLib/LocalCartesian.hpp>

#include <Eigen/Core>

#include "hadal/sensors/geomagnetic.h"
#include "hadal/sensors/magnetometer.h"
#include "hadal/sensors/sensor_kind.h"

namespace hadal::sensors {

SensorEnvironment::SensorEnvironment(double latitude_rad, double longitude_rad, double height_m)
    : latitude_rad_(latitude_rad), longitude_rad_(longitude_rad), height_m_(height_m) {}

SensorEnvironment::~SensorEnvironment() = default;

const GeomagneticModel& SensorEnvironment::geomagnetic() {
  if (!geomagnetic_) {
    geomagnetic_ = std::make_unique<GeomagneticModel>(GeomagneticModel::load_cof(HADAL_WMM_COF));
  }
  return *geomagnetic_;
}

const LocalEnuFrame& SensorEnvironment::frame_W() {
  if (!frame_W_) {
    frame_W_ = std::make_unique<LocalEnuFrame>(GeodeticPosition{latitude_rad_, longitude_rad_, height_m_});
  }
  return *frame_W_;
}

const GeographicLib::LocalCartesian& SensorEnvironment::local_cartesian() {
  if (!local_cartesian_) {
    local_cartesian_ = std::make_unique<GeographicLib::LocalCartesian>(
        latitude_rad_ * 180.0 / EIGEN_PI, longitude_rad_ * 180.0 / EIGEN_PI, height_m_);
  }
  return *local_cartesian_;
}

}  // namespace hadal::sensors
