// The actuator kinds' specs, without their implementations (core/vehicle_spec.h holds them in
// ActuatorSpec): one alternative per kind, in physics/actuator_kinds.h's order (which checks that they
// are the same).
#pragma once

#include <variant>

#include "hadal/physics/buoyancy_engine_spec.h"
#include "hadal/physics/drop_weight_spec.h"
#include "hadal/physics/fin_spec.h"
#include "hadal/physics/thruster_spec.h"
#include "hadal/physics/track_spec.h"

namespace hadal::physics {

using ActuatorKindSpec = std::variant<ThrusterSpec, TrackSpec, FinSpec, BuoyancyEngineSpec, DropWeightSpec>;

}  // namespace hadal::physics
