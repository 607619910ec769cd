// The range window and per-sample figures a range-finding kind shares (the altimeter, the profiler),
// declared once for a kind whose Spec has min_range, max_range, noise_stddev and resolution [m]. Included
// by the kinds' .cc files only.
#pragma once

#include "hadal/config/key_table.h"

namespace hadal::sensors {

template <class Spec, class Ctx>
void declare_range_keys(config::KeyTable<Spec, Ctx>& t) {
  using config::Range;
  t.number("min_range", &Spec::min_range).unit("m").range(Range::non_negative()).doc("nearest range measured");
  t.number("max_range", &Spec::max_range).unit("m").range(Range::positive()).rule("> min_range")
      .doc("farthest range measured");
  t.number("noise_stddev", &Spec::noise_stddev).unit("m").range(Range::non_negative()).doc("white noise per sample");
  t.number("resolution", &Spec::resolution).unit("m").range(Range::non_negative()).doc("quantisation step; 0: none");
  t.check([](const config::KeyReads& reads, Spec& spec, Ctx&) {
    if (!reads.ok("min_range") || !reads.ok("max_range") || spec.max_range > spec.min_range) return true;
    reads.error_at_key(reads.has("max_range") ? "max_range" : "min_range",
                       "max_range (" + config::format_number(spec.max_range) + " m) must exceed min_range (" +
                           config::format_number(spec.min_range) + " m)");
    return false;
  });
}

}  // namespace hadal::sensors
