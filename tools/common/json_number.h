// Shared by Hadal's command-line tools (hadal-mesh-info, hadal-ocean, hadal-validate-*): numbers in
// JSON output. Header-only.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace hadal::tools {

// Shortest text (6 to 17 significant digits) that reads back as the same double; "null" for NaN and
// Inf, which JSON cannot express.
inline std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, x);
    if (std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

}  // namespace hadal::tools
