// The keys an acoustic interrogator shares (the USBL, the LBL; sensors/acoustic_interrogation.h), declared
// once for a kind whose Spec has frequency_hz, bandwidth_hz, source_level_db, directivity_index_db,
// detection_threshold_db, max_range, range_stddev and reference_snr_db, and its acoustics for the
// interrogation engine. Included by the kinds' .cc files only.
#pragma once

#include <algorithm>
#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/sensors/acoustic_interrogation.h"

namespace hadal::sensors {

template <class Spec, class Ctx>
void declare_interrogator_keys(config::KeyTable<Spec, Ctx>& t) {
  using config::Range;
  t.number("frequency_hz", &Spec::frequency_hz).unit("Hz").range(Range::closed(1000.0, 1e6))
      .doc("centre of the band (absorption, noise)");
  t.number("bandwidth_hz", &Spec::bandwidth_hz).unit("Hz").range(Range::positive())
      .doc("the band, below twice the centre frequency (noise)");
  t.number("source_level_db", &Spec::source_level_db).unit("dB re 1 uPa at 1 m").range(Range::closed(100.0, 240.0))
      .doc("the interrogation's source level");
  t.number("directivity_index_db", &Spec::directivity_index_db).unit("dB").range(Range::closed(0.0, 40.0))
      .doc("the receive array's gain over one omnidirectional hydrophone");
  t.number("detection_threshold_db", &Spec::detection_threshold_db).unit("dB").range(Range::closed(-20.0, 60.0))
      .doc("the SNR a reply needs to be detected");
  t.number("max_range", &Spec::max_range).unit("m").range(Range::positive()).doc("the longest slant range measured");
  t.number("range_stddev", &Spec::range_stddev).unit("m").range(Range::non_negative())
      .doc("range error at and above reference_snr_db");
  t.number("reference_snr_db", &Spec::reference_snr_db).unit("dB").range(Range::closed(-20.0, 80.0))
      .doc("below it the errors grow as 10^((reference - SNR) / 20)");
  t.check([](const config::KeyReads& reads, Spec& spec, Ctx&) {
    if (spec.bandwidth_hz < 2.0 * spec.frequency_hz) return true;
    reads.error_at_key("bandwidth_hz", "must be below twice frequency_hz (" +
                                           config::format_number(2.0 * spec.frequency_hz) + " Hz)");
    return false;
  });
}

template <class Spec>
InterrogatorAcoustics interrogator_acoustics(const Spec& spec) {
  return {spec.frequency_hz,         spec.bandwidth_hz,           spec.source_level_db,
          spec.directivity_index_db, spec.detection_threshold_db, spec.max_range};
}

// sigma_0 max(1, 10^((SNR_ref - SNR) / 20)) / sigma_0: the errors' growth below the reference SNR.
template <class Spec>
double error_scale(const Spec& spec, double snr_db) {
  return std::max(1.0, std::pow(10.0, (spec.reference_snr_db - snr_db) / 20.0));
}

}  // namespace hadal::sensors
