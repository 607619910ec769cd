#include "hadal/record/rosbag2_writer.h"

#include <sqlite3.h>
#include <sys/stat.h>
#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>

namespace hadal::record {

namespace {

constexpr int kSchemaVersion = 4;    // rosbag2_storage_sqlite3's database schema
constexpr int kMetadataVersion = 9;  // rosbag2_storage's BagMetadata
// rmw's "infinite" duration (RMW_DURATION_INFINITE) as rosbag2 writes it.
constexpr std::int64_t kInfiniteSec = 9223372036LL;
constexpr std::int64_t kInfiniteNsec = 854775807LL;

// rosbag2's tables, statement for statement (rosbag2_storage_sqlite3, SqliteStorage::initialize).
const char* const kCreateStatements[] = {
    "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY,ros_distro TEXT NOT NULL);",
    "CREATE TABLE metadata(id INTEGER PRIMARY KEY,metadata_version INTEGER NOT NULL,metadata TEXT NOT NULL);",
    "CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT NULL,type TEXT NOT NULL,"
    "serialization_format TEXT NOT NULL,offered_qos_profiles TEXT NOT NULL,type_description_hash TEXT NOT NULL);",
    "CREATE TABLE message_definitions(id INTEGER PRIMARY KEY,topic_type TEXT NOT NULL,encoding TEXT NOT NULL,"
    "encoded_message_definition TEXT NOT NULL,type_description_hash TEXT NOT NULL);",
    "CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp INTEGER NOT NULL, "
    "data BLOB NOT NULL);",
    "CREATE INDEX timestamp_idx ON messages (timestamp ASC);",
};

std::string base_name(const std::string& path) {
  std::string trimmed = path;
  while (trimmed.size() > 1 && trimmed.back() == '/') trimmed.pop_back();
  const auto slash = trimmed.find_last_of('/');
  return slash == std::string::npos ? trimmed : trimmed.substr(slash + 1);
}

YAML::Node duration_node(std::int64_t sec, std::int64_t nsec) {
  YAML::Node node;
  node["sec"] = sec;
  node["nsec"] = nsec;
  return node;
}

// The offered QoS as rosbag2 (metadata version 9) writes it: a list with one profile.
YAML::Node qos_node(const OfferedQos& qos) {
  YAML::Node profile;
  profile["history"] = "unknown";
  profile["depth"] = 0;
  profile["reliability"] = qos.reliable ? "reliable" : "best_effort";
  profile["durability"] = qos.transient_local ? "transient_local" : "volatile";
  profile["deadline"] = duration_node(kInfiniteSec, kInfiniteNsec);
  profile["lifespan"] = duration_node(kInfiniteSec, kInfiniteNsec);
  profile["liveliness"] = "automatic";
  profile["liveliness_lease_duration"] = duration_node(kInfiniteSec, kInfiniteNsec);
  profile["avoid_ros_namespace_conventions"] = false;
  YAML::Node list(YAML::NodeType::Sequence);
  list.push_back(profile);
  return list;
}

std::string dump(const YAML::Node& node) {
  YAML::Emitter out;
  out << node;
  return out.c_str();
}

}  // namespace

struct Rosbag2Writer::Impl {
  sqlite3* db = nullptr;
  sqlite3_stmt* insert_message = nullptr;
  bool in_transaction = false;
  std::vector<BagTopic> topics;  // id - 1
  std::map<std::string, int> topic_ids;
  std::vector<std::uint64_t> counts;  // per topic, committed or not
  std::vector<std::uint64_t> committed_counts;
  std::int64_t first_ns = std::numeric_limits<std::int64_t>::max();
  std::int64_t last_ns = std::numeric_limits<std::int64_t>::min();
  std::int64_t committed_first_ns = 0;
  std::int64_t committed_last_ns = 0;
  bool closed = false;

  ~Impl() {  // a bag that failed half-made, or one closed already (db is then null)
    sqlite3_finalize(insert_message);
    sqlite3_close(db);
  }

