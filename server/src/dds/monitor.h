// rt/hadal/monitor (hadal_msgs/Monitor, idl/hadal_msgs.idl): the latest sample of each of the server's light
// topics in one message, for monitors such as hadal-viewer, so that following a run costs the server one
// sample per wall interval instead of every stream delivered to one more reader (docs/ARCHITECTURE.md,
// "Viewer"). Like camera previews, a side channel paced in wall time (at most every kMonitorInterval, only
// while a reader is matched and something changed): not part of a lockstep run's deterministic output.
//
// MonitorContent keeps, per topic, the message last written and serializes it only when a monitor sample is
// due, so the publish path pays a pointer store per sample whether or not anyone watches.
#pragma once

#include <fastdds/dds/topic/TypeSupport.hpp>
#include <hadal_msgs.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace hadal::dds {

inline constexpr std::chrono::milliseconds kMonitorInterval{50};

class MonitorContent {
 public:
  // A topic to carry: its ROS 2 topic and type names and the type support that serializes its messages.
  // Returns its index for note().
  std::size_t add(const std::string& ros_topic, const std::string& ros_type, eprosima::fastdds::dds::TypeSupport type);
  // The topic's message `msg` was just written, the count-th sample of the topic. The message must stay
  // unchanged until the topic's next note() or the next fill() (the server keeps one message per topic).
  void note(std::size_t index, const void* msg, std::uint64_t count);
  // Whether a topic was noted since the last fill().
  bool changed() const { return changed_; }
  // Serializes what was noted since the last fill() and fills *out with the latest sample of every topic
  // written so far, in the order added; header stamp = sim_time_s. False when a message does not serialize
  // (what was noted stays noted).
  bool fill(double sim_time_s, const std::string& frame_id, hadal_msgs::msg::Monitor* out);

 private:
  struct Entry {
    eprosima::fastdds::dds::TypeSupport type;
    const void* pending = nullptr;  // noted, not serialized yet
    std::uint64_t pending_count = 0;
    hadal_msgs::msg::MonitorSample sample;  // the latest serialized, count 0 before the first
    bool written = false;
  };
  std::vector<Entry> entries_;
  bool changed_ = false;
};

}  // namespace hadal::dds
