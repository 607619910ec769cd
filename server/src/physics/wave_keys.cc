// The keys of a scenario's sea state, `world.waves` (physics/waves.h), each declared once (config/key_table.h).
#include "hadal/config/key_table.h"
#include "hadal/physics/waves.h"

namespace hadal::physics {

using config::Range;

namespace {

const config::KeyTable<WaveComponentSpec>& wave_component_keys() {
  return config::declare_keys<WaveComponentSpec>([](config::KeyTable<WaveComponentSpec>& t) {
    t.describe("world.waves.regular[]", "one regular (Airy) wave component");
    t.number("amplitude", &WaveComponentSpec::amplitude).required().unit("m").range(Range::closed(0.0, 30.0))
        .doc("half its height, crest to trough");
    t.number("period", &WaveComponentSpec::period).required().unit("s").range(Range::left_open(0.0, 60.0))
        .doc("2 pi / omega");
    t.number("direction_deg", &WaveComponentSpec::direction).degrees().range(Range::finite())
        .doc("the way it travels, from W's x axis (east) toward y (north)");
    t.number("phase_deg", &WaveComponentSpec::phase).degrees().range(Range::finite())
        .doc("its phase at t = 0 at W's origin (a crest there at 0)");
  });
}

}  // namespace

const config::KeyTable<WaveSpec>& wave_keys() {
  return config::declare_keys<WaveSpec>([](config::KeyTable<WaveSpec>& t) {
    t.describe("world.waves", "the sea state: linear (Airy) waves on the water's surface, from a spectrum or listed");
    t.choice("spectrum", &WaveSpec::spectrum,
             {{"none", WaveSpectrum::kNone, "a flat surface"},
              {"jonswap", WaveSpectrum::kJonswap, "JONSWAP from significant_height, peak_period and gamma"},
              {"pierson_moskowitz", WaveSpectrum::kPiersonMoskowitz,
               "Pierson-Moskowitz (a fully developed sea: JONSWAP with gamma 1)"},
              {"regular", WaveSpectrum::kRegular, "the components listed in `regular`"}})
        .selects("wave spectrum")
        .doc("what makes the waves");
    t.number("significant_height", &WaveSpec::significant_height).only_for({"jonswap", "pierson_moskowitz"})
        .required_for({"jonswap", "pierson_moskowitz"}).unit("m").range(Range::left_open(0.0, 30.0))
        .doc("Hs = 4 sqrt(m0), the spectrum's energy (0 has none)");
    t.number("peak_period", &WaveSpec::peak_period).only_for({"jonswap", "pierson_moskowitz"})
        .required_for({"jonswap", "pierson_moskowitz"}).unit("s").range(Range::left_open(0.0, 60.0))
        .doc("Tp, the period at the spectrum's peak");
    t.number("gamma", &WaveSpec::gamma).only_for({"jonswap"}).range(Range::closed(1.0, 10.0))
        .doc("JONSWAP's peak enhancement (3.3: the North Sea's mean)");
    t.number("direction_deg", &WaveSpec::direction).only_for({"jonswap", "pierson_moskowitz"}).degrees()
        .range(Range::finite()).doc("the mean direction the waves travel toward, from W's x axis (east) toward y");
    t.number("spreading", &WaveSpec::spreading).only_for({"jonswap", "pierson_moskowitz"})
        .range(Range::closed(1.0, 1000.0)).default_text("none: long-crested")
        .doc("s of the directional spreading cos^2s((theta - theta_0) / 2): each component's direction drawn from "
             "it (about 1-10 for wind sea, 25 and more for swell)");
    t.number("components", &WaveSpec::components).only_for({"jonswap", "pierson_moskowitz"})
        .range(Range::closed(1.0, kMaxWaveComponents))
        .doc("how many components sample the spectrum (each costs every face of every hull near the surface a few "
             "operations a step)");
    t.list("regular", &WaveSpec::regular, wave_component_keys()).only_for({"regular"}).required_for({"regular"})
        .min_items(1, "components").doc("the components, instead of a spectrum");
    t.number("depth", &WaveSpec::depth).unit("m").range(Range::positive()).default_text("deep water")
        .doc("the water's depth under the waves, for their dispersion and decay (deep water: kh large)");
    t.number("ramp_time", &WaveSpec::ramp_time).unit("s").range(Range::closed(0.0, 3600.0))
        .default_text("two peak periods (regular: two of the longest period)")
        .doc("the build-up from calm water at t = 0, (1 - cos(pi t / T)) / 2 on every wave quantity, so that floating "
             "bodies starting at rest are not thrown into a moving sea (0: the full sea from the start)");
    t.check([](const config::KeyReads& reads, WaveSpec& waves, config::NoContext&) {
      if (waves.spectrum != WaveSpectrum::kRegular) return true;
      if (waves.regular.size() > static_cast<std::size_t>(kMaxWaveComponents)) {
        reads.error_at_key("regular", "too many components: " + std::to_string(waves.regular.size()) + " (at most " +
                                          std::to_string(kMaxWaveComponents) + ")");
        return false;
      }
      double energy = 0.0;
      for (const WaveComponentSpec& c : waves.regular) energy += c.amplitude * c.amplitude;
      if (energy > 0.0) return true;
      reads.error_at_key("regular", "the components have no energy (every amplitude is 0)");
      return false;
    });
  });
}

}  // namespace hadal::physics