  bool exec(const char* sql, std::string* error) {
    char* message = nullptr;
    if (sqlite3_exec(db, sql, nullptr, nullptr, &message) != SQLITE_OK) {
      *error = std::string(sql) + ": " + (message ? message : "sqlite error");
      sqlite3_free(message);
      return false;
    }
    return true;
  }
};

std::string Rosbag2Writer::existing_directory_error(const std::string& directory) {
  struct stat existing {};
  if (stat(directory.c_str(), &existing) != 0) return "";
  return "bag directory " + directory + " already exists (a rosbag2 bag is never appended to)";
}

std::unique_ptr<Rosbag2Writer> Rosbag2Writer::create(const std::string& directory, std::string* error) {
  if (*error = existing_directory_error(directory); !error->empty()) return nullptr;
  if (mkdir(directory.c_str(), 0755) != 0) {
    *error = "cannot create bag directory " + directory + ": " + std::strerror(errno);
    return nullptr;
  }
  auto impl = std::make_unique<Impl>();
  const std::string database = directory + "/" + base_name(directory) + "_0.db3";
  if (sqlite3_open_v2(database.c_str(), &impl->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    *error = "cannot create " + database + ": " + sqlite3_errmsg(impl->db);
    return nullptr;
  }
  // WAL with synchronous=NORMAL: a committed transaction survives the process being killed (rosbag2's
  // "resilient" preset uses the same two pragmas).
  if (!impl->exec("PRAGMA journal_mode=WAL;", error) || !impl->exec("PRAGMA synchronous=NORMAL;", error)) {
    return nullptr;
  }
  for (const char* statement : kCreateStatements) {
    if (!impl->exec(statement, error)) return nullptr;
  }
  // ros_distro: the ROS 2 release whose rosbag2 these formats are (schema 4, metadata 9).
  const std::string insert_schema =
      "INSERT INTO schema (schema_version, ros_distro) VALUES (" + std::to_string(kSchemaVersion) + ", 'jazzy');";
  if (!impl->exec(insert_schema.c_str(), error) ||
      sqlite3_prepare_v2(impl->db, "INSERT INTO messages (timestamp, topic_id, data) VALUES (?, ?, ?);", -1,
                         &impl->insert_message, nullptr) != SQLITE_OK) {
    if (error->empty()) *error = sqlite3_errmsg(impl->db);
    return nullptr;
  }
  std::unique_ptr<Rosbag2Writer> writer(new Rosbag2Writer(std::move(impl), directory, database));
  if (!writer->flush()) {  // metadata.yaml from the start: an empty bag is a bag
    *error = writer->error();
    return nullptr;
  }
  return writer;
}

Rosbag2Writer::Rosbag2Writer(std::unique_ptr<Impl> impl, std::string directory, std::string database_path)
    : impl_(std::move(impl)), directory_(std::move(directory)), database_path_(std::move(database_path)) {}

Rosbag2Writer::~Rosbag2Writer() { close(); }

int Rosbag2Writer::add_topic(const BagTopic& topic) {
  Impl& d = *impl_;
  if (const auto found = d.topic_ids.find(topic.name); found != d.topic_ids.end()) return found->second;
  sqlite3_stmt* insert = nullptr;
  sqlite3_prepare_v2(d.db,
                     "INSERT INTO topics (name, type, serialization_format, offered_qos_profiles, "
                     "type_description_hash) VALUES (?, ?, 'cdr', ?, '');",
                     -1, &insert, nullptr);
  const std::string qos = dump(qos_node(topic.qos));
  sqlite3_bind_text(insert, 1, topic.name.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(insert, 2, topic.type.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(insert, 3, qos.c_str(), -1, SQLITE_TRANSIENT);
  const int inserted = sqlite3_step(insert);
  sqlite3_finalize(insert);
  if (inserted != SQLITE_DONE) {
    error_ = std::string("cannot add topic ") + topic.name + ": " + sqlite3_errmsg(d.db);
    return -1;
  }
  // The topic's id, before the definitions table takes its own row id.
  const int id = static_cast<int>(sqlite3_last_insert_rowid(d.db));
  bool known_type = false;
  for (const BagTopic& other : d.topics) known_type = known_type || other.type == topic.type;
  if (!known_type) {  // rosbag2 writes one definition row per type; "unknown" when it has no definition
    sqlite3_stmt* definition = nullptr;
    sqlite3_prepare_v2(d.db,
                       "INSERT INTO message_definitions (topic_type, encoding, encoded_message_definition, "
                       "type_description_hash) VALUES (?, 'unknown', '', '');",
                       -1, &definition, nullptr);
    sqlite3_bind_text(definition, 1, topic.type.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_step(definition);
    sqlite3_finalize(definition);
  }
  d.topics.resize(std::max<std::size_t>(d.topics.size(), static_cast<std::size_t>(id)));
  d.topics[static_cast<std::size_t>(id - 1)] = topic;
  d.counts.resize(d.topics.size(), 0);
  d.committed_counts.resize(d.topics.size(), 0);
  d.topic_ids[topic.name] = id;
  return id;
}

bool Rosbag2Writer::write(int topic_id, std::int64_t timestamp_ns, const unsigned char* data, std::size_t size) {
  Impl& d = *impl_;
  if (d.closed || topic_id < 1 || static_cast<std::size_t>(topic_id) > d.topics.size()) {
    error_ = d.closed ? "the bag is closed" : "no topic " + std::to_string(topic_id) + " in the bag";
    return false;
  }
  if (!d.in_transaction) {
    if (!d.exec("BEGIN TRANSACTION;", &error_)) return false;
    d.in_transaction = true;
  }
  sqlite3_bind_int64(d.insert_message, 1, timestamp_ns);
  sqlite3_bind_int(d.insert_message, 2, topic_id);
  sqlite3_bind_blob64(d.insert_message, 3, data, size, SQLITE_STATIC);
  const int result = sqlite3_step(d.insert_message);
  sqlite3_reset(d.insert_message);
  if (result != SQLITE_DONE) {
    error_ = std::string("writing a message: ") + sqlite3_errmsg(d.db);
    return false;
  }
  ++d.counts[static_cast<std::size_t>(topic_id - 1)];
  d.first_ns = std::min(d.first_ns, timestamp_ns);
  d.last_ns = std::max(d.last_ns, timestamp_ns);
  return true;
}

std::uint64_t Rosbag2Writer::message_count() const {
  std::uint64_t total = 0;
  for (std::uint64_t count : impl_->counts) total += count;
  return total;
}

std::string Rosbag2Writer::metadata_yaml(bool for_database) const {
  const Impl& d = *impl_;
  YAML::Node info;
  std::uint64_t total = 0;
  for (std::uint64_t count : d.committed_counts) total += count;
  const std::string file = base_name(database_path_);
  YAML::Node duration;
  duration["nanoseconds"] = total > 0 ? d.committed_last_ns - d.committed_first_ns : 0;
  YAML::Node start;
  start["nanoseconds_since_epoch"] = total > 0 ? d.committed_first_ns : 0;
  info["version"] = kMetadataVersion;
  info["storage_identifier"] = "sqlite3";
  info["duration"] = duration;
  info["starting_time"] = start;
  info["message_count"] = total;
  YAML::Node topics(YAML::NodeType::Sequence);
  for (std::size_t i = 0; i < d.topics.size(); ++i) {
    YAML::Node metadata;
    metadata["name"] = d.topics[i].name;
    metadata["type"] = d.topics[i].type;
    metadata["serialization_format"] = "cdr";
    metadata["offered_qos_profiles"] = qos_node(d.topics[i].qos);
    metadata["type_description_hash"] = "";
    YAML::Node entry;
    entry["topic_metadata"] = metadata;
    entry["message_count"] = d.committed_counts[i];
    topics.push_back(entry);
  }
  info["topics_with_message_count"] = topics;
  info["compression_format"] = "";
  info["compression_mode"] = "";
  YAML::Node paths(YAML::NodeType::Sequence);
  paths.push_back(file);
  info["relative_file_paths"] = paths;
  YAML::Node file_info;
  file_info["path"] = file;
  file_info["starting_time"] = YAML::Clone(start);  // copies, not aliases of the bag's own
  file_info["duration"] = YAML::Clone(duration);
  file_info["message_count"] = total;
  YAML::Node files(YAML::NodeType::Sequence);
  files.push_back(file_info);
  info["files"] = files;
  info["custom_data"] = YAML::Node(YAML::NodeType::Map);
  info["ros_distro"] = "jazzy";
  if (for_database) return dump(info);
  YAML::Node root;
  root["rosbag2_bagfile_information"] = info;
  return dump(root) + "\n";
}

bool Rosbag2Writer::flush() {
  Impl& d = *impl_;
  if (d.in_transaction) {
    if (!d.exec("COMMIT;", &error_)) return false;
    d.in_transaction = false;
  }
  d.committed_counts = d.counts;
  if (d.first_ns <= d.last_ns) {
    d.committed_first_ns = d.first_ns;
    d.committed_last_ns = d.last_ns;
  }
  const std::string path = directory_ + "/metadata.yaml";
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << metadata_yaml(false);
    if (!out.good()) {
      error_ = "cannot write " + temporary;
      return false;
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    error_ = "cannot rename " + temporary + " to " + path + ": " + std::strerror(errno);
    return false;
  }
  return true;
}

void Rosbag2Writer::close() {
  Impl& d = *impl_;
  if (d.closed) return;
  flush();
  sqlite3_stmt* insert = nullptr;
  sqlite3_prepare_v2(d.db, "INSERT INTO metadata (metadata_version, metadata) VALUES (?, ?);", -1, &insert,
                     nullptr);
  const std::string metadata = metadata_yaml(true);
  sqlite3_bind_int(insert, 1, kMetadataVersion);
  sqlite3_bind_text(insert, 2, metadata.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_step(insert);
  sqlite3_finalize(insert);
  sqlite3_finalize(d.insert_message);
  d.insert_message = nullptr;
  // Checkpoint the WAL into the database file, so that a closed bag is one .db3 file as rosbag2's are.
  // Left in WAL mode (all of it checkpointed into the .db3 all the same) while another process reads it.
  std::string ignored;
  sqlite3_busy_timeout(d.db, 2000);
  if (d.exec("PRAGMA wal_checkpoint(TRUNCATE);", &ignored)) d.exec("PRAGMA journal_mode=DELETE;", &ignored);
  sqlite3_close(d.db);
  d.db = nullptr;
  d.closed = true;
}

}  // namespace hadal::record
