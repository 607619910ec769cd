// libFuzzer target for hadald's run-time command handlers: what a client's sample goes through from the
// wire to the simulation. Byte 0 selects the topic (even: rt/hadal/step_request; odd: the setpoints of
// vehicle (byte 0 / 2) mod n), the rest is the serialized sample as DDS delivers it (encapsulation header
// and CDR body). It is decoded by the same guarded type support as hadald's readers
// (dds/guarded_type.h), parsed (dds/inbound.h), checked (Simulation::check_controls), and, when accepted,
// applied to a simulation of the lockstep test scenario as the run loop applies it: a reset, the
// setpoints, at most two steps. Any crash, sanitizer report, leak or hang is a finding; refusals are the
// expected outcome for most inputs, and none may leave a non-finite state behind.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "hadal/config/scenario_loader.h"
#include "hadal/core/simulation.h"
#include "hadal/dds/guarded_type.h"
#include "inbound.h"

#include <hadal_msgsPubSubTypes.h>
#include <std_msgsPubSubTypes.h>

namespace {

hadal::Simulation& simulation() {
  static std::unique_ptr<hadal::Simulation> sim = [] {
    const auto loaded = hadal::config::load_scenario_file(HADAL_SOURCE_DIR "/tests/integration/scenarios/auv_client.yaml");
    if (!loaded.ok()) std::abort();
    return std::make_unique<hadal::Simulation>(*loaded.model);
  }();
  return *sim;
}

template <class PubSubType, class Msg>
bool decode(const std::uint8_t* data, std::size_t size, Msg* msg) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(size));
  if (size > 0) std::memcpy(payload.data, data, size);
  payload.length = static_cast<std::uint32_t>(size);
  hadal::dds::GuardedType<PubSubType> type;
  return type.deserialize(&payload, msg);
}

void apply(hadal::Simulation& sim, const hadal::dds::InboundCommand& command) {
  if (!command.error.empty() || !sim.check_controls(command.vehicle_index, command.setpoints).empty()) return;
  if (!sim.set_controls(command.vehicle_index, command.setpoints).empty()) std::abort();  // checked above
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1 || size > 65536) return 0;
  hadal::Simulation& sim = simulation();
  const hadal::Model& model = sim.model();
  const hadal::dds::SourceId source{};
  if (data[0] % 2 == 0) {
    hadal_msgs::msg::StepRequest msg;
    if (!decode<hadal_msgs::msg::StepRequestPubSubType>(data + 1, size - 1, &msg)) return 0;
    const hadal::dds::InboundStepRequest request = hadal::dds::parse_step_request(model, msg, source, 0);
    if (!request.error.empty()) return 0;
    for (const auto& command : request.commands) {
      if (!sim.check_controls(command.vehicle_index, command.setpoints).empty()) return 0;  // refused as a whole
    }
    if (request.reset && !sim.reset(request.reset_seed.value_or(model.world.seed), request.reset_X_WB).empty()) {
      return 0;
    }
    for (const auto& command : request.commands) apply(sim, command);
    for (std::uint32_t i = 0; i < std::min<std::uint32_t>(request.steps, 2); ++i) sim.step();
  } else {
    std_msgs::msg::Float64MultiArray msg;
    if (!decode<std_msgs::msg::Float64MultiArrayPubSubType>(data + 1, size - 1, &msg)) return 0;
    const int vehicle = static_cast<int>((data[0] / 2) % model.vehicles.size());
    apply(sim, hadal::dds::command_from_array(vehicle, msg, source, 0));
    sim.step();
  }
  for (const auto& vehicle : sim.state().vehicles) {
    if (!vehicle.body.X_WB.matrix().allFinite()) std::abort();  // the non-finite policy must have caught it
  }
  return 0;
}
