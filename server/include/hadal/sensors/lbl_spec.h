// The LBL's spec (sensors/lbl_sensor.h; keys: LblSensor::keys()).
#pragma once

namespace hadal::sensors {

struct LblSensor;

struct LblSpec {
  using Kind = LblSensor;
  double frequency_hz = 12000.0;         // centre of the band [Hz] (LBL: 8-16 kHz, long ranges)
  double bandwidth_hz = 4000.0;          // [Hz]
  double source_level_db = 190.0;        // interrogation, dB re 1 uPa at 1 m
  double directivity_index_db = 0.0;     // [dB]
  double detection_threshold_db = 10.0;  // SNR a reply needs to be detected [dB]
  double max_range = 10000.0;            // [m]
  double range_stddev = 0.1;             // [m] at reference_snr_db and above
  double reference_snr_db = 20.0;        // below it the error grows as 10^((ref - SNR) / 20)
};

}  // namespace hadal::sensors
