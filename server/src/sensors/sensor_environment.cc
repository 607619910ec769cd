// SensorEnvironment (sensors/sensor_kind.h): the data geo-referenced sensors share.
#include "hadal/sensors/acoustic_channel.h"
#include "hadal/sensors/geodesy.h"
#include "hadal/sensors/geomagnetic.h"
#include "hadal/sensors/sensor_kind.h"

namespace hadal::sensors {

SensorEnvironment::SensorEnvironment(const GeodeticPosition& origin)
    : frame_W_(std::make_unique<LocalEnuFrame>(origin)) {}

SensorEnvironment::~SensorEnvironment() = default;

const GeomagneticModel& SensorEnvironment::geomagnetic() {
  if (!geomagnetic_) {
    geomagnetic_ = std::make_unique<GeomagneticModel>(GeomagneticModel::load_cof(GeomagneticModel::default_cof_path()));
  }
  return *geomagnetic_;
}

const AcousticChannel& SensorEnvironment::acoustic_channel(const physics::Ocean& ocean,
                                                           const AcousticsSpec& acoustics) {
  if (!acoustic_channel_) acoustic_channel_ = std::make_unique<AcousticChannel>(ocean, acoustics);
  return *acoustic_channel_;
}

}  // namespace hadal::sensors
