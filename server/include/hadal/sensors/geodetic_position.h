// A geodetic position on WGS84 (sensors/geodesy.h converts it). YAML world.origin, the geodetic position
// of W's origin, reads it in degrees: sensors::origin_keys() (server/src/sensors/geodesy.cc).
#pragma once

#include "hadal/config/key_table_fwd.h"

namespace hadal::sensors {

struct GeodeticPosition {
  double latitude_rad = 0.0;   // geodetic, [-pi/2, pi/2]
  double longitude_rad = 0.0;  // (-pi, pi] from conversions
  double height_m = 0.0;       // above the WGS84 ellipsoid
};

const config::KeyTable<GeodeticPosition>& origin_keys();

}  // namespace hadal::sensors
