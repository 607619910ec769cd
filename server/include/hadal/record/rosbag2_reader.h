// Reads a rosbag2 bag of sqlite3 storage (record/rosbag2_writer.h's, or one `ros2 bag record` wrote):
// its topics, an index of every message (time, topic) in time order, and a message's serialized bytes on
// demand, so that a player holds the index and not the data. Only the storage's tables are read
// (schema version 3 and 4 have the same topics and messages columns); metadata.yaml names the database
// files, all of which are opened.
#pragma once

#include "hadal/record/rosbag2_writer.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hadal::record {

struct BagIndexEntry {
  std::int64_t timestamp_ns = 0;  // the bag's time of the message
  int topic = 0;                  // index into Rosbag2Reader::topics()
  int file = 0;                   // which database
  std::int64_t row = 0;           // its row in that database's messages table
};

class Rosbag2Reader {
 public:
  // Opens the bag in `directory`; on failure returns null and the reason in *error (no directory, no
  // metadata.yaml or database, not rosbag2's tables, a serialization format other than CDR).
  static std::unique_ptr<Rosbag2Reader> open(const std::string& directory, std::string* error);
  ~Rosbag2Reader();
  Rosbag2Reader(const Rosbag2Reader&) = delete;
  Rosbag2Reader& operator=(const Rosbag2Reader&) = delete;

  const std::vector<BagTopic>& topics() const { return topics_; }
  // Every message, by time (ties in file and row order).
  const std::vector<BagIndexEntry>& index() const { return index_; }
  // The serialized bytes of a message of the index; false with the reason in *error when sqlite fails.
  bool read(const BagIndexEntry& entry, std::vector<unsigned char>* bytes, std::string* error) const;

 private:
  struct Impl;
  explicit Rosbag2Reader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
  std::vector<BagTopic> topics_;
  std::vector<BagIndexEntry> index_;
};

}  // namespace hadal::record
