// hadal-schema: what the scenario format's key tables (config/key_table.h) make, for the repository's
// generated files (docs/ARCHITECTURE.md, "Keys: one declaration each").
//
//   hadal-schema json scenario|vehicle|object [--check FILE]   the JSON Schema (as hadald --schema); with --check,
//                                                        exit 1 when FILE is not exactly it
//   hadal-schema reference FILE [--check]               make FILE's key tables anew (configs/REFERENCE.md);
//                                                        with --check, exit 1 when they are stale instead
// Exit 2 on bad arguments, 1 when a check fails or a table has no place in the reference (or a marker
// names no table).
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "hadal/config/json_schema.h"
#include "hadal/config/key_doc.h"
#include "hadal/config/key_table.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/config/vehicle_keys.h"

namespace {

constexpr const char* kUsage =
    "usage: hadal-schema json scenario|vehicle|object [--check FILE]\n"
    "       hadal-schema reference FILE [--check]\n";

bool read_file(const std::string& path, std::string* text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream out;
  out << in.rdbuf();
  *text = out.str();
  return true;
}

int json(const std::vector<std::string>& args) {
  const std::optional<std::string> schema = args.size() >= 2 ? hadal::config::scenario_json_schema(args[1]) : std::nullopt;
  if (!schema || (args.size() != 2 && !(args.size() == 4 && args[2] == "--check"))) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  if (args.size() == 2) {
    std::fputs(schema->c_str(), stdout);
    return 0;
  }
  std::string committed;
  if (!read_file(args[3], &committed)) {
    std::fprintf(stderr, "hadal-schema: cannot read %s\n", args[3].c_str());
    return 1;
  }
  if (committed != *schema) {
    std::fprintf(stderr,
                 "hadal-schema: %s is stale: the key tables changed; write it anew with\n"
                 "  build/bin/hadal-schema json %s > %s\n",
                 args[3].c_str(), args[1].c_str(), args[3].c_str());
    return 1;
  }
  return 0;
}

int reference(const std::vector<std::string>& args) {
  const bool check = args.size() == 3 && args[2] == "--check";
  if (args.size() != 2 && !check) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  const std::string& path = args[1];
  std::string text;
  if (!read_file(path, &text)) {
    std::fprintf(stderr, "hadal-schema: cannot read %s\n", path.c_str());
    return 1;
  }
  // Every table of a scenario, and the vehicle and object definitions' (an entry describes its keys there).
  std::vector<const hadal::config::TableDoc*> tables = hadal::config::all_tables(hadal::config::scenario_keys().doc());
  for (const auto* root : {&hadal::config::definition_keys().doc(), &hadal::config::object_definition_keys().doc()}) {
    for (const hadal::config::TableDoc* table : hadal::config::all_tables(*root)) {
      if (std::find(tables.begin(), tables.end(), table) == tables.end()) tables.push_back(table);
    }
  }
  const hadal::config::ReferenceUpdate update = hadal::config::update_reference(text, tables);
  int status = 0;
  for (const std::string& id : update.missing) {
    std::fprintf(stderr, "hadal-schema: %s: no place for the keys of `%s` (add <!-- keys: %s --><!-- end keys -->)\n",
                 path.c_str(), id.c_str(), id.c_str());
    status = 1;
  }
  for (const std::string& id : update.unknown) {
    std::fprintf(stderr, "hadal-schema: %s: the marker `%s` names no key table\n", path.c_str(), id.c_str());
    status = 1;
  }
  if (check) {
    if (update.text != text) {
      std::fprintf(stderr,
                   "hadal-schema: %s: its key tables are stale: the key declarations changed; write them anew with\n"
                   "  build/bin/hadal-schema reference %s\n",
                   path.c_str(), path.c_str());
      status = 1;
    }
    return status;
  }
  std::ofstream(path, std::ios::binary) << update.text;
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help") {
    std::fputs(kUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "json") return json(args);
  if (args[0] == "reference") return reference(args);
  std::fputs(kUsage, stderr);
  return 2;
}
