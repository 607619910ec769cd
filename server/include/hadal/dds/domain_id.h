// The DDS domain rule of every Hadal program, ROS 2's: the domain given (hadald --domain-id, a tool's
// --domain-id, ClientOptions::domain_id), else $ROS_DOMAIN_ID, else 0; an id is a whole number in 0..232.
// Header-only: hadald, the tools and the client library share it.
#pragma once

#include <cerrno>
#include <cstdlib>
#include <string>

namespace hadal::dds {

// `text` as a domain id (decimal digits only) into *out; false, and *out unchanged, otherwise.
inline bool parse_domain_id(const std::string& text, int* out) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
  errno = 0;
  const unsigned long long id = std::strtoull(text.c_str(), nullptr, 10);
  if (errno != 0 || id > 232) return false;
  *out = static_cast<int>(id);
  return true;
}

// --domain-id's value into *out: "" when it is a domain id, else the usage error.
inline std::string read_domain_id_option(const std::string& text, int* out) {
  return parse_domain_id(text, out) ? "" : "--domain-id must be an integer in 0..232 (got '" + text + "')";
}

// The domain when none is given, into *out, from ROS_DOMAIN_ID's value `env` (nullptr or empty: unset, so
// 0): "" when valid, else what is wrong.
inline std::string domain_id_from_environment(const char* env, int* out) {
  if (env == nullptr || *env == '\0') {
    *out = 0;
    return "";
  }
  if (parse_domain_id(env, out)) return "";
  return "ROS_DOMAIN_ID must be an integer in 0..232 (got '" + std::string(env) + "')";
}

}  // namespace hadal::dds
