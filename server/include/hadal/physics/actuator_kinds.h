// The actuator kinds: the one list every layer dispatches over (physics/actuator_kind.h has the contract
// a kind fulfils). Adding a kind is its module and one entry here (and, for its state topic,
// dds/actuator_topics.h).
#pragma once

#include "hadal/core/kind_list.h"
#include "hadal/physics/buoyancy_engine.h"
#include "hadal/physics/drop_weight.h"
#include "hadal/physics/fin.h"
#include "hadal/physics/thruster.h"
#include "hadal/physics/track.h"

namespace hadal::physics {

using ActuatorKinds = KindList<ThrusterActuator, TrackActuator, FinActuator, BuoyancyEngineActuator, DropWeightActuator>;

using ActuatorKindSpec = ActuatorKinds::Specs;
using ActuatorKindState = ActuatorKinds::States;

}  // namespace hadal::physics
