#include "hadal/config/vehicle_keys.h"

#include <algorithm>
#include <functional>
#include <map>
#include <utility>

#include "hadal/config/entry_keys.h"
#include "hadal/config/urdf_import.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/physics/actuator_kinds.h"
#include "hadal/physics/articulation.h"
#include "hadal/physics/control_vector.h"
#include "hadal/sensors/sensor_kinds.h"

namespace hadal::config {
namespace {

// --- sensors -------------------------------------------------------------------------------------------

struct SensorEntry {
  SensorSpec spec;
  std::size_t kind = 0;  // index into sensors::SensorKinds
};

const KeyTable<SensorEntry, VehicleContext>& sensor_entry_keys() {
  return declare_keys<SensorEntry, VehicleContext>([](KeyTable<SensorEntry, VehicleContext>& t) {
    t.describe("sensors[]",
               "a sensor on a link, published on rt/<vehicle>/<name> at rate_hz in sim "
               "time: the common keys, then those of its type");
    declare_name_key(t, "sensor", [](SensorEntry& e) -> std::string& { return e.spec.name; })
        .doc("unique in the vehicle; the topic's last part");
    std::vector<KeyTable<SensorEntry, VehicleContext>::Named<std::size_t>> types;
    std::vector<std::string> captured;
    std::vector<bool> on_joint, on_moving_link;
    sensors::SensorKinds::for_each([&](auto tag) {
      using Kind = typename decltype(tag)::type;
      types.push_back({std::string(Kind::kType), types.size()});
      if (Kind::kCaptures) captured.emplace_back(Kind::kType);
      on_joint.push_back(sensors::OnJoint<Kind>::value);
      on_moving_link.push_back(sensors::OnMovingLink<Kind>::value);
    });
    t.choice("type", &SensorEntry::kind, types).required().selects("sensor type").doc("the sensor's kind");
    declare_link_key(
        t, [](SensorEntry& e) -> int& { return e.spec.link_index; },
        LinkPlacement<SensorEntry>([on_joint, on_moving_link, types](const SensorEntry& e, const LinkSpec& link,
                                                                     bool moves) -> std::string {
          const std::string type = types.at(e.kind).name;
          const std::string a = std::string("aeiou").find(type.front()) == std::string::npos ? "a " : "an ";
          if (on_joint.at(e.kind)) {
            if (link.joint.type != JointType::kFixed) return "";
            return std::string("is not on a moving joint") +
                   (link.joint.locked_type != JointType::kFixed ? " (its joint's limits meet: it is locked)" : "") +
                   ": " + a + type + " sensor measures the wrench across its link's joint (revolute, continuous or " +
                   "prismatic)";
          }
          if (moves && !on_moving_link.at(e.kind)) {
            return "moves on a joint: " + a + type + " sensor reads its vehicle body's motion, which is not its " +
                   "link's: mount it on a link that does not move";
          }
          return "";
        }))
        .default_text("the base link")
        .doc("a link of this vehicle; the sensor follows it when it moves on a joint (not an imu or a dvl); "
             "force_torque: a link on a moving joint, whose joint it measures");
    t.pose("pose", [](SensorEntry& e) -> Eigen::Isometry3d& { return e.spec.X_LS; }).doc("mounting pose X_LS in the link frame");
    t.rate_hz("rate_hz", [](SensorEntry& e) -> double& { return e.spec.rate_hz; })
        .doc("samples per second of sim time (a preset may set it when not given)");
    t.string("frame_id", [](SensorEntry& e) -> std::string& { return e.spec.frame_id; }).default_text("`<vehicle>/<name>`")
        .doc("header.frame_id of the samples");
    t.number("latency_s", [](SensorEntry& e) -> double& { return e.spec.latency_s; }).only_for(captured).unit("s")
        .range(Range::closed(0.0, 10.0))
        .default_text("one sample period, 1 / rate_hz")
        .doc("from a capture to its publication, rounded up to whole physics steps; in real time a capture not "
             "ready by then is dropped, so 0 publishes nothing there");
    // A captured kind's default latency: one sample period, which the ray-cast workers have to make the capture
    // before the next one is taken (0 would drop every capture in real time: configs/REFERENCE.md, "Captured sensors").
    t.check([](const KeyReads& reads, SensorEntry& e, VehicleContext&) {
      if (e.spec.captured() && !reads.has("latency_s") && e.spec.rate_hz > 0.0) e.spec.latency_s = 1.0 / e.spec.rate_hz;
      return true;
    });
    t.check([on_joint](const KeyReads& reads, SensorEntry& e, VehicleContext&) {
      if (!on_joint.at(e.kind) || reads.has("link")) return true;
      reads.error_at_key("type", "a " + std::string(e.spec.type()) + " sensor needs `link`: the link on a moving " +
                                     "joint whose joint it measures");
      return false;
    });
    t.unused_note([](const MapReader&, const SensorEntry&) -> std::string {
      return " (it samples on the stepping thread, without latency)";
    });
    sensors::SensorKinds::for_each([&](auto tag) {
      using Kind = typename decltype(tag)::type;
      using Spec = typename Kind::Spec;
      t.variant(std::string(Kind::kType), Kind::keys(),
                [](const MapReader& map, const KeyTable<Spec, sensors::SensorReader>& kind, SensorEntry& e,
                   VehicleContext& c) {
                  Spec spec = kind.defaults();
                  sensors::SensorReader reader{c.actuator_names, c.actuator_types, map.has("rate_hz"), e.spec.rate_hz};
                  const bool ok = kind.read_map(map, &spec, reader);
                  e.spec.kind = std::move(spec);
                  return ok;
                });
    });
  });
}

// --- actuators -----------------------------------------------------------------------------------------

template <class Kind>
const KeyTable<ActuatorSpec, VehicleContext>& actuator_entry_keys() {
  return declare_keys<ActuatorSpec, VehicleContext>([](KeyTable<ActuatorSpec, VehicleContext>& t) {
    t.describe(std::string(Kind::kListKey) + "[]", Kind::keys().doc().title);
    declare_name_key(t, std::string(Kind::kType), &ActuatorSpec::name).doc("unique among the vehicle's actuators");
    declare_link_key(t, &ActuatorSpec::link_index).required().doc("the link it is mounted on");
    using Spec = typename Kind::Spec;
    t.part(Kind::keys(), [](const MapReader& map, const KeyTable<Spec>& kind, ActuatorSpec& a, VehicleContext&) {
      Spec spec = kind.defaults();
      NoContext none;
      const bool ok = kind.read_map(map, &spec, none);
      a.kind = std::move(spec);
      return ok;
    });
  });
}

// One actuator kind's list: appended to the definition's actuators, its controls to the control vector.
template <class Kind>
bool read_actuator_list(const Value& value, VehicleDefinition& d, VehicleContext& c) {
  const auto items = value.list();
  if (!items) {
    d.control_count.reset();
    d.control_names.reset();
    return false;
  }
  if (d.control_count) *d.control_count += items->size() * Kind::kControls;
  c.links = &d.links;  // an actuator on a link that moves is refused at its `link`
  std::swap(c.names_taken, c.actuator_names_taken);  // unique across every actuator list
  bool ok = true;
  for (const Value& item : *items) {
    ActuatorSpec actuator;
    ok &= actuator_entry_keys<Kind>().read(item, &actuator, c);
    if (!actuator.name.empty() && d.control_names) {
      for (std::size_t k = 0; k < Kind::kControls; ++k) {
        d.control_names->push_back(Kind::kControls == 1 ? actuator.name : actuator.name + "[" + std::to_string(k) + "]");
      }
      d.actuator_names.push_back(actuator.name);
      d.actuator_types.emplace_back(Kind::kType);
    } else {
      d.control_names.reset();
    }
    d.actuators.push_back(std::move(actuator));
  }
  std::swap(c.names_taken, c.actuator_names_taken);
  return ok;
}

// Checks over the whole link list (YAML's and a URDF's), its locked joints first made fixed at their locks
// (lock_joints): joint names unique among the reported joints, and the tree as the physics builds it
// (physics/articulation.h: each moving body's mass and inertia, joint axes and limits). `at(l)` is where link
// l's problems are reported, `whole` where the tree's are.
bool check_link_tree(VehicleDefinition& d, const std::function<Value(std::size_t)>& at, const Value& whole) {
  bool ok = true;
  lock_joints(d.links);
  // Joint names (a link's own unless its joint names itself), locked ones too (JointState reports them).
  std::map<std::string, std::string> joint_owner;
  for (std::size_t l = 0; l < d.links.size(); ++l) {
    if (!reports_joint(d.links[l])) continue;
    const auto [it, inserted] = joint_owner.emplace(joint_name(d.links[l]), d.links[l].name);
    if (!inserted) {
      at(l).error("joint name " + config::quoted(it->first) + " (link " + config::quoted(d.links[l].name) +
                  ") is taken by the joint of link " + config::quoted(it->second));
      ok = false;
    }
  }
  if (!ok) return false;
  try {
    const physics::Articulation articulation(d.links);
  } catch (const std::invalid_argument& e) {
    whole.error(std::string(e.what()).substr(std::string("articulation: ").size()));
    return false;
  }
  return true;
}

// A vehicle's `urdf`: its links appended to those of `links` (docs/ARCHITECTURE.md, "URDF import").
bool read_urdf(const Value& value, VehicleDefinition& d, VehicleContext& c) {
  UrdfMount mount = urdf_keys().defaults();
  if (!urdf_keys().read(value, &mount, c)) return false;
  if (!d.links.empty() && !d.link_names) return false;  // `links` were unusable (reported)
  int parent_index = 0;
  if (!mount.parent.empty()) {
    const Value parent = value.in_same_file(value.node()["parent"], child_path(value.path(), "parent"),
                                            value.node()["parent"].Mark());
    if (d.links.empty()) {
      parent.error("needs `links` (without them the URDF's root is the base link)");
      return false;
    }
    const auto index = read_link_reference(parent, d.link_names);
    if (!index) return false;
    parent_index = *index;
  }
  const std::size_t before = d.links.size();
  bool ok = import_urdf(value, mount, parent_index, &d.links);
  if (!d.link_names) d.link_names.emplace();
  for (std::size_t l = before; l < d.links.size(); ++l) {
    const std::string& name = d.links[l].name;
    if (std::find(d.link_names->begin(), d.link_names->end(), name) != d.link_names->end()) {
      value.error("the URDF's link " + quoted(name) + " has the name of a link in `links`");
      ok = false;
    }
    d.link_names->push_back(name);
  }
  c.link_names = d.link_names;
  c.links = &d.links;
  if (!ok) return false;
  return check_link_tree(d, [&](std::size_t) { return value; }, value);
}

// What the sensors and lights of a definition refer to: its links and actuators.
void refer_to(const VehicleDefinition& d, VehicleContext& c) {
  c.link_names = d.link_names;
  c.links = &d.links;
  c.actuator_names = d.control_names ? d.actuator_names : std::vector<std::string>();
  c.actuator_types = d.control_names ? d.actuator_types : std::vector<std::string>();
}

// The keys of a vehicle definition, or (object) of an object's: no type, actuators, sensors, lights or joint
// controllers.
void declare_definition_keys(KeyTable<VehicleDefinition, VehicleContext>& t, bool object) {
  if (object) {
    t.describe("object",
               "an object's definition (a sample, a rock, a crate): an object file, or inline in an "
               "object entry; its links and fluid model, as a vehicle's");
  } else {
    t.describe("vehicle", "a vehicle definition: a vehicle file, or inline in a vehicle entry");
    t.choice("type", &VehicleDefinition::type,
             {{"auv", VehicleType::kAuv},
              {"rov", VehicleType::kRov},
              {"lander", VehicleType::kLander},
              {"surface_vessel", VehicleType::kSurfaceVessel},
              {"glider", VehicleType::kGlider},
              {"crawler", VehicleType::kCrawler}})
        .required()
        .unless("include")
        .doc(
            "the vehicle's class, a label for tools and logs; what it does comes from its links, actuators and "
            "sensors");
  }
  t.choice("seabed_contact", &VehicleDefinition::seabed_contact,
           {{"rigid", SeabedContact::kRigid,
             "Bullet's rigid contact of the collision shapes (friction: each link's `friction` times the seabed's 0.8, "
             "0.4 by default; no bounce)"},
            {"soil", SeabedContact::kSoil,
             "world.soil presses and shears every face of the surface that sinks into the seabed, instead of Bullet"}})
      .unless("include")
      .doc("how the vehicle meets the seabed; soil needs a link with a mesh or collision shapes");
  t.list("links", &VehicleDefinition::links, geometry::link_keys())
      .required()
      .unless("include")
      .optional_with("urdf")
      .min_items(1)
      .read_with([](const Value& value, VehicleDefinition& d, VehicleContext& c) {
        const auto items = value.list();
        if (!items) return false;
        bool ok = true;
        if (items->empty()) {
          value.error("must not be empty (links[0] is the base link)");
          ok = false;
        }
        d.link_names.emplace();
        c.names_taken.clear();
        for (const Value& item : *items) {
          c.link_names = d.link_names;  // the earlier links: a `parent` names one of them
          LinkSpec link = geometry::link_keys().defaults();
          ok &= geometry::link_keys().read(item, &link, c);
          // `pose` of a link with a parent is X_PL: X_BL at q = 0 through the parent's.
          if (link.parent >= 0) link.X_BL = d.links[static_cast<std::size_t>(link.parent)].X_BL * link.X_BL;
          if (!link.name.empty() && d.link_names) {
            d.link_names->push_back(link.name);
          } else {
            d.link_names.reset();
          }
          d.links.push_back(std::move(link));
        }
        c.link_names = d.link_names;
        return ok && check_link_tree(
                         d, [&](std::size_t l) { return (*items)[l]; }, value);
      })
      .doc(
          "rigid bodies; links[0] is the base link, the others hang on it or on a `parent` through a `joint` "
          "(fixed by default)");
  t.custom("urdf", read_urdf, "", "map")
      .keys_of(urdf_keys())
      .unless("include")
      .doc("links and joints from a URDF file, after those of `links` (or instead of them)");
  if (object) {
    t.check([](const KeyReads&, VehicleDefinition& d, VehicleContext&) {
      d.type = VehicleType::kObject;
      return true;
    });
  }
  if (!object) {
    physics::ActuatorKinds::for_each([&](auto tag) {
      using Kind = typename decltype(tag)::type;
      t.custom(std::string(Kind::kListKey), read_actuator_list<Kind>, "", "list of maps")
          .items_of(actuator_entry_keys<Kind>())
          .unless("include")
          .doc(std::string("the vehicle's ") + std::string(Kind::kType) + " actuators; their controls follow in the " +
               "control vector, kinds in this order, each in list order");
    });
    t.custom(
         "sensors",
         [](const Value& value, VehicleDefinition& d, VehicleContext& c) {
           const auto items = value.list();
           if (!items) return false;
           refer_to(d, c);
           c.names_taken.clear();
           for (const SensorSpec& sensor : d.sensors) c.names_taken.emplace(sensor.name, d.source_file);
           bool ok = true;
           for (const Value& item : *items) {
             SensorEntry entry;
             ok &= sensor_entry_keys().read(item, &entry, c);
             d.sensors.push_back(std::move(entry.spec));
           }
           return ok;
         },
         "", "list of maps")
        .items_of(sensor_entry_keys())
        .doc("sensors, each published on rt/<vehicle>/<name>");
    t.list("lights", &VehicleDefinition::lights, render::light_keys())
        .read_with([](const Value& value, VehicleDefinition& d, VehicleContext& c) {
          const auto items = value.list();
          if (!items) return false;
          refer_to(d, c);
          c.names_taken.clear();
          for (const LightSpec& light : d.lights) c.names_taken.emplace(light.name, d.source_file);
          bool ok = true;
          for (const Value& item : *items) {
            LightSpec light = render::light_keys().defaults();
            ok &= render::light_keys().read(item, &light, c);
            d.lights.push_back(std::move(light));
          }
          return ok;
        })
        .doc("spot lights that cameras see by");
    t.custom(
         "joint_controllers",
         [](const Value& value, VehicleDefinition& d, VehicleContext& c) {
           const auto items = value.list();
           if (!items) return false;
           refer_to(d, c);
           c.names_taken.clear();
           for (const auto& controller : d.joint_controllers) c.names_taken.emplace(controller.name, d.source_file);
           // Which group drives each joint so far (a joint is in one group at most).
           std::map<int, std::string> owner;
           for (const auto& controller : d.joint_controllers) {
             for (int joint : controller.joints) owner.emplace(joint, controller.name);
           }
           bool ok = true;
           for (const Value& item : *items) {
             physics::JointControllerSpec controller = physics::joint_controller_keys().defaults();
             if (!physics::joint_controller_keys().read(item, &controller, c)) {
               ok = false;
               continue;
             }
             for (int joint : controller.joints) {
               const auto [it, inserted] = owner.emplace(joint, controller.name);
               if (!inserted) {
                 std::string name = std::to_string(joint);
                 for (std::size_t l = 0, dof = 0; l < d.links.size(); ++l) {
                   if (d.links[l].joint.type == JointType::kFixed) continue;
                   if (dof++ == static_cast<std::size_t>(joint)) name = joint_name(d.links[l]);
                 }
                 item.error("joint " + config::quoted(name) + " is already driven by joint controller " +
                            config::quoted(it->second) + " (a joint is in one controller at most)");
                 ok = false;
               }
             }
             d.joint_controllers.push_back(std::move(controller));
           }
           return ok;
         },
         "", "list of maps")
        .items_of(physics::joint_controller_keys())
        .doc("groups of an articulated vehicle's joints commanded together (position, velocity or effort)");
    t.map("transponder", &VehicleDefinition::transponder, sensors::transponder_keys())
        .doc("an acoustic transponder, which USBLs interrogate (none by default)");
  }
  t.map("fluid", &VehicleDefinition::fluid, physics::fluid_keys())
      .unless("include")
      .read_with([](const Value& value, VehicleDefinition& d, VehicleContext& c) {
        d.fluid = physics::default_fluid(d.links);
        c.links = &d.links;
        return physics::fluid_keys().read(value, &d.fluid, c);
      })
      .default_text("`surface` with added mass fitted to the hull, or `lumped` without link geometry")
      .doc("the fluid model");
  t.check([](const KeyReads& reads, VehicleDefinition& d, VehicleContext&) {
    if (!reads.has("fluid")) d.fluid = physics::default_fluid(d.links);
    if (d.seabed_contact == SeabedContact::kSoil && !d.links.empty() && !geometry::has_surface_geometry(d.links)) {
      reads.error_at_key("seabed_contact",
                         "soil contact presses on the vehicle's surface, and no link has a mesh or collision shapes");
      return false;
    }
    return true;
  });
}

}  // namespace

const KeyTable<VehicleDefinition, VehicleContext>& definition_keys() {
  return declare_keys<VehicleDefinition, VehicleContext>(
      [](KeyTable<VehicleDefinition, VehicleContext>& t) { declare_definition_keys(t, false); });
}

const KeyTable<VehicleDefinition, VehicleContext>& object_definition_keys() {
  return declare_keys<VehicleDefinition, VehicleContext>(
      [](KeyTable<VehicleDefinition, VehicleContext>& t) { declare_definition_keys(t, true); });
}

const KeyTable<SetpointKeyframe>& keyframe_keys() {
  return declare_keys<SetpointKeyframe>([](KeyTable<SetpointKeyframe>& t) {
    t.describe("schedule[]", "from time_s on (zero-order hold), the vehicle's actuators take `setpoints`");
    t.number("time_s", &SetpointKeyframe::time).required().unit("s").range(Range::non_negative())
        .rule("strictly increasing along the list").doc("sim time");
    t.numbers(
         "setpoints", 0, [](SetpointKeyframe& k, const std::vector<double>& v) { k.setpoints = v; }, nullptr)
        .required()
        .range(Range::closed(-1.0, 1.0))
        .rule("one per control, passing its actuator's own check")
        .doc("the vehicle's control vector, in control-vector order");
  });
}

namespace {

// The keys of a vehicle entry, or (object) of an object entry: no actuators, so no command timeout,
// actuator states or schedule.
void declare_entry_keys(KeyTable<VehicleSpec, LoadContext>& t, bool object) {
  if (object) {
    t.describe("objects[]",
               "a free object (a sample, a rock, a crate): its definition from `include` or inline, where it "
               "starts; it rests on the seabed, sinks or floats by its own fluid model, can be grasped, carried and "
               "dropped, and its ground truth is published on rt/<name>/odometry");
  } else {
    t.describe("vehicles[]",
               "a vehicle: its definition either from `include` (which the entry may extend "
               "with sensors and lights) or inline, where it starts, its rates and schedule");
  }
  t.string("name", &VehicleSpec::name)
      .required()
      .read_elsewhere()
      .rule("[A-Za-z][A-Za-z0-9_]*, unique among vehicles and objects")
      .doc("a topic segment: rt/<name>/...");
  t.string("include", &VehicleSpec::source_file)
      .read_elsewhere()
      .doc(object
               ? "an object file, relative to this file; not with the inline definition keys"
               : "a vehicle file, relative to this file; not with the inline definition keys but sensors and lights");
  t.pose("initial_pose", &VehicleSpec::X_WB_initial).doc("X_WB at t = 0");
  t.boolean("static", &VehicleSpec::is_static)
      .doc(
          "fixed at its initial pose (a prop, a fixed instrument): no forces, never moves, others collide with "
          "it; its sensors still sample");
  t.vector("initial_velocity", &VehicleSpec::v_WB_initial).unit("m/s").doc("v_WB in W");
  t.vector("initial_angular_velocity", &VehicleSpec::w_WB_initial)
      .unit("rad/s")
      .range(Range::closed(-100.0, 100.0))
      .doc("w_WB in W (a tumbling calibration target, say)");
  if (!object) {
    t.number("command_timeout_s", &VehicleSpec::command_timeout)
        .unit("s")
        .range(Range::positive())
        .doc("the actuators stop when no command arrives for this long (sim time)");
  }
  t.rate_hz("odometry_rate_hz", &VehicleSpec::odometry_rate_hz).doc("rate of rt/<vehicle>/odometry");
  if (!object) {
    t.rate_hz("actuator_state_rate_hz", &VehicleSpec::actuator_state_rate_hz)
        .doc("rate of every actuator kind's state topic (rt/<vehicle>/<kind>/state)");
    t.renamed("thruster_state_rate_hz", "actuator_state_rate_hz", "it sets every actuator kind's state rate");
    t.list("schedule", &VehicleSpec::schedule, keyframe_keys())
        .read_elsewhere()
        .doc(
            "an open-loop schedule that drives the vehicle until a client first commands it; before its first "
            "keyframe the setpoints are zero");
  }
  // Read by the scenario loader, which resolves `include`.
  t.part(object ? object_definition_keys() : definition_keys());
  t.check([](const KeyReads& reads, VehicleSpec& v, LoadContext&) {
    if (!v.is_static) return true;
    bool ok = true;
    for (const char* key : {"initial_velocity", "initial_angular_velocity"}) {
      const bool moving =
          std::string(key) == "initial_velocity" ? !v.v_WB_initial.isZero(0.0) : !v.w_WB_initial.isZero(0.0);
      if (reads.has(key) && reads.ok(key) && moving) {
        reads.error_at_key(key, "a static vehicle never moves (static: true): leave it out");
        ok = false;
      }
    }
    return ok;
  });
}

}  // namespace

const KeyTable<VehicleSpec, LoadContext>& vehicle_entry_keys() {
  return declare_keys<VehicleSpec, LoadContext>(
      [](KeyTable<VehicleSpec, LoadContext>& t) { declare_entry_keys(t, false); });
}

const KeyTable<VehicleSpec, LoadContext>& object_entry_keys() {
  return declare_keys<VehicleSpec, LoadContext>(
      [](KeyTable<VehicleSpec, LoadContext>& t) { declare_entry_keys(t, true); });
}

}  // namespace hadal::config
