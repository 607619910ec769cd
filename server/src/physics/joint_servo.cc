#include "hadal/physics/joint_servo.h"

#include <algorithm>
#include <string>

#include "hadal/config/entry_keys.h"
#include "hadal/geometry/link_spec.h"

namespace hadal::physics {

using namespace config::keys;
using config::VehicleContext;

double joint_servo_torque(const JointServoSpec& spec, JointCommandMode mode, double target, double q, double qd) {
  double tau = target;
  switch (mode) {
    case JointCommandMode::kPosition: {
      // kp (q* - q) - kd qd = kd (qd_wanted - qd) with qd_wanted = kp (q* - q) / kd: that rate is what the
      // velocity limit bounds (a PD law without kd has no rate to bound).
      if (spec.kd > 0.0) {
        const double wanted = std::clamp(spec.kp * (target - q) / spec.kd, -spec.velocity_limit, spec.velocity_limit);
        tau = spec.kd * (wanted - qd);
      } else {
        tau = spec.kp * (target - q);
      }
      break;
    }
    case JointCommandMode::kVelocity:
      tau = spec.kd * (std::clamp(target, -spec.velocity_limit, spec.velocity_limit) - qd);
      break;
    case JointCommandMode::kEffort:
      break;
  }
  return std::clamp(tau, -spec.effort_limit, spec.effort_limit);
}

const char* to_string(JointCommandMode mode) {
  switch (mode) {
    case JointCommandMode::kPosition: return "position";
    case JointCommandMode::kVelocity: return "velocity";
    case JointCommandMode::kEffort: return "effort";
  }
  return "?";
}

namespace {

// `joints`: names of links on moving joints, each once; into their indices among the moving joints.
bool read_controlled_joints(const config::Value& value, JointControllerSpec& controller, VehicleContext& c) {
  const auto items = value.list();
  if (!items) return false;
  if (items->empty()) {
    value.error("must name at least one joint");
    return false;
  }
  if (!c.link_names || !c.links) return true;  // the links were unusable (reported already)
  bool ok = true;
  for (const config::Value& item : *items) {
    const auto index = config::read_link_reference(item, c.link_names);
    if (!index) {
      ok = false;
      continue;
    }
    const std::vector<LinkSpec>& links = *c.links;
    if (links[static_cast<std::size_t>(*index)].joint.type == JointType::kFixed) {
      item.error("link " + config::quoted(links[static_cast<std::size_t>(*index)].name) +
                 " has no moving joint (its `joint` is fixed)");
      ok = false;
      continue;
    }
    int dof = 0;
    for (int i = 0; i < *index; ++i) dof += links[static_cast<std::size_t>(i)].joint.type != JointType::kFixed;
    if (std::find(controller.joints.begin(), controller.joints.end(), dof) != controller.joints.end()) {
      item.error("joint " + config::quoted(links[static_cast<std::size_t>(*index)].name) + " is listed twice");
      ok = false;
      continue;
    }
    controller.joints.push_back(dof);
  }
  return ok;
}

}  // namespace

const config::KeyTable<JointControllerSpec, VehicleContext>& joint_controller_keys() {
  using Table = config::KeyTable<JointControllerSpec, VehicleContext>;
  return declare_keys<JointControllerSpec, VehicleContext>([](Table& t) {
    t.describe("joint_controllers[]",
               "a group of joints commanded together (ros2_control's shape): one value per joint");
    config::declare_name_key(t, "joint controller", &JointControllerSpec::name)
        .doc("unique within the vehicle; its commands come on rt/<vehicle>/<name>/commands (not `actuators`)");
    t.check([](const config::KeyReads& reads, JointControllerSpec& controller, VehicleContext&) {
      if (controller.name != "actuators") return true;
      reads.error_at_key("name", "'actuators' is taken: rt/<vehicle>/actuators/commands carries the control vector");
      return false;
    });
    t.choice("type", &JointControllerSpec::mode,
             {{"position", JointCommandMode::kPosition, "kd (clamp(kp (q* - q) / kd, +-velocity_limit) - q_dot)"},
              {"velocity", JointCommandMode::kVelocity, "kd (clamp(q_dot*, +-velocity_limit) - q_dot)"},
              {"effort", JointCommandMode::kEffort, "the commanded torque (force)"}})
        .required()
        .selects("joint controller type")
        .doc("what a command sets; every joint's torque stays within its effort_limit");
    t.custom("joints", read_controlled_joints, R"({"type": "array", "items": {"type": "string"}, "minItems": 1})",
             "list of link names")
        .required()
        .doc("the links whose joints it drives, in command order");
    t.number("kp", &JointControllerSpec::kp).only_for({"position"}).required_for({"position"})
        .unit("N m/rad or N/m").range(Range::positive()).doc("stiffness");
    t.number("kd", &JointControllerSpec::kd).only_for({"position", "velocity"}).required_for({"velocity"})
        .unit("N m s/rad or N s/m").range(Range::non_negative())
        .default_text("0 (position: a plain kp law, no rate limit)").doc("damping gain");
  });
}

}  // namespace hadal::physics
