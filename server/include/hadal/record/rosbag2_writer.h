// A rosbag2 bag written without ROS 2: a directory holding one sqlite3 database (rosbag2's "sqlite3"
// storage, database schema version 4) and metadata.yaml (bag metadata version 9), so that `ros2 bag
// info`, `ros2 bag play` and the rosbag2 Python API read it (docs/ARCHITECTURE.md, "Recording").
//
// Messages are stored as DDS put them on the wire: CDR with its 4-byte encapsulation header, which is
// what rosbag2 stores for serialization format "cdr". Topic names and types are ROS 2's ("/auv/odometry",
// "nav_msgs/msg/Odometry"; ros_names() converts DDS's "rt/..." and "pkg::msg::dds_::Type_").
//
// Durability: the database runs in WAL mode and flush() commits what was written since the last flush and
// rewrites metadata.yaml (to a temporary file, then renamed over the old one), so a process killed at any
// point leaves a bag that reads as of its last flush. The recorders flush once per wall second.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hadal::record {

// The QoS a topic's writer offered, as rosbag2 records it for replay. DDS discovery does not carry a
// writer's history, so rosbag2 records it as history "unknown", depth 0; so does this writer.
struct OfferedQos {
  bool reliable = true;
  bool transient_local = false;
};

struct BagTopic {
  std::string name;  // ROS 2 topic name: "/auv/odometry"
  std::string type;  // ROS 2 type name: "nav_msgs/msg/Odometry"
  OfferedQos qos;
};

class Rosbag2Writer {
 public:
  // Creates `directory` (it must not exist, as rosbag2 requires) with `directory`_0.db3 in it.
  // On failure returns null and the reason in *error.
  static std::unique_ptr<Rosbag2Writer> create(const std::string& directory, std::string* error);
  // "" when create() may make `directory`, else why not (it exists): for the recorders to refuse a bag
  // directory before they start anything.
  static std::string existing_directory_error(const std::string& directory);
  ~Rosbag2Writer();  // close()
  Rosbag2Writer(const Rosbag2Writer&) = delete;
  Rosbag2Writer& operator=(const Rosbag2Writer&) = delete;

  // Registers a topic; returns its id for write(), or -1 with the reason in error() when sqlite refuses
  // it. Registering a name again returns the first id.
  int add_topic(const BagTopic& topic);
  // One message: `timestamp_ns` (the bag's time: receive or sim time, ns) and the serialized bytes.
  // Returns false with the reason in error() when sqlite refuses it.
  bool write(int topic_id, std::int64_t timestamp_ns, const unsigned char* data, std::size_t size);
  // Commits the messages written since the last flush and rewrites metadata.yaml.
  bool flush();
  // flush(), then the metadata into the database's metadata table, as rosbag2 does on closing.
  void close();

  const std::string& directory() const { return directory_; }
  const std::string& database_path() const { return database_path_; }
  std::uint64_t message_count() const;
  const std::string& error() const { return error_; }

 private:
  struct Impl;
  Rosbag2Writer(std::unique_ptr<Impl> impl, std::string directory, std::string database_path);
  std::string metadata_yaml(bool for_database) const;

  std::unique_ptr<Impl> impl_;
  std::string directory_;
  std::string database_path_;
  std::string error_;
};

}  // namespace hadal::record
