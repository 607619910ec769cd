// The USBL's spec and its transponder's (sensors/usbl_sensor.h; keys: UsblSensor::keys(), transponder_keys()).
#pragma once

#include <Eigen/Core>

#include "hadal/config/key_table_fwd.h"
#include "hadal/core/units.h"

namespace hadal::sensors {

struct UsblSensor;

struct UsblSpec {
  using Kind = UsblSensor;
  double frequency_hz = 26000.0;              // centre of the band [Hz]
  double bandwidth_hz = 10000.0;              // [Hz]
  double source_level_db = 190.0;             // interrogation, dB re 1 uPa at 1 m
  double directivity_index_db = 0.0;          // the receive array's gain over an omnidirectional hydrophone [dB]
  double detection_threshold_db = 10.0;       // SNR a reply needs to be detected [dB]
  double cone_half_angle = 90.0 * kDegToRad;  // coverage about -z_S [rad]
  double max_range = 4000.0;                  // [m]
  double range_stddev = 0.05;                 // [m] at reference_snr_db and above
  double bearing_stddev = 0.1 * kDegToRad;    // per axis across the direction [rad], at reference_snr_db and above
  double reference_snr_db = 20.0;             // below it the errors grow as 10^((ref - SNR) / 20)
};

// A vehicle's transponder (YAML `transponder:` in a vehicle definition): what a USBL interrogates.
struct TransponderSpec {
  Eigen::Vector3d p_BT = Eigen::Vector3d::Zero();  // its position in B [m]
  double source_level_db = 185.0;                  // the reply, dB re 1 uPa at 1 m
  double detection_threshold_db = 10.0;            // SNR an interrogation needs to be heard [dB]
  double turnaround_s = 0.05;                      // from hearing the interrogation to replying [s]
};

const config::KeyTable<TransponderSpec>& transponder_keys();

}  // namespace hadal::sensors
