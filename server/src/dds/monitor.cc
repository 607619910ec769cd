#include "monitor.h"

#include "hadal/dds/time_msg.h"

#include <fastdds/rtps/common/SerializedPayload.h>

#include <exception>

namespace hadal::dds {

std::size_t MonitorContent::add(const std::string& ros_topic, const std::string& ros_type,
                                eprosima::fastdds::dds::TypeSupport type) {
  Entry& entry = entries_.emplace_back();
  entry.type = std::move(type);
  entry.sample.topic(ros_topic);
  entry.sample.type(ros_type);
  return entries_.size() - 1;
}

void MonitorContent::note(std::size_t index, const void* msg, std::uint64_t count) {
  Entry& entry = entries_[index];
  entry.pending = msg;
  entry.pending_count = count;
  changed_ = true;
}

bool MonitorContent::fill(double sim_time_s, const std::string& frame_id, hadal_msgs::msg::Monitor* out) {
  for (Entry& entry : entries_) {
    if (entry.pending == nullptr) continue;
    void* msg = const_cast<void*>(entry.pending);  // serialize() only reads it
    bool ok = false;
    eprosima::fastrtps::rtps::SerializedPayload_t payload;
    try {
      payload.reserve(entry.type->getSerializedSizeProvider(msg)());
      ok = entry.type->serialize(msg, &payload);
    } catch (const std::exception&) {  // Fast CDR throws when the size provider was short
      ok = false;
    }
    if (!ok) return false;
    entry.sample.cdr().assign(payload.data, payload.data + payload.length);
    entry.sample.count(entry.pending_count);
    entry.written = true;
  }
  for (Entry& entry : entries_) entry.pending = nullptr;
  changed_ = false;
  out->header().stamp(to_time_msg(sim_time_s));
  out->header().frame_id(frame_id);
  out->samples().clear();
  for (const Entry& entry : entries_) {
    if (entry.written) out->samples().push_back(entry.sample);
  }
  return true;
}

}  // namespace hadal::dds
