// The actuator kinds: the one list every layer dispatches over (physics/actuator_kind.h has the contract
// a kind fulfils). Adding a kind is its module and one entry here (and, for its state topic,
// dds/actuator_topics.h).
#pragma once

#include "hadal/core/kind_list.h"
#include "hadal/physics/buoyancy_engine.h"
#include "hadal/physics/drop_weight.h"
#include "hadal/physics/fin.h"
#include "hadal/physics/thruster.h"
#include "hadal/physics/actuator_specs.h"
#include "hadal/physics/track.h"

#include <type_traits>

namespace hadal::physics {

using ActuatorKinds = KindList<ThrusterActuator, TrackActuator, FinActuator, BuoyancyEngineActuator, DropWeightActuator>;

// The model's variant of specs (physics/actuator_specs.h) is this list's.
static_assert(std::is_same_v<ActuatorKindSpec, ActuatorKinds::Specs>, "physics/actuator_specs.h lists the kinds in this order");
using ActuatorKindState = ActuatorKinds::States;

}  // namespace hadal::physics
