// The forward-looking sonar's spec (sensors/fls_sensor.h; keys: FlsSensor::keys()).
#pragma once

#include <memory>

#include "hadal/core/units.h"
#include "hadal/sensors/sonar_spec.h"

namespace hadal::sensors {

struct FlsSensor;

struct FlsSpec {
  using Kind = FlsSensor;
  int beams = 256;
  double fov = 130.0 * kDegToRad;              // [rad]
  double beam_width = 1.0 * kDegToRad;         // in the fan [rad]
  double vertical_aperture = 20.0 * kDegToRad;  // across it [rad]
  int azimuth_rays = 2;
  int rays_per_cell = 4;
  SonarAcoustics acoustics;
  SonarImageEncoding encoding;
  std::shared_ptr<const render::SonarPingSpec> ping;  // made by keys() / make_ping() from the above
};

}  // namespace hadal::sensors
