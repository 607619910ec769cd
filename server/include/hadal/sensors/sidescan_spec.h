// The side-scan sonar's spec (sensors/sidescan_sensor.h; keys: SidescanSensor::keys()).
#pragma once

#include <memory>

#include "hadal/core/units.h"
#include "hadal/sensors/sonar_spec.h"

namespace hadal::sensors {

struct SidescanSensor;

// A side-scan's acoustics without a preset: its window and bins.
SonarAcoustics sidescan_default_acoustics();

struct SidescanSpec {
  using Kind = SidescanSensor;
  double horizontal_beam_width = 0.5 * kDegToRad;  // along track [rad]
  double vertical_beam_width = 50.0 * kDegToRad;   // [rad]
  double depression = 20.0 * kDegToRad;            // of the beams' axes below S's x-y plane [rad]
  int along_rays = 2;
  int rays_per_cell = 4;
  SonarAcoustics acoustics = sidescan_default_acoustics();
  SonarImageEncoding encoding;
  std::shared_ptr<const render::SonarPingSpec> ping;
};

}  // namespace hadal::sensors
