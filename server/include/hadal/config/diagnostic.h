// A problem found while reading configuration: where it is (file, 1-based line and column, YAML path)
// and what is wrong (docs/ARCHITECTURE.md, "Strict configuration").
#pragma once

#include <string>

namespace hadal::config {

struct Diagnostic {
  std::string file;
  int line = 0;    // 1-based
  int column = 0;  // 1-based
  std::string path;  // e.g. vehicles[0].thrusters[1].max_rpm
  std::string message;
  bool warning = false;  // a warning does not stop the load

  // "file:line:col: error: path: message" (or "warning:")
  std::string format() const;
};

}  // namespace hadal::config
