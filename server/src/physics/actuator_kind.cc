#include "hadal/physics/actuator_kind.h"

#include <algorithm>
#include <cmath>

#include "hadal/config/yaml_reader.h"

namespace hadal::physics {

std::string check_normalised_setpoint(double value, std::size_t first) {
  const std::string label = "setpoint[" + std::to_string(first) + "]";
  if (std::isnan(value)) return label + " is NaN";
  if (std::isinf(value)) return label + " is " + (value > 0 ? "+inf" : "-inf");
  if (value < -1.0 || value > 1.0) return label + " = " + config::format_number(value) + " is outside [-1, 1]";
  return {};
}

double held_setpoint(double value) { return std::isfinite(value) ? std::clamp(value, -1.0, 1.0) : 0.0; }

}  // namespace hadal::physics
