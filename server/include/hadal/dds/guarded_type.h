// Deserialization that a malformed sample cannot turn into a crash.
//
// fastddsgen's deserialize() catches only Fast CDR's NotEnoughMemoryException (which Fast CDR 1.0 also
// throws, before allocating, for a sequence claiming more elements than bytes are left). Anything else it
// throws, such as the BadParamException of an encapsulation no final type has, or a std::bad_alloc, would
// escape into Fast DDS's take() and end the process. GuardedType<PubSubType> is the generated type with a
// deserialize() that turns every exception into a refusal (false: Fast DDS drops the sample) and counts
// the refused samples (undecodable_samples()). TopicRegistry registers every type through it.
#pragma once

#include <fastdds/rtps/common/SerializedPayload.h>

#include <atomic>
#include <cstdint>
#include <exception>

namespace hadal::dds {

// Samples every GuardedType in this process refused.
inline std::atomic<std::uint64_t>& undecodable_samples() {
  static std::atomic<std::uint64_t> count{0};
  return count;
}

template <class PubSubType>
class GuardedType : public PubSubType {
 public:
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    try {
      if (PubSubType::deserialize(payload, data)) return true;
    } catch (const std::exception&) {
    }
    ++undecodable_samples();
    return false;
  }
};

}  // namespace hadal::dds
