#include "hadal/physics/control_vector.h"
#include "hadal/physics/actuator_kinds.h"

#include <type_traits>
#include <variant>

namespace hadal::physics {

std::string check_actuator_controls(const std::vector<ActuatorSpec>& actuators, const std::vector<double>& controls,
                                    std::size_t* failed) {
  std::size_t first = 0;
  for (std::size_t k = 0; k < actuators.size(); ++k) {
    const std::string reason = std::visit(
        [&](const auto& spec) { return std::decay_t<decltype(spec)>::Kind::check(spec, &controls[first], first); },
        actuators[k].kind);
    if (!reason.empty()) {
      if (failed) *failed = k;
      return reason;
    }
    first += actuators[k].num_controls();
  }
  return {};
}

}  // namespace hadal::physics
