// The keys of a scenario's cables (physics/cable.h), each declared once (config/key_table.h).
#include "hadal/config/key_table.h"
#include "hadal/physics/cable.h"

namespace hadal::physics {

using config::Range;

const config::KeyTable<WinchSpec>& winch_keys() {
  return config::declare_keys<WinchSpec>([](config::KeyTable<WinchSpec>& t) {
    t.describe("cables[].from.winch",
               "a winch holding the end: pays the cable out or hauls it in at a commanded speed (topic "
               "rt/hadal/cables/<name>/winch/command, or attached to a lockstep step request); its state on "
               "rt/hadal/cables/<name>/winch/state");
    t.number("drum_length", &WinchSpec::drum_length).required().unit("m").range(Range::positive())
        .doc("cable it holds, in the water and on the drum together: at least the cable's `length` (what is in the "
             "water at the start)");
    t.number("min_length", &WinchSpec::min_length).unit("m").range(Range::positive())
        .doc("hauling in stops with this much in the water");
    t.number("max_speed", &WinchSpec::max_speed).unit("m/s").range(Range::positive())
        .doc("the fastest line speed it takes a command for");
    t.number("max_acceleration", &WinchSpec::max_acceleration).unit("m/s^2").range(Range::positive())
        .doc("how fast its line speed changes (it also brakes at this rate to stop at a target or a limit)");
    t.check([](const config::KeyReads& reads, WinchSpec& winch, config::NoContext&) {
      if (winch.min_length < winch.drum_length) return true;
      reads.error_at_key("min_length", "must be less than drum_length (" + config::format_number(winch.drum_length) + " m)");
      return false;
    });
  });
}

const config::KeyTable<CableEndSpec>& cable_end_keys() {
  return config::declare_keys<CableEndSpec>([](config::KeyTable<CableEndSpec>& t) {
    t.describe("cables[].from", "what holds an end of a cable: a point fixed in W, a point on a vehicle's link, or nothing");
    t.string("vehicle", &CableEndSpec::vehicle).default_text("none: fixed in W").doc("the vehicle it is attached to");
    t.string("link", &CableEndSpec::link).default_text("the base link").doc("the vehicle's link it is attached to");
    t.vector("position", &CableEndSpec::position).unit("m")
        .doc("on a vehicle: in its link's frame; else the fixed point in W");
    t.vector("velocity", &CableEndSpec::velocity_W).unit("m/s")
        .doc("fixed in W only: the point moves at this velocity from `position` at t = 0 (a tow point on a ship whose "
             "course the cable does not change)");
    t.boolean("free", &CableEndSpec::free).doc("true: nothing holds this end (it trails)");
    t.map("winch", &CableEndSpec::winch, winch_keys()).doc("a winch at this end (at most one per cable)");
    t.check([](const config::KeyReads& reads, CableEndSpec& end, config::NoContext&) {
      if (end.free && (reads.has("vehicle") || reads.has("link") || reads.has("position") || reads.has("winch") ||
                       reads.has("velocity"))) {
        reads.error_at_key("free", "a free end is held by nothing: leave out vehicle, link, position, velocity and winch");
        return false;
      }
      if (reads.has("velocity") && !end.vehicle.empty()) {
        reads.error_at_key("velocity", "an end on a vehicle moves with its link: `velocity` is for a point fixed in W");
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
    t.number("bending_stiffness", [](CableModel& c) -> double& { return c.spec.bending_stiffness; }).unit("N m^2")
        .range(Range::non_negative()).doc("EI: a stiff umbilical resists bending; 0 bends freely (a wire rope, a "
                                         "tether). The ends are pinned: no moment where it is held");
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
      if (cable.ends[0].free && cable.ends[1].free) {
        reads.error_at_key("to", "a cable needs at least one held end");
        return false;
      }
      if (cable.ends[0].winch && cable.ends[1].winch) {
        reads.error_at_key("to", "a cable has at most one winch (`from` has one)");
        return false;
      }
      return true;
    });
  });
}

}  // namespace hadal::physics
