// The keys the sonar kinds share (sensors/sonar.h): the acoustics every sonar has, the image encoding of
// the imaging ones (fls, sidescan), and the checks that close a sonar's keys (the receive window, the ping
// rate against the two-way travel time, the ping spec the kind makes). Declared once, for a kind whose Spec
// has `acoustics` (and `encoding`). Included by the sonar kinds' .cc files only.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include "hadal/config/key_table.h"
#include "hadal/sensors/sonar.h"

namespace hadal::sensors {

// The sound speed bounding seawater's from above, for the ping-rate check [m/s].
inline constexpr double kMaxSoundSpeed = 1600.0;

template <class Spec>
void declare_sonar_acoustic_keys(config::KeyTable<Spec, SensorReader>& t) {
  using config::Range;
  const auto a = [](auto field) {
    return [field](Spec& s) -> auto& { return s.acoustics.*field; };
  };
  t.number("frequency_hz", a(&SonarAcoustics::frequency_hz)).unit("Hz").range(Range::closed(1e3, 5e6))
      .doc("centre frequency: absorption (Francois-Garrison), PingInfo");
  t.number("min_range", a(&SonarAcoustics::min_range)).unit("m").range(Range::non_negative())
      .doc("the receive window's near end");
  t.number("max_range", a(&SonarAcoustics::max_range)).unit("m").range(Range::closed(0.1, 10000.0))
      .rule("> min_range").doc("the receive window's far end");
  t.number("bins", a(&SonarAcoustics::bins)).range(Range::closed(1.0, 65536.0)).doc("equal range bins over the window");
  t.number("source_level_db", a(&SonarAcoustics::source_level_db)).unit("dB re 1 µPa at 1 m")
      .range(Range::closed(100.0, 260.0)).doc("source level");
  t.number("noise_level_db", a(&SonarAcoustics::noise_level_db)).unit("dB re 1 µPa")
      .range(Range::closed(-50.0, 200.0)).doc("receiver noise per bin");
  t.boolean("speckle", a(&SonarAcoustics::speckle)).doc("Rayleigh speckle per bin");
  t.boolean("receiver_noise", a(&SonarAcoustics::receiver_noise)).doc("complex Gaussian receiver noise");
  t.number("spreading_db_per_decade", a(&SonarAcoustics::spreading_db_per_decade)).unit("dB")
      .range(Range::closed(0.0, 40.0)).doc("one-way spreading N log10 r (20 spherical, 10 cylindrical)");
  t.number("tvg_db_per_decade", a(&SonarAcoustics::tvg_db_per_decade)).unit("dB").range(Range::closed(0.0, 60.0))
      .doc("the time-varied gain's spreading term");
  t.boolean("tvg_absorption", a(&SonarAcoustics::tvg_absorption)).doc("the time-varied gain's 2 alpha r term");
}

template <class Spec>
void declare_sonar_image_keys(config::KeyTable<Spec, SensorReader>& t) {
  using config::Range;
  const auto e = [](auto field) {
    return [field](Spec& s) -> auto& { return s.encoding.*field; };
  };
  t.choice("image_dtype", e(&SonarImageEncoding::float32),
           {{"uint8", false, "levels over the display window"}, {"float32", true, "intensity after TVG in µPa², linear"}})
      .doc("sample type");
  t.number("display_min_db", e(&SonarImageEncoding::display_min_db)).unit("dB re 1 µPa")
      .range(Range::closed(-100.0, 300.0)).doc("uint8: the level shown as 0");
  t.number("display_max_db", e(&SonarImageEncoding::display_max_db)).unit("dB re 1 µPa")
      .range(Range::closed(-100.0, 300.0)).rule("> display_min_db").doc("uint8: the level shown as 255");
  t.check([](const config::KeyReads& reads, Spec& spec, SensorReader&) {
    const SonarImageEncoding& encoding = spec.encoding;
    if (!reads.ok("display_min_db") || !reads.ok("display_max_db") || encoding.display_max_db > encoding.display_min_db) {
      return true;
    }
    reads.error_at_key(reads.has("display_max_db") ? "display_max_db" : "display_min_db",
                       "display_max_db (" + config::format_number(encoding.display_max_db) +
                           ") must exceed display_min_db (" + config::format_number(encoding.display_min_db) + ")");
    return false;
  });
}

// The window (max_range > min_range), the ping rate (rate_hz <= 1600 / (2 max_range): a ping's echoes are in
// before the next), then `make_ping` (the kind's) unless the window is unusable; a ping spec it cannot make
// (std::invalid_argument) is an error at the sensor's map.
template <class Spec>
void declare_sonar_check(config::KeyTable<Spec, SensorReader>& t, void (*make_ping)(Spec&)) {
  t.check([make_ping](const config::KeyReads& reads, Spec& spec, SensorReader& reader) {
    const config::MapReader& map = reads.map();
    const SonarAcoustics& a = spec.acoustics;
    if (!reads.ok("min_range") || !reads.ok("max_range")) return false;
    if (!(a.max_range > a.min_range)) {
      map.error_at_key(map.has("max_range") ? "max_range" : "min_range",
                       "max_range (" + config::format_number(a.max_range) + " m) must exceed min_range (" +
                           config::format_number(a.min_range) + " m)");
      return false;
    }
    bool ok = true;
    const double limit_hz = kMaxSoundSpeed / (2.0 * a.max_range);
    if (reader.rate_hz > limit_hz) {
      const std::string message = "a ping every " + config::format_number(1.0 / reader.rate_hz) + " s (rate_hz " +
                                  config::format_number(reader.rate_hz) +
                                  ") is shorter than the echoes' two-way travel time over max_range " +
                                  config::format_number(a.max_range) + " m: rate_hz must be <= " +
                                  config::format_number(limit_hz) + " (1600 m/s / (2 max_range))";
      if (map.has("rate_hz")) {
        map.error_at_key("rate_hz", message);
      } else if (map.has("max_range")) {
        map.error_at_key("max_range", message);
      } else {
        map.value().error(message);
      }
      ok = false;
    }
    try {
      make_ping(spec);
    } catch (const std::invalid_argument& e) {
      map.value().error(std::string("unusable sonar: ") + e.what());
      ok = false;
    }
    return ok;
  });
}

}  // namespace hadal::sensors
