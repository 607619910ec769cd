#include "hadal/config/yaml_reader.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace hadal::config {

std::string Diagnostic::format() const {
  // Line 0 means "no position" (e.g. a file that cannot be opened); an empty path is the document root.
  std::string out = file;
  if (line > 0) out += ":" + std::to_string(line) + ":" + std::to_string(column);
  out += warning ? ": warning: " : ": error: ";
  if (!path.empty()) out += path + ": ";
  return out + message;
}

std::string quoted(const std::string& text) { return "'" + text + "'"; }

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i > 0 ? ", " : "") + names[i];
  return out;
}

namespace {

int one_based(int zero_based) { return zero_based >= 0 ? zero_based + 1 : 0; }

// A plain scalar in the YAML 1.2 core schema's float/int syntax, or its .inf/.nan spellings.
// Returns nullopt when `text` is not a number at all; the value may be non-finite.
std::optional<double> parse_core_number(const std::string& text) {
  static const char* const kSpecial[] = {".inf", ".Inf", ".INF", "+.inf", "+.Inf", "+.INF"};
  for (const char* special : kSpecial) {
    if (text == special) return std::numeric_limits<double>::infinity();
  }
  if (text == "-.inf" || text == "-.Inf" || text == "-.INF") return -std::numeric_limits<double>::infinity();
  if (text == ".nan" || text == ".NaN" || text == ".NAN") return std::numeric_limits<double>::quiet_NaN();

  // [-+]? ( \.[0-9]+ | [0-9]+ ( \.[0-9]* )? ) ( [eE] [-+]? [0-9]+ )?
  std::size_t i = 0;
  const std::size_t n = text.size();
  auto digits = [&] {
    const std::size_t start = i;
    while (i < n && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
    return i - start;
  };
  if (i < n && (text[i] == '-' || text[i] == '+')) ++i;
  const std::size_t mantissa_start = i;
  const std::size_t integer_digits = digits();
  std::size_t fraction_digits = 0;
  if (i < n && text[i] == '.') {
    ++i;
    fraction_digits = digits();
  }
  if (integer_digits == 0 && fraction_digits == 0) return std::nullopt;
  if (i < n && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < n && (text[i] == '-' || text[i] == '+')) ++i;
    if (digits() == 0) return std::nullopt;
  }
  if (i != n) return std::nullopt;

  // from_chars takes no leading '+' and is locale independent (strtod is not).
  const bool negative = text[0] == '-';
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data() + mantissa_start, text.data() + n, value);
  if (ec == std::errc::result_out_of_range) {
    // Overflow reads as infinity (rejected as non-finite); underflow (a negative exponent, or a tiny
    // fraction written out) as zero.
    const std::size_t e = text.find_first_of("eE");
    const bool underflow = e != std::string::npos ? text[e + 1] == '-'
                                                  : text.find_first_not_of('0', mantissa_start) ==
                                                        mantissa_start + integer_digits;
    value = underflow ? 0.0 : std::numeric_limits<double>::infinity();
  } else if (ec != std::errc() || end != text.data() + n) {
    return std::nullopt;
  }
  return negative ? -value : value;
}

// Optimal-string-alignment distance (Levenshtein plus adjacent transpositions, the commonest typo),
// ignoring case.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  auto same = [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  };
  const std::size_t columns = b.size() + 1;
  std::vector<std::size_t> d((a.size() + 1) * columns);
  auto at = [&](std::size_t i, std::size_t j) -> std::size_t& { return d[i * columns + j]; };
  for (std::size_t i = 0; i <= a.size(); ++i) at(i, 0) = i;
  for (std::size_t j = 0; j <= b.size(); ++j) at(0, j) = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      at(i, j) = std::min(
          {at(i - 1, j) + 1, at(i, j - 1) + 1, at(i - 1, j - 1) + (same(a[i - 1], b[j - 1]) ? 0 : 1)});
      if (i > 1 && j > 1 && same(a[i - 1], b[j - 2]) && same(a[i - 2], b[j - 1])) {
        at(i, j) = std::min(at(i, j), at(i - 2, j - 2) + 1);
      }
    }
  }
  return at(a.size(), b.size());
}

}  // namespace

// ---------------------------------------------------------------------------------------------------

