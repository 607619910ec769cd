// Writes the seed corpus of the command fuzzer (command_fuzz.cc): valid samples of both inbound topics,
// serialized as DDS delivers them, each prefixed with the byte that selects its topic.
//   hadal_fuzz_make_command_corpus OUTPUT_DIR
#include <fastdds/rtps/common/SerializedPayload.h>
#include <hadal_msgsPubSubTypes.h>
#include <std_msgsPubSubTypes.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace {

template <class PubSubType, class Msg>
void write(const std::string& path, std::uint8_t selector, Msg msg) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&msg)());
  if (!type.serialize(&msg, &payload)) std::abort();
  std::ofstream out(path, std::ios::binary);
  out.put(static_cast<char>(selector));
  out.write(reinterpret_cast<const char*>(payload.data), payload.length);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: hadal_fuzz_make_command_corpus OUTPUT_DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  using Request = hadal_msgs::msg::StepRequest;
  Request step;
  step.request_id(1);
  step.steps(10);
  write<hadal_msgs::msg::StepRequestPubSubType>(dir + "/step", 0, step);
  Request with_setpoints = step;
  with_setpoints.vehicle_names({"auv"});
  with_setpoints.setpoint_counts({3});
  with_setpoints.setpoints({0.5, -0.2, 0.0});
  write<hadal_msgs::msg::StepRequestPubSubType>(dir + "/step_setpoints", 0, with_setpoints);
  Request reset = with_setpoints;
  reset.reset(true);
  reset.reset_seed_given(true);
  reset.reset_seed(7);
  reset.reset_vehicle_names({"auv"});
  reset.reset_poses({1.0, 2.0, -50.0, 0.0, 0.0, 0.0, 1.0});
  write<hadal_msgs::msg::StepRequestPubSubType>(dir + "/reset_pose", 0, reset);
  std_msgs::msg::Float64MultiArray array;
  array.data({0.8, 0.0, 0.1});
  write<std_msgs::msg::Float64MultiArrayPubSubType>(dir + "/setpoints", 1, array);
  std_msgs::msg::MultiArrayDimension dim;
  dim.label("actuators");
  dim.size(3);
  dim.stride(3);
  array.layout().dim({dim});
  array.layout().data_offset(1);
  array.data({9.0, 0.8, 0.0, 0.1});
  write<std_msgs::msg::Float64MultiArrayPubSubType>(dir + "/setpoints_layout", 1, array);
  return 0;
}
