// Each actuator's own check of its slice of a vehicle's control vector (physics/actuator_kind.h): the
// one check behind a client's command at run time (VehicleActuators::check) and a scenario schedule's
// keyframes at load (config/scenario_loader.cc).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "hadal/core/model.h"

namespace hadal::physics {

// "" when every actuator accepts its entries of `controls` (whose length must be the actuators' total
// controls), else the first actuator's reason ("setpoint[1] is NaN"); *failed (if given) is then that
// actuator's index.
std::string check_actuator_controls(const std::vector<ActuatorSpec>& actuators, const std::vector<double>& controls,
                                    std::size_t* failed = nullptr);

}  // namespace hadal::physics