void DiagnosticSink::add_file(const std::string& file) {
  if (std::find(files_.begin(), files_.end(), file) == files_.end()) files_.push_back(file);
}

void DiagnosticSink::report(const std::string& file, const YAML::Mark& mark, std::string path,
                            std::string message, bool warning) {
  add_file(file);
  Diagnostic diagnostic;
  diagnostic.file = file;
  diagnostic.line = one_based(mark.line);
  diagnostic.column = diagnostic.line > 0 ? one_based(mark.column) : 0;
  diagnostic.path = std::move(path);
  diagnostic.message = std::move(message);
  diagnostic.warning = warning;
  diagnostics_.push_back(std::move(diagnostic));
}

std::vector<Diagnostic> DiagnosticSink::sorted() const {
  auto file_rank = [this](const std::string& file) {
    return std::find(files_.begin(), files_.end(), file) - files_.begin();
  };
  std::vector<Diagnostic> out = diagnostics_;
  std::stable_sort(out.begin(), out.end(), [&](const Diagnostic& a, const Diagnostic& b) {
    const auto rank_a = file_rank(a.file);
    const auto rank_b = file_rank(b.file);
    if (rank_a != rank_b) return rank_a < rank_b;
    if (a.line != b.line) return a.line < b.line;
    return a.column < b.column;
  });
  // A file read twice (an included vehicle file read again with an entry's overrides) reports its own
  // problems twice: once is enough.
  out.erase(std::unique(out.begin(), out.end(),
                        [](const Diagnostic& a, const Diagnostic& b) {
                          return a.file == b.file && a.line == b.line && a.column == b.column && a.path == b.path &&
                                 a.message == b.message && a.warning == b.warning;
                        }),
            out.end());
  return out;
}

namespace {
// A YAML event handler that keeps where each document starts and ignores the rest.
class DocumentStarts : public YAML::EventHandler {
 public:
  explicit DocumentStarts(std::vector<YAML::Mark>* starts) : starts_(starts) {}
  void OnDocumentStart(const YAML::Mark& mark) override { starts_->push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}

 private:
  std::vector<YAML::Mark>* starts_;
};
}  // namespace

std::optional<YAML::Node> parse_yaml_file(const std::string& file, DiagnosticSink* sink,
                                          std::string* open_error) {
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status)) {
    *open_error = "file not found";
    return std::nullopt;
  }
  if (std::filesystem::is_directory(status)) {
    *open_error = "is a directory";
    return std::nullopt;
  }
  std::ifstream stream(file, std::ios::binary);
  std::ostringstream text;
  text << stream.rdbuf();
  if (!stream || stream.bad()) {
    *open_error = "cannot be read";
    return std::nullopt;
  }

  sink->add_file(file);
  // Documents are counted by a parser stopped at the second, and the first is loaded alone: yaml-cpp
  // 0.7's LoadAll never returns on some malformed input (after a stray flow end such as " ]}", it reports
  // one more empty document forever, each one allocated: gigabytes in seconds), found by the scenario
  // fuzzer (tests/fuzz/scenario_fuzz.cc).
  std::vector<YAML::Mark> document_starts;
  YAML::Node document;
  try {
    std::istringstream counted(text.str());
    YAML::Parser parser(counted);
    DocumentStarts starts(&document_starts);
    while (document_starts.size() < 2 && parser.HandleNextDocument(starts)) {
    }
    if (document_starts.size() == 1) document = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    sink->report(file, e.mark, "yaml", e.msg);
    return std::nullopt;
  }
  if (document_starts.empty()) return YAML::Node();  // empty, or only comments
  if (document_starts.size() > 1) {
    sink->report(file, document_starts[1], "yaml", "expected a single document (found more than one)");
    return std::nullopt;
  }
  return document;
}

// ---------------------------------------------------------------------------------------------------

bool Range::contains(double x) const {
  if (!std::isfinite(x)) return false;
  const bool above = min_inclusive ? x >= min : x > min;
  const bool below = max_inclusive ? x <= max : x < max;
  return above && below;
}

std::string Range::describe(bool compact) const {
  const auto number = compact ? format_compact : format_number;
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max) {
    return std::string("in ") + (min_inclusive ? "[" : "(") + number(min) + ", " + number(max) +
           (max_inclusive ? "]" : ")");
  }
  if (has_min) return (min_inclusive ? ">= " : "> ") + number(min);
  if (has_max) return (max_inclusive ? "<= " : "< ") + number(max);
  return "finite";
}

