#include "hadal/config/json_schema.h"

#include <nlohmann/json.hpp>

#include "hadal/config/key_table.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/config/vehicle_keys.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hadal::config {
namespace {

using Json = nlohmann::ordered_json;

// A table's definition name: its id with each list's "[]" as "_entry" ("links[].mesh" is "links_entry.mesh"),
// which a URI fragment may hold unescaped.
std::string definition_name(const std::string& id) {
  std::string name;
  for (std::size_t i = 0; i < id.size(); ++i) {
    if (id.compare(i, 2, "[]") == 0) {
      name += "_entry";
      ++i;
    } else {
      name += id[i];
    }
  }
  return name;
}

std::string definition_ref(const TableDoc& table) { return "#/definitions/" + definition_name(table.id); }

bool contains(const std::vector<std::string>& list, const std::string& value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

// JSON numbers for the bounds; whole bounds as integers ("minimum": 0, not 0.0).
Json bound(double x) {
  if (x == std::trunc(x) && std::abs(x) < 9e15) return static_cast<long long>(x);
  return x;
}

void add_range(const Range& range, Json& schema) {
  if (std::isfinite(range.min)) schema[range.min_inclusive ? "minimum" : "exclusiveMinimum"] = bound(range.min);
  if (std::isfinite(range.max)) schema[range.max_inclusive ? "maximum" : "exclusiveMaximum"] = bound(range.max);
}

std::string description(const KeyDoc& key) {
  std::string text = key.doc;
  if (!key.unit.empty()) text += (text.empty() ? "" : " ") + std::string("[") + key.unit + "]";
  if (!key.default_text.empty() && key.default_text != "none" && key.default_text != "required") {
    text += (text.empty() ? "" : " ") + std::string("Default: ") + key.default_text + ".";
  }
  return text;
}

Json key_schema(const KeyDoc& key) {
  Json schema = Json::object();
  if (!key.renamed_to.empty()) return Json{{"not", Json::object()}, {"description", key.doc}};
  switch (key.type) {
    case KeyType::kNumber:
      schema["type"] = key.whole ? "integer" : "number";
      add_range(key.range, schema);
      break;
    case KeyType::kUnsigned:
      schema["type"] = "integer";
      schema["minimum"] = 0;
      schema["maximum"] = 18446744073709551615ull;
      break;
    case KeyType::kBoolean: schema["type"] = "boolean"; break;
    case KeyType::kString:
    case KeyType::kFile:
      schema["type"] = "string";
      schema["minLength"] = 1;
      break;
    case KeyType::kChoice: {
      Json names = Json::array();
      for (const KeyChoice& choice : key.choices) names.push_back(choice.name);
      schema["enum"] = names;
      if (!key.default_choice.empty()) schema["default"] = key.default_choice;
      break;
    }
    case KeyType::kNumbers: {
      schema["type"] = "array";
      Json item = {{"type", "number"}};
      add_range(key.range, item);
      schema["items"] = item;
      if (key.count > 0) {
        schema["minItems"] = key.count;
        schema["maxItems"] = key.count;
      } else if (key.min_items > 0) {
        schema["minItems"] = key.min_items;
      }
      break;
    }
    case KeyType::kPose: schema["$ref"] = "#/definitions/pose"; break;
    case KeyType::kMap:
      if (key.table == nullptr) throw std::logic_error("json_schema: map key '" + key.name + "' has no table");
      schema["$ref"] = definition_ref(*key.table);
      break;
    case KeyType::kList:
      if (key.table == nullptr) throw std::logic_error("json_schema: list key '" + key.name + "' has no table");
      schema["type"] = "array";
      schema["items"] = {{"$ref", definition_ref(*key.table)}};
      if (key.min_items > 0) schema["minItems"] = key.min_items;
      break;
    case KeyType::kCustom:
      schema = key.json.empty() ? Json::object() : Json::parse(key.json);
      break;
  }
  const std::string text = description(key);
  if (text.empty()) return schema;
  // A $ref's siblings are ignored in draft-07: the reference goes one level down.
  if (schema.contains("$ref")) return Json{{"description", text}, {"allOf", Json::array({schema})}};
  schema["description"] = text;
  return schema;
}

// The if/then clauses of a table's selector: per value, the keys it does not use and those it needs.
void add_selector_clauses(const TableDoc& table, Json& all_of) {
  const KeyDoc* selector = table.selector();
  if (selector == nullptr) return;
  for (const KeyChoice& choice : selector->choices) {
    Json forbidden = Json::object();
    Json required = Json::array();
    for (const KeyDoc& key : table.keys) {
      if (!key.only_for.empty() && !contains(key.only_for, choice.name)) forbidden[key.name] = false;
      if (contains(key.required_for, choice.name)) required.push_back(key.name);
    }
    if (forbidden.empty() && required.empty()) continue;
    Json condition = {{"properties", {{selector->name, {{"const", choice.name}}}}}};
    // The default applies when the selector is absent.
    if (choice.name != selector->default_choice) condition["required"] = Json::array({selector->name});
    Json then = Json::object();
    if (!forbidden.empty()) then["properties"] = forbidden;
    if (!required.empty()) then["required"] = required;
    all_of.push_back({{"if", condition}, {"then", then}});
  }
}

// properties, required and allOf of a table's own keys.
void add_keys(const TableDoc& table, Json& schema) {
  Json properties = Json::object();
  Json required = Json::array();
  Json all_of = Json::array();
  for (const KeyDoc& key : table.keys) {
    properties[key.name] = key_schema(key);
    // Required, or (optional_with) this key or the other one.
    const Json required_clause =
        key.optional_with.empty()
            ? Json{{"required", Json::array({key.name})}}
            : Json{{"anyOf", Json::array({Json{{"required", Json::array({key.name})}},
                                          Json{{"required", Json::array({key.optional_with})}}})}};
    if (key.unless.empty()) {
      if (key.required && key.optional_with.empty()) required.push_back(key.name);
      if (key.required && !key.optional_with.empty()) all_of.push_back(required_clause);
      continue;
    }
    // Not with `unless`; required without it when required at all.
    Json clause = {{"if", {{"required", Json::array({key.unless})}}},
                   {"then", {{"properties", {{key.name, false}}}}}};
    if (key.required) clause["else"] = required_clause;
    all_of.push_back(clause);
  }
  schema["properties"] = properties;
  if (!required.empty()) schema["required"] = required;
  add_selector_clauses(table, all_of);
  if (!all_of.empty()) schema["allOf"] = all_of;
}

Json table_schema(const TableDoc& table) {
  Json schema = {{"type", "object"}};
  if (!table.title.empty()) schema["description"] = table.title;
  add_keys(table, schema);
  schema["additionalProperties"] = false;
  if (table.variants.empty()) return schema;

  // Variants: every variant's keys are allowed names; which of them apply is decided per selector value.
  const KeyDoc* selector = table.selector();
  if (selector == nullptr) throw std::logic_error("json_schema: table '" + table.id + "' has variants, no selector");
  Json& properties = schema["properties"];
  std::vector<std::string> own;
  for (const KeyDoc& key : table.keys) own.push_back(key.name);
  std::vector<std::string> variant_keys;
  for (const TableDoc::Variant& variant : table.variants) {
    for (const KeyDoc& key : variant.table->keys) {
      if (!contains(own, key.name) && !contains(variant_keys, key.name)) variant_keys.push_back(key.name);
    }
  }
  for (const std::string& name : variant_keys) properties[name] = Json::object();
  Json& all_of = schema.contains("allOf") ? schema["allOf"] : (schema["allOf"] = Json::array());
  for (const TableDoc::Variant& variant : table.variants) {
    Json then = Json::object();
    add_keys(*variant.table, then);
    for (const std::string& name : variant_keys) {
      if (variant.table->find(name) == nullptr) then["properties"][name] = false;
    }
    Json condition = {{"properties", {{selector->name, {{"const", variant.value}}}}},
                      {"required", Json::array({selector->name})}};
    all_of.push_back({{"if", condition}, {"then", then}});
  }
  return schema;
}

}  // namespace

std::string json_schema(const TableDoc& root, const std::string& title) {
  Json document = {{"$schema", "http://json-schema.org/draft-07/schema#"}, {"title", title}};
  document["allOf"] = Json::array({{{"$ref", definition_ref(root)}}});
  Json definitions = Json::object();
  definitions["pose"] = {
      {"type", "object"},
      {"description", "A pose: position [m] and roll, pitch, yaw [deg] (R = Rz(yaw) Ry(pitch) Rx(roll))."},
      {"properties",
       {{"position", {{"type", "array"}, {"items", {{"type", "number"}}}, {"minItems", 3}, {"maxItems", 3}}},
        {"rpy_deg", {{"type", "array"}, {"items", {{"type", "number"}}}, {"minItems", 3}, {"maxItems", 3}}}}},
      {"additionalProperties", false}};
  for (const TableDoc* table : all_tables(root)) definitions[definition_name(table->id)] = table_schema(*table);
  document["definitions"] = definitions;
  return document.dump(2) + "\n";
}

std::optional<std::string> scenario_json_schema(const std::string& which) {
  if (which == "scenario") return json_schema(scenario_keys().doc(), "Hadal scenario (configs/scenarios/*.yaml)");
  if (which == "vehicle") return json_schema(definition_keys().doc(), "Hadal vehicle file (configs/vehicles/*.yaml)");
  if (which == "object") {
    return json_schema(object_definition_keys().doc(), "Hadal object file (configs/objects/*.yaml)");
  }
  return std::nullopt;
}

}  // namespace hadal::config
