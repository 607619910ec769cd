// The keys every entry of a vehicle's lists shares (links, actuators, sensors, lights), declared once for
// the tables that have them: its name, unique within its list, and the link it is mounted on.
#pragma once

#include <functional>
#include <string>
#include <type_traits>

#include "hadal/config/key_table.h"
#include "hadal/config/vehicle_context.h"
#include "hadal/geometry/link_spec.h"

namespace hadal::config {

inline constexpr const char* kNameSchema = R"({"type": "string", "minLength": 1})";

// `name`, required and unique within its list ("duplicate <what> name 'x' (first used by <path>)"), into the
// string field `access` gives.
template <class T, class A>
typename KeyTable<T, VehicleContext>::Key declare_name_key(KeyTable<T, VehicleContext>& t, std::string what,
                                                          A access) {
  return t
      .custom(
          "name",
          [what = std::move(what), access](const Value& value, T& out, VehicleContext& context) {
            const std::string owner = value.path().substr(0, value.path().rfind('.'));
            return read_unique_name(value, what, owner, context, &std::invoke(access, out));
          },
          kNameSchema, "string")
      .required();
}

// `link`, one of the vehicle's links: its index, into the int field `access` gives (a link list that was
// itself unusable is reported already: its names are not checked). An entry for which `on_joint` holds
// (a force_torque sensor, read before its link) measures its link's joint: that link must hang on a
// moving joint. Other entries may not be on moving links (yet).
template <class T, class A>
typename KeyTable<T, VehicleContext>::Key declare_link_key(KeyTable<T, VehicleContext>& t, A access,
                                                           std::function<bool(const std::common_type_t<T>&)> on_joint =
                                                               nullptr) {
  return t.custom(
      "link",
      [access, on_joint](const Value& value, T& out, VehicleContext& context) {
        const auto index = read_link_reference(value, context.link_names);
        if (index && context.links && on_joint && on_joint(out)) {
          if ((*context.links)[static_cast<std::size_t>(*index)].joint.type == JointType::kFixed) {
            value.error("link " + quoted(*value.string()) + " is not on a moving joint: this sensor measures the " +
                        "wrench across its link's joint (revolute, continuous or prismatic)");
            return false;
          }
        } else if (index && context.links && link_moves(*context.links, *index)) {
          // Issue 40's first part: mounts follow B only (docs/ARCHITECTURE.md, "Articulated vehicles").
          value.error("link " + quoted(*value.string()) +
                      " moves on a joint: sensors, actuators and lights on moving links are not supported yet");
          return false;
        }
        if (index) std::invoke(access, out) = *index;
        return index.has_value() || !context.link_names;
      },
      kNameSchema, "string");
}

}  // namespace hadal::config