std::string format_number(double x) {
  char buffer[64];
  // Integers print in full ("100000", not the shorter "1e+05") up to where doubles stop being exact.
  const bool integral = std::isfinite(x) && x == std::trunc(x) && std::abs(x) < 1e15;
  const auto result = integral ? std::to_chars(buffer, buffer + sizeof(buffer), static_cast<long long>(x))
                               : std::to_chars(buffer, buffer + sizeof(buffer), x);
  return std::string(buffer, result.ptr);
}

std::string format_compact(double x) {
  if (std::abs(x) < 1e6) return format_number(x);
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), x);
  return std::string(buffer, result.ptr);
}

std::string format_approximate(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", x);
  return buffer;
}

std::optional<std::string> closest_match(const std::string& word,
                                         const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(word, candidate);
    const std::size_t threshold = std::max<std::size_t>(1, candidate.size() / 3);
    if (distance <= threshold && distance < best_distance) {
      best = candidate;
      best_distance = distance;
    }
  }
  return best;
}

bool is_key_name(const std::string& key) {
  if (key.empty() || key.size() > 64 || std::isdigit(static_cast<unsigned char>(key[0]))) return false;
  return std::all_of(key.begin(), key.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; });
}

std::string child_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

// ---------------------------------------------------------------------------------------------------

Value::Value(YAML::Node node, std::shared_ptr<const Source> source, std::string path, YAML::Mark mark)
    : node_(std::move(node)), source_(std::move(source)), path_(std::move(path)), mark_(mark) {}

Value Value::root(YAML::Node node, std::shared_ptr<const Source> source) {
  // An empty document has no mark; point at the start of the file.
  YAML::Mark mark = node.IsDefined() && !node.IsNull() ? node.Mark() : YAML::Mark();
  return Value(std::move(node), std::move(source), "", mark);
}

void Value::error(const std::string& message) const {
  source_->sink->report(source_->file, mark_, path_, message);
}

void Value::warn(const std::string& message) const {
  source_->sink->report(source_->file, mark_, path_, message, /*warning=*/true);
}

std::string Value::describe() const {
  switch (node_.Type()) {
    case YAML::NodeType::Scalar:
      if (path_.empty()) return "a document that is plain text, not keys and values";
      // yaml-cpp tags plain scalars "?"; quoted ones ("5") are strings even when they look like numbers.
      return node_.Tag() == "?" ? quoted(node_.Scalar()) : "the string \"" + node_.Scalar() + "\"";
    case YAML::NodeType::Sequence:
      return "a list of " + std::to_string(node_.size());
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      break;
  }
  return path_.empty() ? "an empty document" : "null";
}

namespace {
// Whether `path` is `root` or lies below it (both absolute and normal: compared component by component, so
// that /data/assets2 is not inside /data/assets).
bool lies_within(const std::filesystem::path& path, const std::filesystem::path& root) {
  auto p = path.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++p) {
    if (p == path.end() || *p != *r) return false;
  }
  return true;
}
}  // namespace

bool Value::file_path(const std::string& written, std::string* path) const {
  const std::filesystem::path directory =
      source_->directory.empty() ? std::filesystem::path(file()).parent_path() : source_->directory;
  const std::filesystem::path joined = directory / written;
  *path = joined.string();
  const std::string refusal = file_refusal(joined, written);
  if (!refusal.empty()) error(refusal);
  return refusal.empty();
}

std::string Value::file_refusal(const std::filesystem::path& path, const std::string& written) const {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path real = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (source_->roots) {
    bool inside = false;
    for (const fs::path& root : *source_->roots) inside |= !ec && lies_within(real, root);
    if (!inside) {
      std::string roots;
      for (const fs::path& root : *source_->roots) roots += (roots.empty() ? "" : ", ") + root.string();
      return quoted(written) + " lies outside the directories a scenario may name files in (" + roots +
             "; symlinks resolved); hadald --asset-root DIR or $HADAL_ASSET_ROOTS adds one";
    }
  }
  if (fs::exists(real, ec) && !fs::is_regular_file(real, ec)) return quoted(written) + " is not a regular file";
  return "";
}

