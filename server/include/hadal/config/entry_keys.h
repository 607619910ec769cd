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
// itself unusable is reported already: its names are not checked). An entry on a link that moves on a joint
// is refused (its mounting would follow the body, not the link) unless `placement` says otherwise:
// placement(entry, link, moves) returns "" to accept the link or what is wrong with it, after the link's
// name ("moves on a joint: ..."; for a sensor, read after its type: most kinds follow a moving link, a
// force_torque sensor needs one).
template <class T>
using LinkPlacement = std::function<std::string(const std::common_type_t<T>&, const LinkSpec&, bool moves)>;

template <class T, class A>
typename KeyTable<T, VehicleContext>::Key declare_link_key(KeyTable<T, VehicleContext>& t, A access,
                                                           LinkPlacement<T> placement = nullptr) {
  return t.custom(
      "link",
      [access, placement](const Value& value, T& out, VehicleContext& context) {
        const auto index = read_link_reference(value, context.link_names);
        if (index && context.links) {
          const bool moves = link_moves(*context.links, *index);
          const std::string refusal =
              placement ? placement(out, (*context.links)[static_cast<std::size_t>(*index)], moves)
              : moves   ? std::string("moves on a joint: actuators on moving links are not supported yet")
                        : std::string();
          if (!refusal.empty()) {
            value.error("link " + quoted(*value.string()) + " " + refusal);
            return false;
          }
        }
        if (index) std::invoke(access, out) = *index;
        return index.has_value() || !context.link_names;
      },
      kNameSchema, "string");
}

}  // namespace hadal::config
