// The keys of a vehicle (docs/ARCHITECTURE.md, "Keys: one declaration each"): its definition (a vehicle
// file's root, or inline in a scenario's vehicle entry) and the entry itself, with the entries of its lists
// (links, the actuator kinds' lists, sensors, lights). The scenario loader (config/scenario_loader.h)
// resolves includes and cross-file references; these tables say what each key is and read it.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hadal/config/key_table.h"
#include "hadal/config/vehicle_context.h"
#include "hadal/core/model.h"

namespace hadal::config {

// What a vehicle definition (inline or included) yields, plus what cross-checks need to know about it.
struct VehicleDefinition {
  std::string source_file;
  VehicleType type = VehicleType::kAuv;
  SeabedContact seabed_contact = SeabedContact::kRigid;
  std::vector<LinkSpec> links;
  std::vector<ActuatorSpec> actuators;
  std::vector<SensorSpec> sensors;
  std::vector<LightSpec> lights;
  std::optional<sensors::TransponderSpec> transponder;
  std::vector<physics::JointControllerSpec> joint_controllers;
  FluidSpec fluid;
  // Length and names of the control vector, or nullopt when an actuator list itself is unusable (not a
  // list, an actuator without a valid name): the schedule's setpoint count is then not checked.
  std::optional<std::size_t> control_count = 0;
  std::optional<std::vector<std::string>> control_names = std::vector<std::string>();
  // Names and kinds of the actuators (for sensors that refer to one); empty when a name is unusable.
  std::vector<std::string> actuator_names;
  std::vector<std::string> actuator_types;
  // The links' names (nullopt when some link has no usable name), for entries that extend an included
  // definition with sensors and lights.
  std::optional<std::vector<std::string>> link_names;
};

// The keys of a vehicle definition: a vehicle file's root, or inline in a scenario's vehicle entry.
const KeyTable<VehicleDefinition, VehicleContext>& definition_keys();
// The keys of a scenario's vehicle entry besides the definition's: name, include, where it starts, rates,
// schedule. `name`, `include` and `schedule` are read by the scenario loader.
const KeyTable<VehicleSpec, LoadContext>& vehicle_entry_keys();
// An object's (a scenario's `objects`: a sample, a rock, a crate): a definition without type, actuators,
// sensors, lights or joint controllers, and an entry without what only actuators need. Objects become
// VehicleSpecs of type kObject after the vehicles.
const KeyTable<VehicleDefinition, VehicleContext>& object_definition_keys();
const KeyTable<VehicleSpec, LoadContext>& object_entry_keys();
// The keys of a schedule keyframe.
const KeyTable<SetpointKeyframe>& keyframe_keys();

}  // namespace hadal::config
