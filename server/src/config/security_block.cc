#include "hadal/config/security_block.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace hadal::config {

std::optional<SecurityFiles> read_security_block(const Value& block) {
  const std::pair<const char*, std::string SecurityFiles::*> keys[] = {
      {"identity_ca", &SecurityFiles::identity_ca},       {"certificate", &SecurityFiles::certificate},
      {"private_key", &SecurityFiles::private_key},       {"permissions_ca", &SecurityFiles::permissions_ca},
      {"governance", &SecurityFiles::governance},         {"permissions", &SecurityFiles::permissions}};
  std::vector<std::string> allowed;
  for (const auto& [key, member] : keys) allowed.emplace_back(key);
  const MapReader map(block, allowed);
  if (!map.ok()) return std::nullopt;
  SecurityFiles files;
  bool ok = true;
  for (const auto& [key, member] : keys) {
    std::string written;
    if (!map.read_string(key, Need::kRequired, &written)) {
      ok = false;
      continue;
    }
    const Value value = *map.optional(key);
    std::string path;
    if (!value.file_path(written, &path)) {
      ok = false;
      continue;
    }
    // Fast DDS reads these itself, later, and says only that security could not be set up: name the file here.
    if (std::FILE* file = std::fopen(path.c_str(), "rb")) {
      std::fclose(file);
    } else {
      value.error("cannot read " + config::quoted(written) + " (" + std::strerror(errno) + ")");
      ok = false;
      continue;
    }
    files.*member = path;
  }
  if (!ok) return std::nullopt;
  return files;
}

SecurityFiles load_security_file(const std::string& path) {
  DiagnosticSink sink;
  sink.add_file(path);
  std::string open_error;
  const std::optional<YAML::Node> root = parse_yaml_file(path, &sink, &open_error);
  if (!root && !open_error.empty()) {
    sink.report(path, YAML::Mark::null_mark(), "", "cannot open security file (" + open_error + ")");
  }
  std::optional<SecurityFiles> files;
  if (root) {
    // No roots: the file's own directory tree or anywhere, as the operator wrote it.
    const auto source = std::make_shared<const Source>(Source{path, &sink, nullptr});
    const MapReader map(Value::root(*root, source), {"security"});
    if (const auto block = map.required("security")) files = read_security_block(*block);
  }
  std::string message;
  for (const Diagnostic& diagnostic : sink.sorted()) {
    if (!diagnostic.warning) message += (message.empty() ? "" : "\n") + diagnostic.format();
  }
  if (!message.empty() || !files) throw std::runtime_error(message.empty() ? path + ": no security block" : message);
  return *files;
}

}  // namespace hadal::config
