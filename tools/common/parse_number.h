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

// A DDS domain id for --domain-id (0..232, as ROS_DOMAIN_ID) into *out: "" when valid, else the usage error.
inline std::string parse_domain_id(const std::string& text, int* out) {
  return parse_int(text, 0, 232, out) ? "" : "--domain-id must be an integer in 0..232 (got '" + text + "')";
}

// The domain a tool joins without --domain-id into *out: $ROS_DOMAIN_ID when set, else 0. "" when valid, else
// the usage error.
inline std::string default_domain_id(int* out) {
  const char* env = std::getenv("ROS_DOMAIN_ID");
  if (env == nullptr || *env == '\0') {
    *out = 0;
    return "";
  }
  if (parse_int(env, 0, 232, out)) return "";
  return "ROS_DOMAIN_ID must be an integer in 0..232 (got '" + std::string(env) + "')";
}

}  // namespace hadal::tools
