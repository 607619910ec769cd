// A hadald's topics into a rosbag2 bag: a TopicTap feeding a Rosbag2Writer, flushed once per wall second
// on a thread of its own (docs/ARCHITECTURE.md, "Recording"). Used by hadal-record and hadald --record.
#pragma once

#include "hadal/core/security_files.h"

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>

namespace hadal::record {

struct BagRecorderOptions {
  int domain_id = 0;
  std::string directory;      // must not exist
  std::set<std::string> topics;  // ROS 2 names to record; empty: every topic of the hadald but /hadal/monitor
  // Bag time in sim time: a sample's own header stamp (every type hadald publishes but the step reply has one: a
  // captured sensor's is its capture time), else the sim time of the latest /clock sample; false: receive time.
  bool use_sim_time = false;
  double wait_s = 20.0;       // how long to look for the hadald and to match its writers
  std::string participant_name = "hadal_record";
  SecurityFiles security;     // DDS Security of its participant (a secure hadald's domain); empty: off
};

class BagRecorder {
 public:
  explicit BagRecorder(BagRecorderOptions options);
  ~BagRecorder();  // stop()
  BagRecorder(const BagRecorder&) = delete;
  BagRecorder& operator=(const BagRecorder&) = delete;

  // Finds the hadald, creates the bag and starts recording; returns "" or the reason it could not (then no
  // bag directory is left behind unless the failure came after creating it). Warnings go to stderr.
  std::string start();
  std::size_t topic_count() const;
  // Takes what the readers hold, stops reading and closes the bag; returns "" or the first write error.
  // Idempotent.
  std::string stop();
  std::uint64_t message_count() const;
  // The samples the recorder never got, per DDS topic, as "12 of rt/clock, 3 of rt/auv/imu" (gaps in the
  // writers' sequence numbers: a writer keeps its last few samples only, and a recorder that falls behind loses
  // the older); "" when the bag is complete.
  std::string lost_samples_text() const;
  // Per recorded DDS topic, the sequence number of the last sample read (its writer's count of samples written up
  // to it; 0: none yet): what hadald --record compares with what it published, to wait for the recorder.
  std::map<std::string, std::int64_t> last_sequences() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hadal::record