void Value::report_in(const std::string& file, int line, int column, std::string path, std::string message,
                      bool warning) const {
  YAML::Mark mark = YAML::Mark::null_mark();
  if (line > 0) {
    mark.line = line - 1;
    mark.column = std::max(column - 1, 0);
  }
  source_->sink->report(file, mark, std::move(path), std::move(message), warning);
}

Value Value::in_same_file(YAML::Node node, std::string path, YAML::Mark mark) const {
  return Value(std::move(node), source_, std::move(path), mark);
}

void Value::error_at(const YAML::Mark& mark, const std::string& path, const std::string& message) const {
  source_->sink->report(source_->file, mark, path, message);
}

Value Value::element(std::size_t index) const {
  const YAML::Node item = node_[index];
  // An empty item ("- " alone) has no useful mark of its own.
  const YAML::Mark mark = item.IsNull() && item.Mark().line < 0 ? mark_ : item.Mark();
  return Value(item, source_, path_ + "[" + std::to_string(index) + "]", mark);
}

std::optional<double> Value::number(const Range& range) const {
  const bool plain = node_.IsScalar() && node_.Tag() == "?";
  const std::optional<double> x = plain ? parse_core_number(node_.Scalar()) : std::nullopt;
  if (!x) {
    error("expected a number (got " + describe() + ")");
    return std::nullopt;
  }
  if (!std::isfinite(*x)) {
    error("must be a finite number (got " + node_.Scalar() + ")");
    return std::nullopt;
  }
  if (!range.contains(*x)) {
    error("must be " + range.describe() + " (got " + node_.Scalar() + ")");
    return std::nullopt;
  }
  return x;
}

std::optional<std::uint64_t> Value::non_negative_integer() const {
  const bool plain = node_.IsScalar() && node_.Tag() == "?";
  const std::string text = plain ? node_.Scalar() : std::string();
  const std::size_t start = !text.empty() && text[0] == '+' ? 1 : 0;
  const bool digits_only = text.size() > start && std::all_of(text.begin() + start, text.end(), [](char c) {
                             return std::isdigit(static_cast<unsigned char>(c)) != 0;
                           });
  if (!digits_only) {
    error("expected a non-negative integer (got " + describe() + ")");
    return std::nullopt;
  }
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data() + start, text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) {
    error("must be <= " + std::to_string(std::numeric_limits<std::uint64_t>::max()) + " (got " + text + ")");
    return std::nullopt;
  }
  return value;
}

std::optional<std::string> Value::string() const {
  if (!node_.IsScalar()) {
    error("expected a string (got " + describe() + ")");
    return std::nullopt;
  }
  if (node_.Scalar().empty()) {
    error("must not be empty");
    return std::nullopt;
  }
  return node_.Scalar();
}

std::optional<bool> Value::boolean() const {
  const bool plain = node_.IsScalar() && node_.Tag() == "?";
  const std::string text = plain ? node_.Scalar() : std::string();
  if (text == "true" || text == "True" || text == "TRUE") return true;
  if (text == "false" || text == "False" || text == "FALSE") return false;
  error("expected true or false (got " + describe() + ")");
  return std::nullopt;
}

std::optional<std::vector<Value>> Value::list() const {
  if (!node_.IsSequence()) {
    error("expected a list (got " + describe() + ")");
    return std::nullopt;
  }
  std::vector<Value> items;
  for (std::size_t i = 0; i < node_.size(); ++i) items.push_back(element(i));
  return items;
}

std::optional<std::vector<double>> Value::numbers(std::optional<std::size_t> count, const Range& each) const {
  const std::string expected =
      count ? "a list of " + std::to_string(*count) + " numbers" : std::string("a list of numbers");
  if (!node_.IsSequence() || (count && node_.size() != *count)) {
    error("expected " + expected + " (got " + describe() + ")");
    return std::nullopt;
  }
  std::vector<double> values;
  bool ok = true;
  for (std::size_t i = 0; i < node_.size(); ++i) {
    const std::optional<double> x = element(i).number(each);
    ok = ok && x.has_value();
    values.push_back(x.value_or(0.0));
  }
  if (!ok) return std::nullopt;
  return values;
}

