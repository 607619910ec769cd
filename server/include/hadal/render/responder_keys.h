// render::declare_responder_keys (render/acoustics_spec.h): the keys of a beacon and of a transponder. Included
// by the .cc files that declare those tables only.
#pragma once

#include <string>

#include "hadal/config/key_table.h"
#include "hadal/render/acoustics_spec.h"

namespace hadal::render {

template <class Spec, class Ctx>
void declare_responder_keys(config::KeyTable<Spec, Ctx>& t, const char* interrogator) {
  using config::Range;
  t.number("source_level_db", &Spec::source_level_db).unit("dB re 1 uPa at 1 m").range(Range::closed(100.0, 240.0))
      .doc("the reply's source level");
  t.number("detection_threshold_db", &Spec::detection_threshold_db).unit("dB").range(Range::closed(-20.0, 60.0))
      .doc("the SNR an interrogation needs to be heard");
  t.number("turnaround_s", &Spec::turnaround_s).unit("s").range(Range::closed(0.0, 10.0))
      .doc(std::string("from hearing an interrogation to replying (known to the ") + interrogator +
           ", which subtracts it)");
}

}  // namespace hadal::render
