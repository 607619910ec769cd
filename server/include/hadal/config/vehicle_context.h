// What the readers of a vehicle definition's entries (links, actuators, sensors, lights) know besides
// their own map, and the custom keys they share: a name unique within its list, a reference to one of
// the vehicle's links.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hadal {
struct LinkSpec;
}

namespace hadal::config {

class Value;

struct VehicleContext {
  // Bounds a rate; nullopt when world.physics_rate_hz is invalid (LoadContext).
  std::optional<double> physics_rate_hz;
  // The vehicle's link names, or nullopt when some link has no usable name (a reference is then not
  // checked: the bad link list was reported already).
  std::optional<std::vector<std::string>> link_names;
  // The vehicle's actuators' names and kinds, in control-vector order (a sensor may name one); empty
  // when the actuator lists are unusable.
  std::vector<std::string> actuator_names;
  std::vector<std::string> actuator_types;
  // The links as read (a fluid model's default depends on their geometry).
  const std::vector<LinkSpec>* links = nullptr;
  // Names taken in the list being read: name -> path of the entry that took it first.
  std::map<std::string, std::string> names_taken;
  // Names taken by actuators, whose names are unique across every actuator list.
  std::map<std::string, std::string> actuator_names_taken;
};

// A name unique among `context.names_taken` ("duplicate <what> name 'x' (first used by <path>)"): true
// with *name set when the value is a string, also a duplicate (reported), which references can still
// match.
bool read_unique_name(const Value& value, const std::string& what, const std::string& owner_path,
                      VehicleContext& context, std::string* name);
// A `link` value naming one of the vehicle's links: its index, or nullopt (reported unless the link
// names are unknown).
std::optional<int> read_link_reference(const Value& link, const std::optional<std::vector<std::string>>& link_names);

}  // namespace hadal::config
