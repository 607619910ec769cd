#include "hadal/record/rosbag2_writer.h"
#include "hadal/record/rosbag2_reader.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace hadal::record {
namespace {

namespace fs = std::filesystem;

std::string fresh_directory(const std::string& name) {
  const fs::path path = fs::temp_directory_path() / ("hadal_bag_test_" + std::to_string(getpid()) + "_" + name);
  fs::remove_all(path);
  return path.string();
}

struct Db {
  sqlite3* db = nullptr;
  explicit Db(const std::string& path) {
    EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  }
  ~Db() { sqlite3_close(db); }
  // Rows of a query, each as its columns' text.
  std::vector<std::vector<std::string>> rows(const std::string& sql) const {
    std::vector<std::vector<std::string>> result;
    sqlite3_stmt* statement = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr), SQLITE_OK) << sql;
    while (sqlite3_step(statement) == SQLITE_ROW) {
      std::vector<std::string> row;
      for (int c = 0; c < sqlite3_column_count(statement); ++c) {
        const auto* text = sqlite3_column_blob(statement, c);
        row.emplace_back(text ? static_cast<const char*>(text) : "",
                         static_cast<std::size_t>(sqlite3_column_bytes(statement, c)));
      }
      result.push_back(row);
    }
    sqlite3_finalize(statement);
    return result;
  }
};

// (name, type, notnull, pk) of a table's columns, as PRAGMA table_info gives them.
std::vector<std::vector<std::string>> columns(const Db& db, const std::string& table) {
  std::vector<std::vector<std::string>> result;
  for (const auto& row : db.rows("PRAGMA table_info(" + table + ")")) {
    result.push_back({row[1], row[2], row[3], row[5]});
  }
  return result;
}