std::optional<Eigen::Vector3d> Value::vector3(const Range& each) const {
  const auto values = numbers(3, each);
  if (!values) return std::nullopt;
  return Eigen::Vector3d((*values)[0], (*values)[1], (*values)[2]);
}

void Value::report_bad_choice(const std::vector<std::string>& names) const {
  std::vector<std::string> quoted_names;
  for (const auto& name : names) quoted_names.push_back(quoted(name));
  const std::string allowed = names.size() == 1 ? quoted_names.front() : "one of " + join_names(quoted_names);
  error("must be " + allowed + " (got " + describe() + ")");
}

// ---------------------------------------------------------------------------------------------------

MapReader::MapReader(Value value, std::vector<std::string> allowed)
    : value_(std::move(value)), allowed_(std::move(allowed)) {
  const YAML::Node& node = value_.node();
  if (!node.IsMap()) {
    value_.error("expected a map (got " + value_.describe() + ")");
    return;
  }
  ok_ = true;
  for (auto it = node.begin(); it != node.end(); ++it) {
    const YAML::Node key_node = it->first;
    if (!key_node.IsScalar()) {
      value_.error_at(
          key_node.Mark(), value_.path(),
          "keys must be strings (got " + value_.in_same_file(key_node, "", key_node.Mark()).describe() + ")");
      continue;
    }
    const std::string& key = key_node.Scalar();
    const std::string path = child_path(value_.path(), key);
    // A key that is no name (a line of a file that is not YAML, such as /etc/shadow's, can read as one) is
    // neither quoted nor put in the path: an error must not print another file's contents.
    const bool name = is_key_name(key);
    if (const Entry* first = find(key)) {
      value_.error_at(key_node.Mark(), name ? path : value_.path(),
                      "duplicate key " + (name ? quoted(key) + " " : "") + "(first defined at line " +
                          std::to_string(one_based(first->key_node.Mark().line)) + ")");
      continue;
    }
    if (!name) {
      value_.error_at(key_node.Mark(), value_.path(), "unknown key that is not a name (its text is not shown)");
      continue;
    }
    if (std::find(allowed_.begin(), allowed_.end(), key) == allowed_.end()) {
      std::string message = "unknown key " + quoted(key);
      if (const auto suggestion = closest_match(key, allowed_)) {
        message += "; did you mean " + quoted(*suggestion) + "?";
      }
      value_.error_at(key_node.Mark(), path, message);
      continue;
    }
    // An empty value ("key:" then a newline) is a null whose mark is the next token; point at the key.
    const YAML::Node value_node = it->second;
    const bool empty_value = value_node.IsNull() && value_node.Mark().line != key_node.Mark().line;
    entries_.push_back(
        {key, key_node,
         value_.in_same_file(value_node, path, empty_value ? key_node.Mark() : value_node.Mark())});
  }
  apply_overrides();
}

