#include "hadal/render/acoustics_spec.h"

#include "hadal/config/key_table.h"
#include "hadal/render/responder_keys.h"

namespace hadal::render {

const config::KeyTable<AmbientNoiseSpec>& ambient_noise_keys() {
  return config::declare_keys<AmbientNoiseSpec>([](config::KeyTable<AmbientNoiseSpec>& t) {
    t.describe("world.acoustics.ambient_noise", "Wenz's ambient noise: shipping, wind, turbulence and thermal noise");
    t.number("shipping", &AmbientNoiseSpec::shipping).range(config::Range::closed(0.0, 1.0))
        .doc("shipping activity, 0 (none) to 1 (heavy); dominates from 10 to 100 Hz");
    t.number("wind_speed", &AmbientNoiseSpec::wind_speed).unit("m/s").range(config::Range::closed(0.0, 50.0))
        .doc("wind speed at the surface; dominates from 100 Hz to 50 kHz (5 m/s is about sea state 3)");
  });
}

const config::KeyTable<BeaconSpec>& beacon_keys() {
  return config::declare_keys<BeaconSpec>([](config::KeyTable<BeaconSpec>& t) {
    t.describe("world.acoustics.beacons[]", "a long-baseline beacon fixed in W, which LBL sensors interrogate");
    t.string("name", &BeaconSpec::name).required().doc("unique among the beacons; names its ranges");
    t.vector("position", &BeaconSpec::p_W).required().unit("m").doc("its position in W (in the water)");
    declare_responder_keys(t, "LBL");
  });
}

const config::KeyTable<AcousticsSpec>& acoustics_keys() {
  return config::declare_keys<AcousticsSpec>([](config::KeyTable<AcousticsSpec>& t) {
    t.describe("world.acoustics", "what sonars, acoustic positioning and modems hear: backscatter, spreading, ambient noise");
    t.number("seabed_backscatter_db", &AcousticsSpec::seabed_backscatter_db).unit("dB")
        .range(config::Range::closed(-80.0, 0.0))
        .doc("the seabed's (Mackenzie 1961, deep-sea bottom); mud is about -40 to -35, sand -30 to -25, rock -15 to "
             "-10 at 100-400 kHz");
    t.number("surface_backscatter_db", &AcousticsSpec::surface_backscatter_db).unit("dB")
        .range(config::Range::closed(-80.0, 0.0))
        .doc("the sea surface's, seen from below by a sonar's beams that rise to it (Chapman and Harris 1962: about "
             "-50 dB in a calm to -20 dB in a high wind at moderate grazing angles)");
    t.number("vehicle_backscatter_db", &AcousticsSpec::vehicle_backscatter_db).unit("dB")
        .range(config::Range::closed(-80.0, 0.0))
        .doc("hulls (metal, composite); a link's appearance.backscatter_db overrides it");
    t.number("spreading_exponent", &AcousticsSpec::spreading_exponent).range(config::Range::closed(1.0, 2.0))
        .doc("k in the acoustic links' transmission loss k 10 log10 r + alpha r: 2 spherical, 1.5 practical, 1 "
             "cylindrical (positioning and modems; the sonars use their own)");
    t.map("ambient_noise", &AcousticsSpec::ambient_noise, ambient_noise_keys())
        .doc("the ambient noise acoustic receivers hear in their band");
    t.list("beacons", &AcousticsSpec::beacons, beacon_keys())
        .doc("long-baseline beacons on the seabed (or anywhere in the water), which LBL sensors interrogate");
    t.check([](const config::KeyReads& reads, AcousticsSpec& spec, config::NoContext&) {
      for (std::size_t i = 0; i < spec.beacons.size(); ++i) {
        for (std::size_t j = 0; j < i; ++j) {
          if (spec.beacons[i].name != spec.beacons[j].name) continue;
          reads.error_at_key("beacons", "duplicate beacon name " + config::quoted(spec.beacons[i].name) +
                                            " (beacons[" + std::to_string(j) + "] and beacons[" + std::to_string(i) +
                                            "])");
          return false;
        }
      }
      return true;
    });
  });
}

}  // namespace hadal::render
