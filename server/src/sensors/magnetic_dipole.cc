#include "hadal/sensors/magnetic_dipole.h"

#include "hadal/config/key_table.h"

namespace hadal::sensors {

const config::KeyTable<MagneticDipole>& dipole_keys() {
  return config::declare_keys<MagneticDipole>([](config::KeyTable<MagneticDipole>& t) {
    t.describe("magnetic_dipole", "a magnetic dipole, in the frame of its list");
    t.vector("position", &MagneticDipole::p_FD).required().unit("m").doc("its position");
    t.vector("moment", &MagneticDipole::m_F).required().unit("A m²").doc("its moment");
    t.number("radius", &MagneticDipole::radius).unit("m").range(config::Range::non_negative())
        .doc("0: a point dipole; > 0: a uniformly magnetised sphere, finite inside");
  });
}

}  // namespace hadal::sensors
