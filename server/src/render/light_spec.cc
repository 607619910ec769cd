#include "hadal/render/light_spec.h"

#include "hadal/config/entry_keys.h"

namespace hadal::render {

using namespace config::keys;
using config::VehicleContext;

const KeyTable<LightSpec, VehicleContext>& light_keys() {
  return declare_keys<LightSpec, VehicleContext>([](KeyTable<LightSpec, VehicleContext>& t) {
    t.describe("lights[]",
               "a spot light on a link: full intensity inside the inner half angle of its "
               "axis (x of its frame), none beyond the outer, a smooth edge between");
    config::declare_name_key(t, "light", &LightSpec::name).doc("unique among the vehicle's lights");
    // A light on a link that moves on a joint (a lamp on an arm) follows its link (geometry/world_scene.h).
    config::declare_link_key(t, &LightSpec::link_index, config::LinkPlacement<LightSpec>([](auto&&...) {
                               return std::string();
                             }))
        .required()
        .doc("a link of this vehicle (one on a joint moves with it)");
    t.pose("pose", &LightSpec::X_LF).doc("the light's frame in the link frame; the beam points along its x");
    t.number("inner_half_angle_deg", &LightSpec::inner_half_angle).degrees().range(Range::right_open(0.0, 180.0))
        .doc("full intensity inside");
    t.number("outer_half_angle_deg", &LightSpec::outer_half_angle).degrees().range(Range::left_open(0.0, 180.0))
        .rule("> inner_half_angle_deg").doc("no light beyond");
    t.vector("intensity_w_per_sr", &LightSpec::intensity_W_per_sr).unit("W/sr").range(Range::closed(0.0, 1e7))
        .doc("radiant intensity on the axis, per channel");
    t.check([](const KeyReads& reads, LightSpec& light, VehicleContext&) {
      if (!reads.ok("inner_half_angle_deg") || !reads.ok("outer_half_angle_deg")) return true;
      if (light.inner_half_angle < light.outer_half_angle) return true;
      reads.error_at_key(reads.has("outer_half_angle_deg") ? "outer_half_angle_deg" : "inner_half_angle_deg",
                         "the beam's outer half angle (" + config::format_approximate(to_degrees(light.outer_half_angle)) +
                             " deg) must exceed its inner half angle (" +
                             config::format_approximate(to_degrees(light.inner_half_angle)) + " deg)");
      return false;
    });
  });
}

}  // namespace hadal::render
