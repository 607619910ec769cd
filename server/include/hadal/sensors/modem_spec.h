// The acoustic modem's spec and its presets' figures (sensors/modem_sensor.h; keys: ModemSensor::keys()).
#pragma once

#include <cstddef>

#include "hadal/config/preset.h"

namespace hadal::sensors {

struct ModemSensor;
struct ModemSpec;

// The modulation whose bit error rate the packet error curve starts from (ModemSensor::packet_success).
enum class ModemModulation {
  kFsk,  // non-coherent binary FSK: BER = exp(-Eb/N0 / 2) / 2
  kPsk,  // coherent BPSK: BER = erfc(sqrt(Eb/N0)) / 2
};

// A product's figures (a `preset:`; modem_presets()).
struct ModemFigures {
  double frequency_hz = 0.0;
  double bandwidth_hz = 0.0;
  double bit_rate_bps = 0.0;
  double source_level_db = 0.0;
  ModemModulation modulation = ModemModulation::kFsk;
  double implementation_loss_db = 0.0;
  double preamble_s = 0.0;
  int max_payload_bytes = 0;
  void apply(ModemSpec& spec) const;
};

const config::Presets<ModemFigures>& modem_presets();

// Defaults: the WHOI Micro-Modem's FH-FSK packet (modem_presets(), "whoi_micromodem_fhfsk").
struct ModemSpec {
  using Kind = ModemSensor;
  double frequency_hz = 25000.0;       // centre of the band [Hz]
  double bandwidth_hz = 4000.0;        // [Hz]
  double bit_rate_bps = 80.0;          // payload bits per second of the packet's data part [bit/s]
  double source_level_db = 185.0;      // dB re 1 uPa at 1 m
  ModemModulation modulation = ModemModulation::kFsk;
  double implementation_loss_db = 3.0;  // Eb/N0 the receiver needs beyond the ideal modulation's [dB]
  double preamble_s = 0.3;              // synchronisation before the data [s]
  int max_payload_bytes = 32;           // the largest packet a client may send [bytes]
  int queue_length = 4;                 // packets waiting while the modem transmits (0: a send then is refused)
  double capture_threshold_db = 10.0;   // how much stronger than all overlapping packets together a packet
                                        // must arrive to survive a collision [dB]
  double max_range = 10000.0;           // nothing is heard from farther [m]
};

}  // namespace hadal::sensors
