// The std::invalid_argument a module throws when its own parameters are wrong, in one wording:
// "<field>: <what is wrong>" or "<field>: <requirement> (got <value>)". Config readers turn these into
// file:line:col diagnostics at the key (configs/REFERENCE.md).
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace hadal::validation {

[[noreturn]] inline void invalid(const std::string& field, const std::string& what) {
  throw std::invalid_argument(field + ": " + what);
}

[[noreturn]] inline void invalid(const std::string& field, const std::string& requirement, double got) {
  std::ostringstream message;
  message << field << ": " << requirement << " (got " << got << ")";
  throw std::invalid_argument(message.str());
}

}  // namespace hadal::validation
