#include "hadal/physics/joint_servo.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "hadal/config/entry_keys.h"
#include "hadal/geometry/link_spec.h"

namespace hadal::physics {

using namespace config::keys;
using config::VehicleContext;

ServoStep joint_servo_step(const JointServoSpec& spec, JointCommandMode mode, double target, double q, double qd,
                           double dt, double target_rate) {
  ServoStep step;
  step.torque = target;
  switch (mode) {
    case JointCommandMode::kPosition:
    case JointCommandMode::kGripper: {
      // kp (q* - q) + kd (qd* - qd) = kd (qd_wanted - qd) with qd_wanted = kp (q* - q) / kd + qd*: that
      // rate is what the velocity limit bounds (a PD law without kd has no rate to bound, nor a rate to feed
      // forward). At the step's end, q' = q + dt qd + dt^2 qdd and qd' = qd + dt qdd.
      const double q_end = q + dt * qd;
      if (spec.kd > 0.0) {
        const double wanted = spec.kp * (target - q_end) / spec.kd + target_rate;
        if (std::abs(wanted) < spec.velocity_limit) {
          step.torque = spec.kp * (target - q_end) + spec.kd * (target_rate - qd);
          step.D = spec.kp * dt * dt + spec.kd * dt;
        } else {
          step.torque = spec.kd * (std::copysign(spec.velocity_limit, wanted) - qd);
          step.D = spec.kd * dt;
        }
      } else {
        step.torque = spec.kp * (target - q_end);
        step.D = spec.kp * dt * dt;
      }
      break;
    }
    case JointCommandMode::kVelocity:
      step.torque = spec.kd * (std::clamp(target, -spec.velocity_limit, spec.velocity_limit) - qd);
      step.D = spec.kd * dt;
      break;
    case JointCommandMode::kEffort:
      break;
  }
  return step;
}

double joint_servo_torque(const JointServoSpec& spec, JointCommandMode mode, double target, double q, double qd,
                          double target_rate) {
  return std::clamp(joint_servo_step(spec, mode, target, q, qd, 0.0, target_rate).torque, -spec.effort_limit,
                    spec.effort_limit);
}

const char* to_string(JointCommandMode mode) {
  switch (mode) {
    case JointCommandMode::kPosition: return "position";
    case JointCommandMode::kVelocity: return "velocity";
    case JointCommandMode::kEffort: return "effort";
    case JointCommandMode::kGripper: return "gripper";
  }
  return "?";
}

namespace {

constexpr const char* kGainsSchema =
    R"({"oneOf": [{"type": "number"}, {"type": "array", "items": {"type": "number"}, "minItems": 1}]})";

// A gain: one number, or a list of them (one per joint; the table's check matches it to `joints`).
bool read_gains(const config::Value& value, const Range& range, std::vector<double>* gains) {
  if (value.node().IsSequence()) {
    const auto numbers = value.numbers(std::nullopt, range);
    if (!numbers) return false;
    if (numbers->empty()) {
      value.error("must not be empty");
      return false;
    }
    *gains = *numbers;
    return true;
  }
  const auto number = value.number(range);
  if (!number) return false;
  *gains = {*number};
  return true;
}

// `joints`: names of links on moving joints, each once; into their indices among the moving joints.
bool read_controlled_joints(const config::Value& value, JointControllerSpec& controller, VehicleContext& c) {
  const auto items = value.list();
  if (!items) return false;
  if (items->empty()) {
    value.error("must name at least one joint");
    return false;
  }
  if (!c.link_names || !c.links) return true;  // the links were unusable (reported already)
  // The moving joints' names, in state order.
  std::vector<std::string> names;
  std::vector<const JointSpec*> joints;
  for (const LinkSpec& link : *c.links) {
    if (link.joint.type == JointType::kFixed) continue;
    names.push_back(joint_name(link));
    joints.push_back(&link.joint);
  }
  bool ok = true;
  for (const config::Value& item : *items) {
    const auto name = item.string();
    if (!name) {
      ok = false;
      continue;
    }
    const auto found = std::find(names.begin(), names.end(), *name);
    const auto locked = std::find_if(c.links->begin(), c.links->end(), [&](const LinkSpec& link) {
      return link.joint.locked_type != JointType::kFixed && joint_name(link) == *name;
    });
    if (found == names.end() && locked != c.links->end()) {
      item.error("joint " + config::quoted(*name) + " is locked (its limits meet): nothing can move it");
      ok = false;
      continue;
    }
    if (found == names.end()) {
      item.error("no moving joint named " + config::quoted(*name) + " in this vehicle" +
                 (names.empty() ? std::string(" (it has none)") : " (joints: " + config::join_names(names) + ")"));
      ok = false;
      continue;
    }
    const int dof = static_cast<int>(found - names.begin());
    // A URDF's <limit effort="0"> (velocity="0"): the joint has no motor (it cannot move by command).
    const JointSpec& joint = *joints[static_cast<std::size_t>(dof)];
    if (!(joint.effort_limit > 0.0) || !(joint.velocity_limit > 0.0)) {
      item.error("joint " + config::quoted(*name) + " has no motor (its " +
                 (joint.effort_limit > 0.0 ? "velocity" : "effort") + " limit is 0)");
      ok = false;
      continue;
    }
    if (std::find(controller.joints.begin(), controller.joints.end(), dof) != controller.joints.end()) {
      item.error("joint " + config::quoted(*name) + " is listed twice");
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
        .doc("unique within the vehicle; its commands come on rt/<vehicle>/<name>/commands (not `actuators`), a "
             "position group's trajectories on rt/<vehicle>/<name>/joint_trajectory");
    t.check([](const config::KeyReads& reads, JointControllerSpec& controller, VehicleContext&) {
      if (controller.name != "actuators") return true;
      reads.error_at_key("name", "'actuators' is taken: rt/<vehicle>/actuators/commands carries the control vector");
      return false;
    });
    t.choice("type", &JointControllerSpec::mode,
             {{"position", JointCommandMode::kPosition,
               "kd (clamp(kp (q* - q) / kd + q_dot*, +-velocity_limit) - q_dot), q_dot* a trajectory's rate"},
              {"velocity", JointCommandMode::kVelocity, "kd (clamp(q_dot*, +-velocity_limit) - q_dot)"},
              {"effort", JointCommandMode::kEffort, "the commanded torque (force)"},
              {"gripper", JointCommandMode::kGripper,
               "fingers moved together: a command [position] or [position, max_effort] holds finger j at "
               "multipliers[j] x position by the position law, its effort within max_effort if given"}})
        .required()
        .selects("joint controller type")
        .doc("what a command sets; every joint's torque stays within its effort_limit");
    t.custom("joints", read_controlled_joints, R"({"type": "array", "items": {"type": "string"}, "minItems": 1})",
             "list of joint names")
        .required()
        .doc("the joints it drives (by name: a link's own unless its joint names itself), in command order");
    t.custom("kp", [](const config::Value& value, JointControllerSpec& c, VehicleContext&) {
           return read_gains(value, Range::positive(), &c.kp);
         }, kGainsSchema, "number or list of numbers")
        .only_for({"position", "gripper"}).required_for({"position", "gripper"}).unit("N m/rad or N/m")
        .range(Range::positive())
        .doc("stiffness: one for every joint, or one per joint in `joints` order");
    t.custom("kd", [](const config::Value& value, JointControllerSpec& c, VehicleContext&) {
           return read_gains(value, Range::non_negative(), &c.kd);
         }, kGainsSchema, "number or list of numbers")
        .only_for({"position", "velocity", "gripper"}).required_for({"velocity"}).unit("N m s/rad or N s/m")
        .range(Range::non_negative())
        .default_text("0 (position: a plain kp law, no rate limit)")
        .doc("damping gain: one for every joint, or one per joint in `joints` order");
    t.custom("multipliers", [](const config::Value& value, JointControllerSpec& c, VehicleContext&) {
           const auto items = value.list();
           if (!items) return false;
           bool ok = true;
           for (const config::Value& item : *items) {
             const auto m = item.number(Range::finite());
             if (m && *m == 0.0) item.error("a finger's multiplier must not be 0 (the finger would not move)");
             ok = ok && m && *m != 0.0;
             if (m) c.multipliers.push_back(*m);
           }
           return ok;
         }, R"({"type": "array", "items": {"type": "number"}, "minItems": 1})", "list of numbers")
        .only_for({"gripper"})
        .default_text("1 for every joint")
        .doc("each finger's position per unit of the gripper's command, in `joints` order (URDF's mimic "
             "multiplier: -1 for a finger whose joint opens the other way)");
    // One gain for the group stands for each joint's; a list has one per joint.
    t.check([](const config::KeyReads& reads, JointControllerSpec& c, VehicleContext&) {
      bool ok = true;
      if (c.mode == JointCommandMode::kGripper) {
        if (c.multipliers.empty()) c.multipliers.assign(c.joints.size(), 1.0);
        if (c.multipliers.size() != c.joints.size() && !c.joints.empty() && reads.ok("joints")) {
          reads.error_at_key("multipliers", "has " + std::to_string(c.multipliers.size()) + " multipliers for " +
                                                std::to_string(c.joints.size()) + " joints (one per joint)");
          ok = false;
        }
      }
      for (auto [key, gains] : {std::pair{"kp", &c.kp}, std::pair{"kd", &c.kd}}) {
        if (gains->size() == 1) gains->resize(c.joints.size(), gains->front());
        const bool positional = c.mode == JointCommandMode::kPosition || c.mode == JointCommandMode::kGripper;
        if (gains->empty() && positional) gains->resize(c.joints.size(), 0.0);
        if (!gains->empty() && gains->size() != c.joints.size() && !c.joints.empty() && reads.ok("joints")) {
          reads.error_at_key(key, "has " + std::to_string(gains->size()) + " gains for " +
                                      std::to_string(c.joints.size()) + " joints (give one, or one per joint)");
          ok = false;
        }
      }
      return ok;
    });
  });
}

}  // namespace hadal::physics