// The tables are rosbag2's (rosbag2_storage_sqlite3, schema version 4): the same columns, types and keys,
// so its reader's queries run unchanged; the metadata is version 9's layout.
TEST(Rosbag2WriterTest, WritesRosbag2sSchemaMessagesAndMetadata) {
  const std::string directory = fresh_directory("bag");
  std::string error;
  auto bag = Rosbag2Writer::create(directory, &error);
  ASSERT_NE(bag, nullptr) << error;
  const int odometry = bag->add_topic({"/auv/odometry", "nav_msgs/msg/Odometry", {true, false}});
  const int clock = bag->add_topic({"/clock", "rosgraph_msgs/msg/Clock", {false, false}});
  EXPECT_EQ(bag->add_topic({"/auv/odometry", "nav_msgs/msg/Odometry", {}}), odometry);
  // A second topic of a known type, then a new type: topic ids run on while the definitions table,
  // one row per type, falls behind (ids once came from the wrong table).
  EXPECT_EQ(bag->add_topic({"/lander/odometry", "nav_msgs/msg/Odometry", {true, false}}), 3);
  const int imu = bag->add_topic({"/auv/imu", "sensor_msgs/msg/Imu", {true, false}});
  EXPECT_EQ(imu, 4);
  const std::vector<unsigned char> first{0, 1, 0, 0, 42, 0, 0, 0};
  const std::vector<unsigned char> second{0, 1, 0, 0, 0, 0xff, 7};
  ASSERT_TRUE(bag->write(odometry, 2'000'000'000, first.data(), first.size()));
  ASSERT_TRUE(bag->write(clock, 2'010'000'000, second.data(), second.size()));
  ASSERT_TRUE(bag->write(odometry, 2'020'000'000, second.data(), second.size()));
  ASSERT_TRUE(bag->write(imu, 2'030'000'000, first.data(), first.size()));
  EXPECT_FALSE(bag->write(7, 0, first.data(), first.size()));
  EXPECT_EQ(bag->error(), "no topic 7 in the bag");
  bag->close();
  EXPECT_FALSE(bag->write(odometry, 0, first.data(), first.size()));

  const std::string file = directory + "/" + fs::path(directory).filename().string() + "_0.db3";
  ASSERT_TRUE(fs::exists(file));
  EXPECT_FALSE(fs::exists(file + "-wal"));  // closed: one file, as rosbag2 leaves it
  Db db(file);
  using Rows = std::vector<std::vector<std::string>>;
  EXPECT_EQ(columns(db, "schema"), (Rows{{"schema_version", "INTEGER", "0", "1"}, {"ros_distro", "TEXT", "1", "0"}}));
  EXPECT_EQ(columns(db, "metadata"), (Rows{{"id", "INTEGER", "0", "1"}, {"metadata_version", "INTEGER", "1", "0"},
                                           {"metadata", "TEXT", "1", "0"}}));
  EXPECT_EQ(columns(db, "topics"),
            (Rows{{"id", "INTEGER", "0", "1"}, {"name", "TEXT", "1", "0"}, {"type", "TEXT", "1", "0"},
                  {"serialization_format", "TEXT", "1", "0"}, {"offered_qos_profiles", "TEXT", "1", "0"},
                  {"type_description_hash", "TEXT", "1", "0"}}));
  EXPECT_EQ(columns(db, "message_definitions"),
            (Rows{{"id", "INTEGER", "0", "1"}, {"topic_type", "TEXT", "1", "0"}, {"encoding", "TEXT", "1", "0"},
                  {"encoded_message_definition", "TEXT", "1", "0"}, {"type_description_hash", "TEXT", "1", "0"}}));
  EXPECT_EQ(columns(db, "messages"), (Rows{{"id", "INTEGER", "0", "1"}, {"topic_id", "INTEGER", "1", "0"},
                                           {"timestamp", "INTEGER", "1", "0"}, {"data", "BLOB", "1", "0"}}));
  EXPECT_EQ(db.rows("SELECT name FROM sqlite_master WHERE type = 'index'"), (Rows{{"timestamp_idx"}}));
  EXPECT_EQ(db.rows("SELECT schema_version, ros_distro FROM schema"), (Rows{{"4", "jazzy"}}));
  EXPECT_EQ(db.rows("SELECT id, name, type, serialization_format FROM topics ORDER BY id"),
            (Rows{{"1", "/auv/odometry", "nav_msgs/msg/Odometry", "cdr"},
                  {"2", "/clock", "rosgraph_msgs/msg/Clock", "cdr"},
                  {"3", "/lander/odometry", "nav_msgs/msg/Odometry", "cdr"},
                  {"4", "/auv/imu", "sensor_msgs/msg/Imu", "cdr"}}));
  // rosbag2's reader query.
  const Rows messages = db.rows(
      "SELECT data, timestamp, topics.name FROM messages JOIN topics ON messages.topic_id = topics.id "
      "ORDER BY messages.timestamp");
  ASSERT_EQ(messages.size(), 4u);
  EXPECT_EQ(messages[3][2], "/auv/imu");
  EXPECT_EQ(messages[0],
            (std::vector<std::string>{std::string(first.begin(), first.end()), "2000000000", "/auv/odometry"}));
  EXPECT_EQ(messages[1][2], "/clock");
  EXPECT_EQ(messages[2][0], std::string(second.begin(), second.end()));
  // The QoS column holds version 9's YAML list; the metadata row is the bag's metadata.
  const YAML::Node qos = YAML::Load(db.rows("SELECT offered_qos_profiles FROM topics WHERE id = 2")[0][0]);
  ASSERT_TRUE(qos.IsSequence());
  EXPECT_EQ(qos[0]["reliability"].as<std::string>(), "best_effort");
  EXPECT_EQ(qos[0]["deadline"]["sec"].as<std::int64_t>(), 9223372036LL);
  const Rows metadata_rows = db.rows("SELECT metadata_version, metadata FROM metadata");
  ASSERT_EQ(metadata_rows.size(), 1u);
  EXPECT_EQ(metadata_rows[0][0], "9");
  EXPECT_EQ(YAML::Load(metadata_rows[0][1])["message_count"].as<int>(), 4);

  const YAML::Node info = YAML::LoadFile(directory + "/metadata.yaml")["rosbag2_bagfile_information"];
  EXPECT_EQ(info["version"].as<int>(), 9);
  EXPECT_EQ(info["storage_identifier"].as<std::string>(), "sqlite3");
  EXPECT_EQ(info["message_count"].as<int>(), 4);
  EXPECT_EQ(info["starting_time"]["nanoseconds_since_epoch"].as<std::int64_t>(), 2'000'000'000);
  EXPECT_EQ(info["duration"]["nanoseconds"].as<std::int64_t>(), 30'000'000);
  EXPECT_EQ(info["relative_file_paths"][0].as<std::string>(), fs::path(file).filename().string());
  EXPECT_EQ(info["files"][0]["message_count"].as<int>(), 4);
  EXPECT_EQ(info["topics_with_message_count"][3]["topic_metadata"]["name"].as<std::string>(), "/auv/imu");
  EXPECT_EQ(info["topics_with_message_count"][3]["message_count"].as<int>(), 1);
  EXPECT_EQ(info["topics_with_message_count"][0]["topic_metadata"]["name"].as<std::string>(), "/auv/odometry");
  EXPECT_EQ(info["topics_with_message_count"][0]["message_count"].as<int>(), 2);
  const YAML::Node clock_qos = info["topics_with_message_count"][1]["topic_metadata"]["offered_qos_profiles"];
  EXPECT_EQ(clock_qos[0]["history"].as<std::string>(), "unknown");
  EXPECT_EQ(info["compression_format"].as<std::string>(), "");
  EXPECT_TRUE(info["custom_data"].IsMap());
  EXPECT_EQ(info["ros_distro"].as<std::string>(), "jazzy");
  fs::remove_all(directory);
}

TEST(Rosbag2WriterTest, AnExistingDirectoryIsRefused) {
  const std::string directory = fresh_directory("exists");
  fs::create_directories(directory);
  std::string error;
  EXPECT_EQ(Rosbag2Writer::create(directory, &error), nullptr);
  EXPECT_EQ(error, "bag directory " + directory + " already exists (a rosbag2 bag is never appended to)");
  EXPECT_EQ(Rosbag2Writer::create("/proc/no/such/dir", &error), nullptr);
  EXPECT_NE(error.find("cannot create bag directory /proc/no/such/dir"), std::string::npos);
  fs::remove_all(directory);
}

// A process killed with SIGKILL (no destructor, no close) leaves a bag that reads as of its last flush.
TEST(Rosbag2WriterTest, AKilledWriterLeavesTheBagAsOfItsLastFlush) {
  const std::string directory = fresh_directory("killed");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::string error;
    auto bag = Rosbag2Writer::create(directory, &error);
    if (!bag) _exit(3);
    const int topic = bag->add_topic({"/auv/imu", "sensor_msgs/msg/Imu", {}});
    const unsigned char bytes[6] = {0, 1, 0, 0, 1, 2};
    for (int i = 0; i < 10; ++i) bag->write(topic, 1000 + i, bytes, sizeof(bytes));
    bag->flush();
    for (int i = 10; i < 15; ++i) bag->write(topic, 1000 + i, bytes, sizeof(bytes));  // never flushed
    kill(getpid(), SIGKILL);
    _exit(4);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << status;
  const std::string file = directory + "/" + fs::path(directory).filename().string() + "_0.db3";
  {
    Db db(file);
    EXPECT_EQ(db.rows("SELECT COUNT(*), MIN(timestamp), MAX(timestamp) FROM messages"),
              (std::vector<std::vector<std::string>>{{"10", "1000", "1009"}}));
  }
  const YAML::Node info = YAML::LoadFile(directory + "/metadata.yaml")["rosbag2_bagfile_information"];
  EXPECT_EQ(info["message_count"].as<int>(), 10);
  EXPECT_EQ(info["topics_with_message_count"][0]["message_count"].as<int>(), 10);
  EXPECT_FALSE(fs::exists(directory + "/metadata.yaml.tmp"));
  fs::remove_all(directory);
}

// What the writer wrote reads back (record/rosbag2_reader.h): topics by name, the index in time order
// whatever order messages were written in, each message's bytes; a killed writer's bag as of its last
// flush; a directory that is no bag is refused with its reason.
TEST(Rosbag2ReaderTest, ReadsBackWhatTheWriterWrote) {
  const std::string directory = fresh_directory("read");
  std::string error;
  {
    auto bag = Rosbag2Writer::create(directory, &error);
    ASSERT_NE(bag, nullptr) << error;
    const int odometry = bag->add_topic({"/auv/odometry", "nav_msgs/msg/Odometry", {}});
    const int clock = bag->add_topic({"/clock", "rosgraph_msgs/msg/Clock", {}});
    const std::vector<unsigned char> a{0, 1, 0, 0, 1}, b{0, 1, 0, 0, 2, 2}, c{0, 1, 0, 0, 3, 3, 3};
    ASSERT_TRUE(bag->write(clock, 300, c.data(), c.size()));
    ASSERT_TRUE(bag->write(odometry, 100, a.data(), a.size()));
    ASSERT_TRUE(bag->write(clock, 200, b.data(), b.size()));
    ASSERT_TRUE(bag->flush());
    ASSERT_TRUE(bag->write(clock, 400, c.data(), c.size()));
  }
  auto reader = Rosbag2Reader::open(directory, &error);
  ASSERT_NE(reader, nullptr) << error;
  ASSERT_EQ(reader->topics().size(), 2u);
  EXPECT_EQ(reader->topics()[0].name, "/auv/odometry");
  EXPECT_EQ(reader->topics()[1].type, "rosgraph_msgs/msg/Clock");
  const auto& index = reader->index();
  ASSERT_EQ(index.size(), 4u);
  const std::vector<std::int64_t> times{index[0].timestamp_ns, index[1].timestamp_ns, index[2].timestamp_ns,
                                        index[3].timestamp_ns};
  EXPECT_EQ(times, (std::vector<std::int64_t>{100, 200, 300, 400}));
  EXPECT_EQ(index[0].topic, 0);
  EXPECT_EQ(index[1].topic, 1);
  std::vector<unsigned char> bytes;
  ASSERT_TRUE(reader->read(index[1], &bytes, &error)) << error;
  EXPECT_EQ(bytes, (std::vector<unsigned char>{0, 1, 0, 0, 2, 2}));
  ASSERT_TRUE(reader->read(index[0], &bytes, &error)) << error;
  EXPECT_EQ(bytes.size(), 5u);

  EXPECT_EQ(Rosbag2Reader::open(directory + "/nothing", &error), nullptr);
  EXPECT_EQ(error, "no bag directory " + directory + "/nothing");
  fs::remove(directory + "/metadata.yaml");
  EXPECT_EQ(Rosbag2Reader::open(directory, &error), nullptr);
  EXPECT_NE(error.find(directory + "/metadata.yaml: "), std::string::npos) << error;
  fs::remove_all(directory);
}

}  // namespace
}  // namespace hadal::record
