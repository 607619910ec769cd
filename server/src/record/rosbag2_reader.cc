#include "hadal/record/rosbag2_reader.h"

#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <map>

namespace hadal::record {

struct Rosbag2Reader::Impl {
  std::vector<sqlite3*> dbs;
  std::vector<sqlite3_stmt*> reads;  // per database: SELECT data FROM messages WHERE id = ?
  ~Impl() {
    for (sqlite3_stmt* read : reads) sqlite3_finalize(read);
    for (sqlite3* db : dbs) sqlite3_close(db);
  }
};

Rosbag2Reader::Rosbag2Reader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Rosbag2Reader::~Rosbag2Reader() = default;

namespace {

// The database files metadata.yaml names, relative to the bag directory.
bool database_files(const std::string& directory, std::vector<std::string>* files, std::string* error) {
  const std::string metadata = directory + "/metadata.yaml";
  try {
    const YAML::Node info = YAML::LoadFile(metadata)["rosbag2_bagfile_information"];
    if (!info) {
      *error = metadata + ": no rosbag2_bagfile_information";
      return false;
    }
    const std::string storage = info["storage_identifier"].as<std::string>("");
    if (storage != "sqlite3") {
      *error = metadata + ": storage '" + storage + "' (only sqlite3 bags are read)";
      return false;
    }
    for (const YAML::Node& path : info["relative_file_paths"]) {
      files->push_back(directory + "/" + path.as<std::string>());
    }
  } catch (const YAML::Exception& e) {
    *error = metadata + ": " + e.what();
    return false;
  }
  if (files->empty()) *error = metadata + ": no database files";
  return !files->empty();
}

}  // namespace

std::unique_ptr<Rosbag2Reader> Rosbag2Reader::open(const std::string& directory, std::string* error) {
  if (!std::filesystem::is_directory(directory)) {
    *error = "no bag directory " + directory;
    return nullptr;
  }
  std::vector<std::string> files;
  if (!database_files(directory, &files, error)) return nullptr;
  auto impl = std::make_unique<Impl>();
  std::vector<BagTopic> topics;
  std::map<std::string, int> topic_by_name;
  std::vector<BagIndexEntry> index;
  for (std::size_t f = 0; f < files.size(); ++f) {
    sqlite3* db = nullptr;
    const int opened = sqlite3_open_v2(files[f].c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
    impl->dbs.push_back(db);
    auto fail = [&](const std::string& what) {
      *error = files[f] + ": " + what + (db ? std::string(" (") + sqlite3_errmsg(db) + ")" : "");
      return nullptr;
    };
    if (opened != SQLITE_OK) return fail("cannot open");
    // This file's topic ids -> the reader's topic indices (files of a split bag number topics alike, but a
    // name is the key).
    std::map<std::int64_t, int> topic_of_id;
    sqlite3_stmt* query = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT id, name, type, serialization_format FROM topics ORDER BY id;", -1, &query,
                           nullptr) != SQLITE_OK) {
      return fail("not a rosbag2 sqlite3 database");
    }
    while (sqlite3_step(query) == SQLITE_ROW) {
      auto text = [&](int column) {
        const unsigned char* value = sqlite3_column_text(query, column);
        return value ? std::string(reinterpret_cast<const char*>(value)) : std::string();
      };
      const std::string name = text(1), format = text(3);
      if (format != "cdr") {
        sqlite3_finalize(query);
        return fail("topic " + name + " is serialized as '" + format + "', not cdr");
      }
      auto [it, added] = topic_by_name.emplace(name, static_cast<int>(topics.size()));
      if (added) topics.push_back({name, text(2), {}});
      topic_of_id[sqlite3_column_int64(query, 0)] = it->second;
    }
    sqlite3_finalize(query);
    if (sqlite3_prepare_v2(db, "SELECT id, timestamp, topic_id FROM messages;", -1, &query, nullptr) != SQLITE_OK) {
      return fail("not a rosbag2 sqlite3 database");
    }
    while (sqlite3_step(query) == SQLITE_ROW) {
      const auto topic = topic_of_id.find(sqlite3_column_int64(query, 2));
      if (topic == topic_of_id.end()) continue;  // a message of no topic: nothing to say what it is
      index.push_back(
          {sqlite3_column_int64(query, 1), topic->second, static_cast<int>(f), sqlite3_column_int64(query, 0)});
    }
    sqlite3_finalize(query);
    sqlite3_stmt* read = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT data FROM messages WHERE id = ?;", -1, &read, nullptr) != SQLITE_OK) {
      return fail("not a rosbag2 sqlite3 database");
    }
    impl->reads.push_back(read);
  }
  std::stable_sort(index.begin(), index.end(), [](const BagIndexEntry& a, const BagIndexEntry& b) {
    return a.timestamp_ns != b.timestamp_ns ? a.timestamp_ns < b.timestamp_ns
                                            : (a.file != b.file ? a.file < b.file : a.row < b.row);
  });
  std::unique_ptr<Rosbag2Reader> reader(new Rosbag2Reader(std::move(impl)));
  reader->topics_ = std::move(topics);
  reader->index_ = std::move(index);
  return reader;
}

bool Rosbag2Reader::read(const BagIndexEntry& entry, std::vector<unsigned char>* bytes, std::string* error) const {
  sqlite3_stmt* read = impl_->reads.at(static_cast<std::size_t>(entry.file));
  sqlite3_reset(read);
  sqlite3_bind_int64(read, 1, entry.row);
  if (sqlite3_step(read) != SQLITE_ROW) {
    *error = "message " + std::to_string(entry.row) + " is gone (" + sqlite3_errmsg(impl_->dbs[entry.file]) + ")";
    return false;
  }
  const auto* data = static_cast<const unsigned char*>(sqlite3_column_blob(read, 0));
  bytes->assign(data, data + sqlite3_column_bytes(read, 0));
  sqlite3_reset(read);
  return true;
}

}  // namespace hadal::record