void MapReader::apply_overrides() {
  const std::vector<Override>* overrides = value_.overrides();
  if (overrides == nullptr) return;
  const std::string prefix = value_.path().empty() ? "" : value_.path() + ".";
  for (const Override& o : *overrides) {
    if (o.path.size() <= prefix.size() || o.path.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = o.path.substr(prefix.size());
    const std::size_t cut = rest.find_first_of(".[");
    const std::string key = rest.substr(0, cut);
    const std::string path = child_path(value_.path(), key);
    if (!allows(key)) {
      std::string message = "unknown key " + quoted(key);
      if (const auto suggestion = closest_match(key, allowed_)) message += "; did you mean " + quoted(*suggestion) + "?";
      YAML::Mark at_key = o.value.mark();
      for (const auto& [key_path, column] : o.key_columns) {
        if (key_path == path) {
          at_key.line = 0;
          at_key.column = column;
        }
      }
      o.value.error_at(at_key, path, message);
      continue;
    }
    Entry* entry = nullptr;
    for (Entry& e : entries_) {
      if (e.key == key) entry = &e;
    }
    if (cut == std::string::npos) {
      // The override's value itself, in place of the file's.
      Value value(o.value.node(), o.value.source(), path, o.value.mark());
      if (entry != nullptr) {
        entry->value = std::move(value);
        entry->overridden = true;
      } else {
        entries_.push_back({key, YAML::Node(), std::move(value), true});
      }
    } else if (entry == nullptr) {
      // A map the file lacks on the way to a deeper key: an empty one, as if written there, that the
      // override then fills (its own errors at the override).
      entries_.push_back({key, YAML::Node(), Value(YAML::Node(YAML::NodeType::Map), o.value.source(), path, o.value.mark()),
                          true});
    }
  }
}

const MapReader::Entry* MapReader::find(const std::string& key) const {
  for (const Entry& entry : entries_) {
    if (entry.key == key) return &entry;
  }
  return nullptr;
}

void MapReader::check_allowed(const std::string& key) const {
  // A key read but not declared would never be accepted from a file: a programming error.
  if (std::find(allowed_.begin(), allowed_.end(), key) == allowed_.end()) {
    throw std::logic_error("MapReader: key '" + key + "' read but not declared at " + value_.path());
  }
}

bool MapReader::allows(const std::string& key) const {
  return std::find(allowed_.begin(), allowed_.end(), key) != allowed_.end();
}

bool MapReader::has(const std::string& key) const {
  check_allowed(key);
  return find(key) != nullptr;
}

std::optional<Value> MapReader::optional(const std::string& key) const {
  check_allowed(key);
  if (const Entry* entry = find(key)) return entry->value;
  return std::nullopt;
}

std::optional<Value> MapReader::required(const std::string& key, const std::string& why) const {
  std::optional<Value> value = optional(key);
  if (!value && ok_) {
    value_.error("missing required key " + quoted(key) + (why.empty() ? "" : " (" + why + ")"));
  }
  return value;
}

std::optional<Value> MapReader::get(const std::string& key, Need need) const {
  return need == Need::kRequired ? required(key) : optional(key);
}

void MapReader::error_at_key(const std::string& key, const std::string& message) const {
  check_allowed(key);
  if (const Entry* entry = find(key)) {
    if (entry->overridden) {
      entry->value.error(message);
    } else {
      value_.error_at(entry->key_node.Mark(), entry->value.path(), message);
    }
  } else {
    value_.error(key + ": " + message);  // an absent key's check: at the map, never silent
  }
}

bool MapReader::read_number(const std::string& key, Need need, const Range& range, double* out) const {
  const std::optional<Value> value = get(key, need);
  if (!value) return need == Need::kOptional;
  const std::optional<double> x = value->number(range);
  if (x) *out = *x;
  return x.has_value();
}

bool MapReader::read_whole_number(const std::string& key, Need need, const Range& range, int* out) const {
  const std::optional<Value> value = get(key, need);
  if (!value) return need == Need::kOptional;
  const std::optional<double> x = value->number(range);
  if (!x) return false;
  if (*x != std::floor(*x)) {
    value->error("must be a whole number (got " + format_number(*x) + ")");
    return false;
  }
  *out = static_cast<int>(*x);
  return true;
}

bool MapReader::read_vector3(const std::string& key, Need need, const Range& each,
                             Eigen::Vector3d* out) const {
  const std::optional<Value> value = get(key, need);
  if (!value) return need == Need::kOptional;
  const std::optional<Eigen::Vector3d> v = value->vector3(each);
  if (v) *out = *v;
  return v.has_value();
}

bool MapReader::read_direction(const std::string& key, Need need, Eigen::Vector3d* out) const {
  const std::optional<Value> value = get(key, need);
  if (!value) return need == Need::kOptional;
  const std::optional<Eigen::Vector3d> v = value->vector3();
  if (!v) return false;
  if (v->norm() < 1e-9) {
    value->error("must be non-zero (got [" + format_number(v->x()) + ", " + format_number(v->y()) + ", " +
                 format_number(v->z()) + "])");
    return false;
  }
  *out = v->normalized();
  return true;
}

bool MapReader::read_string(const std::string& key, Need need, std::string* out) const {
  const std::optional<Value> value = get(key, need);
  if (!value) return need == Need::kOptional;
  const std::optional<std::string> text = value->string();
  if (text) *out = *text;
  return text.has_value();
}

bool MapReader::read_bool(const std::string& key, Need need, bool* out) const {
  const std::optional<Value> value = get(key, need);
  if (!value) return need == Need::kOptional;
  const std::optional<bool> flag = value->boolean();
  if (flag) *out = *flag;
  return flag.has_value();
}

}  // namespace hadal::config
