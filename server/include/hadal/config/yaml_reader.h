// Strict YAML reading (docs/ARCHITECTURE.md, "Strict configuration"): typed getters over yaml-cpp nodes that turn
// every problem into a Diagnostic instead of throwing, so that one load reports all errors at once.
//
//   DiagnosticSink  collects diagnostics; sorts them by file (in the order files were opened, so a
//                   scenario's errors come before those of the files it includes), line, column.
//   Value           one node + the file holding it + its path (`vehicles[0].links[1].mass`), with
//                   typed conversions (number in a Range, non-negative integer, string, n-vector,
//                   list, one-of-choices) that report at the node and return nullopt on error.
//   MapReader       a map node with a declared set of allowed keys: reports unknown keys (with a
//                   "did you mean" suggestion by edit distance), duplicate keys and non-string keys on
//                   construction; hands out values by key and reports missing required keys at the map.
//
// Numbers follow the YAML 1.2 core schema for plain (unquoted) scalars: decimal integers and floats,
// `.inf`/`.nan` (which are rejected as non-finite). Quoted scalars are strings, never numbers.
// Positions are reported 1-based (yaml-cpp marks are 0-based).
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hadal/config/diagnostic.h"
#include "hadal/config/key_doc.h"  // Range, format_number

namespace hadal::config {

class DiagnosticSink {
 public:
  // Registers a file so that its diagnostics sort after those of files opened before it.
  void add_file(const std::string& file);
  // `mark` is yaml-cpp's 0-based mark; a null mark (or one with negative line) yields line 0 column 0,
  // meaning "no position" (e.g. a file that cannot be opened).
  void report(const std::string& file, const YAML::Mark& mark, std::string path, std::string message,
              bool warning = false);

  bool empty() const { return diagnostics_.empty(); }  // no errors and no warnings
  // All diagnostics sorted by (file order, line, column); ties keep the order of reporting.
  std::vector<Diagnostic> sorted() const;

 private:
  std::vector<std::string> files_;
  std::vector<Diagnostic> diagnostics_;
};

// Reads and parses a whole YAML file holding exactly one document. Returns nullopt if the file cannot be
// read (then *open_error says why and nothing is reported: the caller knows where to report it), or if it
// does not parse or holds several documents (reported at the parser's mark, path `yaml`). An empty file
// yields a null node.
std::optional<YAML::Node> parse_yaml_file(const std::string& file, DiagnosticSink* sink,
                                          std::string* open_error);

// The closest candidate to `word` by case-insensitive edit distance (insertions, deletions, substitutions,
// adjacent transpositions), if close enough to be a plausible typo (distance <= max(1, candidate length /
// 3)); ties go to the earlier candidate.
std::optional<std::string> closest_match(const std::string& word, const std::vector<std::string>& candidates);

struct Override;

// A source file being read: where its diagnostics go, and where the files it names may lie.
struct Source {
  std::string file;
  DiagnosticSink* sink = nullptr;
  // The directories (absolute, symlinks resolved) a file this one names must lie in; null: anywhere.
  std::shared_ptr<const std::vector<std::filesystem::path>> roots;
  // Values that stand in for this file's own (command-line overrides: config/scenario_loader.h), each at its
  // path in this file; null or empty: none. Owned by whoever reads the file, alive while it is read.
  const std::vector<Override>* overrides = nullptr;
  // Where the relative file names this source's values give resolve; empty: the directory of `file`.
  std::filesystem::path directory;
};

class Value {
 public:
  Value(YAML::Node node, std::shared_ptr<const Source> source, std::string path, YAML::Mark mark);
  // The root of a parsed document (empty path).
  static Value root(YAML::Node node, std::shared_ptr<const Source> source);

  const YAML::Node& node() const { return node_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return source_->file; }
  const YAML::Mark& mark() const { return mark_; }
  const std::shared_ptr<const Source>& source() const { return source_; }
  bool is_map() const { return node_.IsMap(); }

  // Reports `message` at this node.
  void error(const std::string& message) const;
  // Reports a warning at this node (the load goes on).
  void warn(const std::string& message) const;
  // What the node holds, for "(got ...)": 'text' for plain scalars, the string "text" for quoted ones,
  // null, a list of 2, a map, an empty document. A document that is one scalar (a file that is not YAML
  // keys and values) is never quoted: a name gone wrong must not print another file's contents.
  std::string describe() const;
  // The file `written` (this node's text) names, relative to the directory of the file holding this node,
  // in *path. False, with an error here, when it lies outside the source's roots once symlinks are
  // resolved, or names something that is not a regular file (a directory, a device, a pipe)
  // (docs/ARCHITECTURE.md, "Files a scenario may reach"). A file that does not exist passes: its reader
  // reports it.
  bool file_path(const std::string& written, std::string* path) const;
  // Why `path` may not be named by this source's files, or "": outside its roots once symlinks are resolved
  // ("lies outside ..."), or not a regular file. `written` is how the file named it.
  std::string file_refusal(const std::filesystem::path& path, const std::string& written) const;
  // The directories the files this source names must lie in (null: anywhere).
  const std::vector<std::filesystem::path>* roots() const { return source_->roots.get(); }
  // The overrides standing in for values of this node's file (null: none).
  const std::vector<Override>* overrides() const { return source_->overrides; }
  // Reports in another file this one led to (a URDF a vehicle names): 1-based line and column (0: none).
  void report_in(const std::string& file, int line, int column, std::string path, std::string message,
                 bool warning = false) const;

  // Element `index` of a list node (path `path[index]`).
  Value element(std::size_t index) const;
  // Another node of the same file, at `path` and `mark` (e.g. the value of a map entry).
  Value in_same_file(YAML::Node node, std::string path, YAML::Mark mark) const;
  // Reports `message` in this node's file at another position.
  void error_at(const YAML::Mark& mark, const std::string& path, const std::string& message) const;

