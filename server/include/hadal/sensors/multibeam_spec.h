// The multibeam's spec (sensors/multibeam_sensor.h; keys: MultibeamSensor::keys()).
#pragma once

#include <memory>

#include "hadal/core/units.h"
#include "hadal/sensors/sonar_spec.h"

namespace hadal::sensors {

struct MultibeamSensor;

// A multibeam's acoustics without a preset: 215 dB source level, a 4000-bin window.
SonarAcoustics multibeam_default_acoustics();

struct MultibeamSpec {
  using Kind = MultibeamSensor;
  int beams = 256;
  double swath = 130.0 * kDegToRad;            // [rad]
  double across_beam_width = 1.0 * kDegToRad;  // in the swath [rad]
  double along_beam_width = 1.0 * kDegToRad;   // across it [rad]
  int rays_across = 32;
  int rays_along = 4;
  double min_snr_db = 10.0;
  SonarAcoustics acoustics = multibeam_default_acoustics();
  std::shared_ptr<const render::SonarPingSpec> ping;  // made by keys() / make_ping()
};

}  // namespace hadal::sensors
