// What a scenario key is, written once (docs/ARCHITECTURE.md, "Keys: one declaration each"): the
// type-erased description that a KeyTable (config/key_table.h) keeps beside its readers, and from which
// the reference tables of configs/REFERENCE.md (reference_tables()) and the JSON Schema of the scenario
// format (config/scenario_schema.h) are made. Nothing here reads YAML.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace hadal::config {

// An interval of accepted numbers. Every Range also requires the number to be finite.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  bool max_inclusive = true;

  static Range finite() { return {}; }
  static Range positive() { return {0.0, kInfinity, false, true}; }               // > 0
  static Range non_negative() { return {0.0, kInfinity, true, true}; }            // >= 0
  static Range closed(double lo, double hi) { return {lo, hi, true, true}; }      // [lo, hi]
  static Range left_open(double lo, double hi) { return {lo, hi, false, true}; }  // (lo, hi]
  static Range right_open(double lo, double hi) { return {lo, hi, true, false}; }  // [lo, hi)
  static Range open(double lo, double hi) { return {lo, hi, false, false}; }      // (lo, hi)

  bool contains(double x) const;
  // "> 0", ">= 0", "<= 5", "in [50, 100000]", "in (0, 2000]", or "finite"; compact: numbers of a million
  // and more as "1e+07".
  std::string describe(bool compact = false) const;

  static constexpr double kInfinity = std::numeric_limits<double>::infinity();
};

// Shortest text that reads back as `x` ("500", "100000", "0.1", "1e-07"): for values from the file.
std::string format_number(double x);
// format_number, but a million and more in the shortest form ("2.2e+09"): for tables people read.
std::string format_compact(double x);
// Six significant digits ("-1", "6.445"): for computed values, whose last bits are rounding noise.
std::string format_approximate(double x);

enum class KeyType {
  kNumber,    // a finite number in `range` (whole: an integer)
  kUnsigned,  // an integer 0 .. 2^64-1 (a seed)
  kBoolean,
  kString,    // a non-empty scalar
  kChoice,    // one of `choices`
  kNumbers,   // a list of `count` numbers (0: any count), each in `range`
  kPose,      // {position, rpy_deg}
  kFile,      // a path relative to the file that names it
  kMap,       // a map read by `table`
  kList,      // a list of maps, each read by `table`
  kCustom,    // its own reader; `json` is its schema, `type_text` its type
};

struct KeyChoice {
  std::string name;
  std::string doc;     // what it means, for the reference; may be empty
  std::string source;  // a preset's: where its figures come from (config/preset.h); empty otherwise
};

struct TableDoc;

struct KeyDoc {
  std::string name;
  KeyType type = KeyType::kNumber;
  std::string unit;  // as written in the YAML ("m", "deg", "Hz", "rpm"); empty: none or not a number
  std::string doc;   // one line: what it is
  Range range;       // kNumber, kNumbers: each value, in the YAML's unit
  bool whole = false;       // kNumber: must be a whole number
  std::size_t count = 0;    // kNumbers: exactly this many (0: any)
  std::size_t min_items = 0;  // kList, kNumbers with count 0: at least this many
  std::vector<KeyChoice> choices;  // kChoice
  bool required = false;
  std::string required_why;  // appended to "missing required key" in parentheses
  std::string default_text;  // for the reference: the default in the YAML's unit, "none", ...
  std::string default_choice;  // kChoice: the default's name; empty when the default depends on context
  const TableDoc* table = nullptr;  // kMap, kList
  // Values of the table's selector (a kChoice key marked as such) for which the key is used; empty: all.
  std::vector<std::string> only_for;
  // Values of the selector for which the key is required.
  std::vector<std::string> required_for;
  std::string json;       // kCustom: its JSON Schema, a JSON text
  std::string type_text;  // the reference's Type column when not derived from `type`
  std::string rule;       // what the range column adds ("<= `world.physics_rate_hz`")
  std::string unless;     // not read when this other key is given (and then not required)
  std::string optional_with;  // a required key that may be left out when this other key is given
  // The table this key comes from when another table's keys sit in this map but are read by the map's
  // owner (a vehicle entry's inline definition): the reference points there instead of repeating them.
  std::string described_in;
  std::string renamed_to;  // a former name: refused, naming this key
  bool selector = false;  // the kChoice key whose value decides which keys apply
};

// A map's keys. A table with `variants` (a sensor entry: its common keys, then those of its `type`)
// takes, besides its own keys, those of the variant its selector names.
struct TableDoc {
  std::string id;     // dotted, e.g. "world.water": the reference's marker and the JSON Schema's $defs name
  std::string title;  // one line, for the JSON Schema
  std::vector<KeyDoc> keys;
  std::string selector_phrase;  // "seabed type": "key 'x' is not used by seabed type 'plane'"
  struct Variant {
    std::string value;  // the selector's value
    const TableDoc* table = nullptr;
  };
  std::vector<Variant> variants;

  const KeyDoc* find(const std::string& name) const;
  const KeyDoc* selector() const;  // null when the table has none
};

// The reference table of one map (Markdown): Key | Type | Unit | Default | Range | Description.
std::string reference_table(const TableDoc& table);
// The reference's type of a key ("number", "3 numbers", "map", "list of maps", "pose", ...).
std::string type_text(const KeyDoc& key);
// Its range or rule ("> 0", "in [0, 1]", "`plane`, `mesh`", ...), as the reference shows it.
std::string range_text(const KeyDoc& key);

// configs/REFERENCE.md with its key tables made anew: each table sits between `<!-- keys: ID -->` and
// `<!-- end keys -->` (ID a table's id), and the prose around them is kept. `missing` lists the tables
// of `tables` no marker places, `unknown` the markers that name no table.
struct ReferenceUpdate {
  std::string text;
  std::vector<std::string> missing;
  std::vector<std::string> unknown;
};
ReferenceUpdate update_reference(const std::string& markdown, const std::vector<const TableDoc*>& tables);

// Every table reachable from `root` (nested maps and lists, variants), each once, depth first.
std::vector<const TableDoc*> all_tables(const TableDoc& root);

}  // namespace hadal::config
