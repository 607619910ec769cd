#include "hadal/config/vehicle_context.h"

#include <algorithm>

#include "hadal/config/yaml_reader.h"

namespace hadal::config {

bool read_unique_name(const Value& value, const std::string& what, const std::string& owner_path,
                      VehicleContext& context, std::string* name) {
  const std::optional<std::string> text = value.string();
  if (!text) return false;
  *name = *text;
  const auto [it, inserted] = context.names_taken.emplace(*text, owner_path);
  if (!inserted) value.error("duplicate " + what + " name " + quoted(*text) + " (first used by " + it->second + ")");
  return true;
}

std::optional<int> read_link_reference(const Value& link, const std::optional<std::vector<std::string>>& link_names) {
  const auto link_name = link.string();
  if (!link_name) return std::nullopt;
  const auto& names = link_names.value_or(std::vector<std::string>());
  const auto it = std::find(names.begin(), names.end(), *link_name);
  if (it != names.end()) return static_cast<int>(it - names.begin());
  if (link_names) {
    link.error("no link named " + quoted(*link_name) + " in this vehicle (links: " + join_names(names) + ")");
  }
  return std::nullopt;
}

}  // namespace hadal::config
