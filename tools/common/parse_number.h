// Shared by Hadal's command-line tools: a command-line argument as a number. Header-only.
#pragma once

#include <cmath>
#include <cstdlib>
#include <string>

namespace hadal::tools {

// The whole of `text` as a finite number into *out; false (and *out unchanged) otherwise.
inline bool parse_number(const std::string& text, double* out) {
  if (text.empty()) return false;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(x)) return false;
  *out = x;
  return true;
}

// The whole of `text` as an integer in [min, max] into *out; false (and *out unchanged) otherwise.
inline bool parse_int(const std::string& text, long min, long max, int* out) {
  if (text.empty()) return false;
  char* end = nullptr;
  const long x = std::strtol(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size() || x < min || x > max) return false;
  *out = static_cast<int>(x);
  return true;
}

}  // namespace hadal::tools
