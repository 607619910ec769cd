#include "hadal/config/key_doc.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "hadal/config/key_table.h"

namespace hadal::config {

const KeyDoc* TableDoc::find(const std::string& name) const {
  for (const KeyDoc& key : keys) {
    if (key.name == name) return &key;
  }
  return nullptr;
}

const KeyDoc* TableDoc::selector() const {
  for (const KeyDoc& key : keys) {
    if (key.selector) return &key;
  }
  return nullptr;
}

bool KeyReads::ok(const std::string& key) const {
  return std::find(failed_.begin(), failed_.end(), key) == failed_.end();
}

Eigen::Matrix3d rotation_from_rpy(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

bool read_pose(const Value& value, Eigen::Isometry3d* X) {
  const MapReader map(value, {"position", "rpy_deg"});
  if (!map.ok()) return false;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();
  const bool ok = map.read_vector3("position", Need::kOptional, Range::finite(), &position) &
                  map.read_vector3("rpy_deg", Need::kOptional, Range::finite(), &rpy_deg);
  if (!ok) return false;
  if (const std::optional<Value> angles = map.optional("rpy_deg")) {
    key_detail::warn_if_radians(*angles, rpy_deg.data(), 3);
  }
  X->setIdentity();
  X->linear() = rotation_from_rpy(rpy_deg * kDegToRad);
  X->translation() = position;
  return true;
}

namespace key_detail {

void warn_if_radians(const Value& value, const double* degrees, std::size_t count) {
  constexpr double kTwoPi = 2.0 * kPi;
  const double* radian_like = nullptr;
  long twelfths = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double x = degrees[i];
    if (x == 0.0) continue;
    if (!(std::abs(x) <= kTwoPi + 1e-9)) return;  // a degree-sized angle: degrees it is
    const long k = std::lround(x / (kPi / 12.0));
    if (radian_like == nullptr && k != 0 && std::abs(x - k * kPi / 12.0) <= 0.002 && x != std::floor(x)) {
      radian_like = &degrees[i];
      twelfths = k;
    }
  }
  if (radian_like == nullptr) return;
  value.warn(format_number(*radian_like) + " is " + format_number(15.0 * static_cast<double>(twelfths)) +
             " deg in radians, but this key is in degrees: did you mean " +
             format_number(15.0 * static_cast<double>(twelfths)) + "?");
}

std::string format_default(double si, double (*from_si)(double), bool approximate) {
  const double x = from_si ? from_si(si) : si;
  if (!std::isfinite(x)) return "none";
  return approximate ? format_approximate(x) : format_compact(x);
}

std::string format_numbers(const double* values, std::size_t count) {
  std::string out = "[";
  for (std::size_t i = 0; i < count; ++i) out += (i > 0 ? ", " : "") + format_approximate(values[i]);
  return out + "]";
}

}  // namespace key_detail

namespace {

std::string backticked(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i > 0 ? ", `" : "`") + names[i] + "`";
  return out;
}

// A table cell: '|' would end it, a newline would end the row.
std::string cell(std::string text) {
  std::string out;
  for (char c : text) {
    if (c == '|') {
      out += "\\|";
    } else if (c == '\n') {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out.empty() ? "–" : out;
}

}  // namespace

std::string range_only(const KeyDoc& key);

std::string type_text(const KeyDoc& key) {
  if (!key.type_text.empty()) return key.type_text;
  switch (key.type) {
    case KeyType::kNumber: return key.whole ? "integer" : "number";
    case KeyType::kUnsigned: return "integer";
    case KeyType::kBoolean: return "boolean";
    case KeyType::kString: return "string";
    case KeyType::kChoice: return "string";
    case KeyType::kNumbers: return key.count == 0 ? "list of numbers" : std::to_string(key.count) + " numbers";
    case KeyType::kPose: return "pose";
    case KeyType::kFile: return "file";
    case KeyType::kMap: return "map";
    case KeyType::kList: return "list of maps";
    case KeyType::kCustom: return "–";
  }
  return "–";
}

std::string range_text(const KeyDoc& key) {
  const std::string text = range_only(key);
  if (key.rule.empty()) return text;
  return text.empty() ? key.rule : text + "; " + key.rule;
}

std::string range_only(const KeyDoc& key) {
  const std::string range = key.range.describe(true);
  switch (key.type) {
    case KeyType::kNumber:
      return key.whole ? (range == "finite" ? "whole number" : "whole number " + range) : range;
    case KeyType::kUnsigned: return "0 … 2^64−1";
    case KeyType::kBoolean: return "`true`, `false`";
    case KeyType::kString: return "non-empty";
    case KeyType::kChoice: {
      std::string out;
      for (std::size_t i = 0; i < key.choices.size(); ++i) {
        out += (i > 0 ? ", `" : "`") + key.choices[i].name + "`";
        // A preset's product and source go in the table of presets below the keys.
        if (!key.choices[i].doc.empty() && key.choices[i].source.empty()) out += " (" + key.choices[i].doc + ")";
      }
      return out;
    }
    case KeyType::kNumbers: {
      std::string out = range == "finite" ? "finite" : "each " + range;
      if (key.count == 0 && key.min_items > 0) out += "; at least " + std::to_string(key.min_items);
      return out;
    }
    case KeyType::kPose: return "`{position, rpy_deg}`";
    case KeyType::kFile: return "relative to this file";
    case KeyType::kMap: return "";
    case KeyType::kList:
      return key.min_items > 0 ? "at least " + std::to_string(key.min_items) + (key.min_items == 1 ? " entry" : " entries")
                               : "";
    case KeyType::kCustom: return "";
  }
  return "";
}

std::string reference_table(const TableDoc& table) {
  std::string out = "| Key | Type | Unit | Default | Range | Description |\n|---|---|---|---|---|---|\n";
  const KeyDoc* selector = table.selector();
  std::vector<std::string> described_in, renamed;
  for (const KeyDoc& key : table.keys) {
    if (!key.renamed_to.empty()) {
      renamed.push_back("`" + key.name + "` (now `" + key.renamed_to + "`)");
      continue;
    }
    if (!key.described_in.empty()) {
      if (std::find(described_in.begin(), described_in.end(), key.described_in) == described_in.end()) {
        described_in.push_back(key.described_in);
      }
      continue;
    }
    std::string description;
    if (!key.only_for.empty() && selector != nullptr) description = backticked(key.only_for) + " only: ";
    description += key.doc;
    if ((key.type == KeyType::kMap || key.type == KeyType::kList) && key.table != nullptr) {
      description += (key.doc.empty() ? "keys: `" : " (keys: `") + key.table->id + (key.doc.empty() ? "`" : "`)");
    }
    if (!key.unless.empty()) description += "; not with `" + key.unless + "`";
    if (!key.optional_with.empty()) description += "; may be left out with `" + key.optional_with + "`";
    out += "| `" + key.name + "` | " + cell(type_text(key)) + " | " + cell(key.unit) + " | " + cell(key.default_text) +
           " | " + cell(range_text(key)) + " | " + cell(description) + " |\n";
  }
  for (const KeyDoc& key : table.keys) {
    if (key.type != KeyType::kChoice || key.choices.empty() || key.choices.front().source.empty()) continue;
    out += "\n| `" + key.name + ":` | Product | Source |\n|---|---|---|\n";
    for (const KeyChoice& choice : key.choices) {
      out += "| `" + choice.name + "` | " + cell(choice.doc) + " | " + cell(choice.source) + " |\n";
    }
  }
  for (const std::string& id : described_in) out += "\nBesides these, the keys of `" + id + "`.\n";
  if (!renamed.empty()) {
    std::string names;
    for (std::size_t i = 0; i < renamed.size(); ++i) names += (i > 0 ? ", " : "") + renamed[i];
    out += "\nRenamed, and refused under the old name: " + names + ".\n";
  }
  return out;
}

std::vector<const TableDoc*> all_tables(const TableDoc& root) {
  std::vector<const TableDoc*> out;
  std::set<const TableDoc*> seen;
  // Depth first, children in declaration order.
  const auto visit = [&](const TableDoc* table, const auto& self) -> void {
    if (!seen.insert(table).second) return;
    out.push_back(table);
    for (const KeyDoc& key : table->keys) {
      if (key.table != nullptr) self(key.table, self);
    }
    for (const TableDoc::Variant& variant : table->variants) self(variant.table, self);
  };
  visit(&root, visit);
  return out;
}

ReferenceUpdate update_reference(const std::string& markdown, const std::vector<const TableDoc*>& tables) {
  static const std::string kOpen = "<!-- keys: ", kClose = " -->", kEnd = "<!-- end keys -->";
  ReferenceUpdate update;
  std::set<std::string> placed;
  std::size_t at = 0;
  while (true) {
    const std::size_t open = markdown.find(kOpen, at);
    if (open == std::string::npos) break;
    const std::size_t id_start = open + kOpen.size();
    const std::size_t close = markdown.find(kClose, id_start);
    const std::size_t end = close == std::string::npos ? std::string::npos : markdown.find(kEnd, close);
    if (end == std::string::npos) {
      update.unknown.push_back(markdown.substr(open, 40) + "... (no closing marker)");
      break;
    }
    const std::string id = markdown.substr(id_start, close - id_start);
    update.text += markdown.substr(at, close + kClose.size() - at) + "\n";
    const auto table = std::find_if(tables.begin(), tables.end(), [&](const TableDoc* t) { return t->id == id; });
    if (table == tables.end()) {
      update.unknown.push_back(id);
    } else {
      update.text += reference_table(**table);
      placed.insert(id);
    }
    update.text += kEnd;
    at = end + kEnd.size();
  }
  update.text += markdown.substr(at);
  for (const TableDoc* table : tables) {
    if (placed.count(table->id) == 0) update.missing.push_back(table->id);
  }
  return update;
}

}  // namespace hadal::config
