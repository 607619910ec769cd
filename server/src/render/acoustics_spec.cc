#include "hadal/render/acoustics_spec.h"

#include "hadal/config/key_table.h"

namespace hadal::render {

const config::KeyTable<AcousticsSpec>& acoustics_keys() {
  return config::declare_keys<AcousticsSpec>([](config::KeyTable<AcousticsSpec>& t) {
    t.describe("world.acoustics", "what sonars hear: Lambert's backscatter parameter mu");
    t.number("seabed_backscatter_db", &AcousticsSpec::seabed_backscatter_db).unit("dB")
        .range(config::Range::closed(-80.0, 0.0))
        .doc("the seabed's (Mackenzie 1961, deep-sea bottom); mud is about -40 to -35, sand -30 to -25, rock -15 to "
             "-10 at 100-400 kHz");
    t.number("vehicle_backscatter_db", &AcousticsSpec::vehicle_backscatter_db).unit("dB")
        .range(config::Range::closed(-80.0, 0.0))
        .doc("hulls (metal, composite); a link's appearance.backscatter_db overrides it");
  });
}

}  // namespace hadal::render
