// The keys of a scenario's cables (physics/cable.h), each declared once (config/key_table.h).
#include "hadal/config/key_table.h"
#include "hadal/physics/cable.h"

namespace hadal::physics {

using config::Range;

namespace {

const config::KeyTable<CableEndSpec>& cable_end_keys() {
  return config::declare_keys<CableEndSpec>([](config::KeyTable<CableEndSpec>& t) {
    t.describe("cables[].from", "what holds an end of a cable: a point fixed in W, a point on a vehicle's link, or nothing");
    t.string("vehicle", &CableEndSpec::vehicle).default_text("none: fixed in W").doc("the vehicle it is attached to");
    t.string("link", &CableEndSpec::link).default_text("the base link").doc("the vehicle's link it is attached to");
    t.vector("position", &CableEndSpec::position).unit("m")
        .doc("on a vehicle: in its link's frame; else the fixed point in W");
    t.boolean("free", &CableEndSpec::free).doc("true: nothing holds this end (it trails)");
    t.check([](const config::KeyReads& reads, CableEndSpec& end, config::NoContext&) {
      if (end.free && (reads.has("vehicle") || reads.has("link") || reads.has("position"))) {
        reads.error_at_key("free", "a free end is held by nothing: leave out vehicle, link and position");
        return false;
      }
      if (reads.has("link") && end.vehicle.empty()) {
        reads.error_at_key("link", "a link needs its `vehicle`");
        return false;
      }
      if (!end.free && end.vehicle.empty() && !reads.has("position")) {
        reads.error_at_key("free", "needs `vehicle` (and `position` in its link), `position` (fixed in W) or "
                                   "`free: true`");
        return false;
      }
      return true;
    });
  });
}

}  // namespace

const config::KeyTable<CableModel>& cable_keys() {
  return config::declare_keys<CableModel>([](config::KeyTable<CableModel>& t) {
    t.describe("cables[]",
               "a cable in the water (tether, umbilical, lift line, tow cable): a lumped-mass chain between two ends");
    t.string("name", &CableModel::name).required().doc("unique among the cables");
    t.number("length", [](CableModel& c) -> double& { return c.spec.length; }).required().unit("m")
        .range(Range::positive()).doc("unstretched");
    t.number("segments", [](CableModel& c) -> int& { return c.spec.segments; }).range(Range::closed(1.0, 10000.0))
        .doc("lumped-mass segments");
    t.number("diameter", [](CableModel& c) -> double& { return c.spec.diameter; }).required().unit("m")
        .range(Range::positive()).doc("outer (drag, buoyancy)");
    t.number("density", [](CableModel& c) -> double& { return c.spec.density; }).required().unit("kg/m^3")
        .range(Range::positive()).doc("the cable's mass per volume of its outer diameter (its mass per metre / area)");
    t.number("axial_stiffness", [](CableModel& c) -> double& { return c.spec.axial_stiffness; }).required()
        .unit("N").range(Range::positive()).doc("EA");
    t.number("damping_s", [](CableModel& c) -> double& { return c.spec.damping_s; }).unit("s")
        .range(Range::closed(0.0, 10.0)).doc("Kelvin-Voigt axial damping: EA x this x the strain rate");
    t.number("normal_drag_coefficient", [](CableModel& c) -> double& { return c.spec.normal_drag_coefficient; })
        .range(Range::closed(0.0, 10.0)).doc("C_dn, on the diameter, against the flow across the cable");
    t.number("tangential_drag_coefficient",
             [](CableModel& c) -> double& { return c.spec.tangential_drag_coefficient; })
        .range(Range::closed(0.0, 1.0)).doc("C_dt, on the circumference, against the flow along the cable");
    t.number("normal_added_mass_coefficient",
             [](CableModel& c) -> double& { return c.spec.normal_added_mass_coefficient; })
        .range(Range::closed(0.0, 10.0)).doc("C_an: the water accelerated with the cable across it");
    t.number("seabed_stiffness", [](CableModel& c) -> double& { return c.spec.seabed_stiffness; })
        .unit("N/m per m").range(Range::positive()).doc("the seabed's push on a node in it, per metre of cable");
    t.number("friction", [](CableModel& c) -> double& { return c.spec.friction; }).range(Range::closed(0.0, 5.0))
        .doc("Coulomb coefficient on the seabed");
    t.rate_hz("rate_hz", &CableModel::rate_hz)
        .doc("samples per second of sim time of its topics: rt/hadal/cables/<name>/from, /to (the force on each end's "
             "holder, geometry_msgs/WrenchStamped) and /shape (nav_msgs/Path)");
    t.map("from", [](CableModel& c) -> CableEndSpec& { return c.ends[0]; }, cable_end_keys()).required()
        .doc("what holds its first end");
    t.map("to", [](CableModel& c) -> CableEndSpec& { return c.ends[1]; }, cable_end_keys()).required()
        .doc("what holds its other end");
    t.check([](const config::KeyReads& reads, CableModel& cable, config::NoContext&) {
      if (!cable.ends[0].free || !cable.ends[1].free) return true;
      reads.error_at_key("to", "a cable needs at least one held end");
      return false;
    });
  });
}

}  // namespace hadal::physics