  // Typed conversions. On failure they report at this node (or the offending element) and return nullopt.
  std::optional<double> number(const Range& range = Range::finite()) const;
  std::optional<std::uint64_t> non_negative_integer() const;
  std::optional<std::string> string() const;  // any non-empty scalar
  // A plain true/True/TRUE or false/False/FALSE (YAML 1.2 core schema; YAML 1.1's yes/no/on/off are
  // rejected as ambiguous).
  std::optional<bool> boolean() const;
  std::optional<std::vector<Value>> list() const;
  // A list of numbers, each in `each`; with `count`, exactly that many. All bad elements are reported.
  std::optional<std::vector<double>> numbers(std::optional<std::size_t> count,
                                             const Range& each = Range::finite()) const;
  std::optional<Eigen::Vector3d> vector3(const Range& each = Range::finite()) const;
  // One of named choices; the error lists them all.
  template <typename E>
  std::optional<E> choice(const std::vector<std::pair<std::string, E>>& choices) const;

 private:
  // Reports "must be one of ..." for `text` (kept out of the template).
  void report_bad_choice(const std::vector<std::string>& names) const;

  YAML::Node node_;
  std::shared_ptr<const Source> source_;
  std::string path_;
  YAML::Mark mark_;
};

// A value standing in for a file's own at `path` (as diagnostics print paths in that file:
// "world.water.current.uniform", "vehicles[0].initial_pose"): the map holding that key reads `value` in place
// of the file's, or as if the file had it, creating the maps on the way that the file lacks. `value`'s own
// source says where its errors are reported.
struct Override {
  std::string path;
  Value value;
  // Each key's path on the way and the 0-based column of its name in the override's text (an unknown key is
  // reported there).
  std::vector<std::pair<std::string, int>> key_columns;
};

enum class Need { kOptional, kRequired };

class MapReader {
 public:
  // Checks that `value` is a map (reporting "expected a map" otherwise) whose keys are plain strings,
  // unique, and among `allowed`; each violation is reported at its key.
  MapReader(Value value, std::vector<std::string> allowed);

  bool ok() const { return ok_; }  // the value is a map
  const Value& value() const { return value_; }

  bool has(const std::string& key) const;
  // Whether `key` is one of the allowed keys.
  bool allows(const std::string& key) const;
  // The value of `key`, or nullopt when absent. `key` must be one of the allowed keys.
  std::optional<Value> optional(const std::string& key) const;
  // Like optional(), but reports "missing required key 'key'" at the map when absent; `why` is appended
  // in parentheses when given.
  std::optional<Value> required(const std::string& key, const std::string& why = "") const;
  std::optional<Value> get(const std::string& key, Need need) const;
  // Reports `message` at the key node of `key`, with path `map.key`; an absent key's at the map, as
  // "key: message".
  void error_at_key(const std::string& key, const std::string& message) const;

  // Shorthands: read `key` into *out (unchanged when an optional key is absent). They return false when
  // the value is invalid or a required key is missing, true otherwise.
  bool read_number(const std::string& key, Need need, const Range& range, double* out) const;
  // A number in `range` that must also be whole ("must be a whole number (got x)" otherwise).
  bool read_whole_number(const std::string& key, Need need, const Range& range, int* out) const;
  bool read_vector3(const std::string& key, Need need, const Range& each, Eigen::Vector3d* out) const;
  // A direction: a non-zero 3-vector ("must be non-zero (got [x, y, z])" below 1e-9, where the normalised
  // vector would be dominated by rounding), stored normalised.
  bool read_direction(const std::string& key, Need need, Eigen::Vector3d* out) const;
  bool read_string(const std::string& key, Need need, std::string* out) const;
  bool read_bool(const std::string& key, Need need, bool* out) const;
  template <typename E>
  bool read_choice(const std::string& key, Need need, const std::vector<std::pair<std::string, E>>& choices,
                   E* out) const;

 private:
  struct Entry {
    std::string key;
    YAML::Node key_node;
    Value value;
    bool overridden = false;  // `value` is an override's (errors at its key are reported at it)
  };
  const Entry* find(const std::string& key) const;
  void check_allowed(const std::string& key) const;
  // The overrides at or below this map's keys, in their order (a later one wins).
  void apply_overrides();

  Value value_;
  std::vector<std::string> allowed_;
  std::vector<Entry> entries_;  // first occurrence of each key, in file order
  bool ok_ = false;
};

// 'text' (names in messages).
std::string quoted(const std::string& text);
// "a, b, c".
std::string join_names(const std::vector<std::string>& names);

// Whether `key` reads as a key name (letters, digits, '_' and '-', not starting with a digit, at most 64
// characters): only such keys are quoted in messages.
bool is_key_name(const std::string& key);
// Path of key `key` inside the map at `path` ("a.b" or "b" at the root).
std::string child_path(const std::string& path, const std::string& key);

template <typename E>
std::optional<E> Value::choice(const std::vector<std::pair<std::string, E>>& choices) const {
  if (const auto text = string()) {
    for (const auto& [name, item] : choices) {
      if (*text == name) return item;
    }
    std::vector<std::string> names;
    for (const auto& entry : choices) names.push_back(entry.first);
    report_bad_choice(names);
  }
  return std::nullopt;
}

template <typename E>
bool MapReader::read_choice(const std::string& key, Need need,
                            const std::vector<std::pair<std::string, E>>& choices, E* out) const {
  const std::optional<Value> value = get(key, need);
  if (!value) return need == Need::kOptional;
  const std::optional<E> result = value->choice(choices);
  if (result) *out = *result;
  return result.has_value();
}

}  // namespace hadal::config
