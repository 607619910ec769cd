// Subscribes to every topic a hadald participant writes and hands over each sample as the bytes on the
// wire (CDR, encapsulation header included), knowing no message type: it discovers the server's writers
// (topic, DDS type name, offered QoS) from the participant named "hadald" on the domain, registers an
// opaque type under each type name and reads raw serialized samples. Used by the recorders (hadal-record,
// hadald --record) and the regression digests (hadal-record-topics).
#pragma once

#include "hadal/core/security_files.h"

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace hadal::record {

struct TappedWriter {
  std::string type;  // DDS type name: "nav_msgs::msg::dds_::Odometry_"
  bool reliable = true;
  bool transient_local = false;
};

struct TappedSample {
  const std::string& topic;                 // DDS topic name: "rt/auv/odometry"
  const std::vector<unsigned char>& bytes;  // the serialized sample
  std::int64_t sequence;                    // the writer's sequence number (1, 2, ... per topic)
};

// What one reader got of one writer's samples, from their sequence numbers (1, 2, ... per writer): samples
// read, the first and last number, and the numbers skipped after the first (samples the writer dropped from its
// KEEP_LAST history before this reader had them: lost). A first number above 1 is not a loss: those samples
// were written before the reader matched.
struct SequenceGaps {
  std::uint64_t samples = 0;
  std::int64_t first = 0;
  std::int64_t last = 0;
  std::uint64_t lost = 0;

  void add(std::int64_t sequence) {
    if (samples == 0) {
      first = sequence;
    } else if (sequence > last + 1) {
      lost += static_cast<std::uint64_t>(sequence - last - 1);
    }
    last = sequence;
    ++samples;
  }
};

class TopicTap {
 public:
  // Joins `domain_id` as a participant named `participant_name`, with DDS Security when `security` names files
  // (dds::create_participant). Topics in `excluded` are never read.
  TopicTap(int domain_id, const std::string& participant_name, std::set<std::string> excluded = {},
           const SecurityFiles& security = {});
  ~TopicTap();
  TopicTap(const TopicTap&) = delete;
  TopicTap& operator=(const TopicTap&) = delete;

  // Waits (up to timeout_s) until a hadald's writers are known and their set has not changed for quiet_s
  // (hadald creates them all before its first step). False when no hadald writer was seen.
  bool discover(double timeout_s, double quiet_s = 1.0);
  // topic -> writer, as discovered.
  std::map<std::string, TappedWriter> writers() const;

  // A reliable, keep-all reader on each discovered topic; `on_sample` gets every sample, one call at a time
  // (from DDS's threads) until the tap is destroyed: what it uses must outlive the tap (declare it before). Waits (up to timeout_s) until every reader has matched its writer; false if not.
  // kept_samples: transient-local readers where the writer offers it, so that the samples the writer kept
  // for late joiners (a lockstep server's t = 0 samples, published before anyone stepped it) come too.
  // wanted: the topics to read (all when empty). latest_only: a viewer's readers, which show the latest sample
  // and need not slow the writer: keep last 1, best effort (reliable where kept samples are read).
  bool subscribe(std::function<void(const TappedSample&)> on_sample, double timeout_s, bool kept_samples = false,
                 const std::function<bool(const std::string& topic, const TappedWriter&)>& wanted = {},
                 bool latest_only = false);
  // Takes whatever the readers hold without having signalled it (after the last step of a run).
  void drain();
  // Wall seconds since the last sample or discovery event.
  double seconds_quiet() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hadal::record
