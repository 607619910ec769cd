// Shared by Hadal's command-line tools that join a hadald's domain: --security FILE, the `security:` block of
// FILE (config/security_block.h; docs/dds.md, "DDS Security"). Header-only; the tool links hadal_security_block.
#pragma once

#include "hadal/config/security_block.h"

#include <stdexcept>
#include <string>

namespace hadal::tools {

// FILE's security files into *out: "" when FILE is right, else what is wrong (file:line:col diagnostics).
inline std::string read_security_option(const std::string& file, SecurityFiles* out) {
  try {
    *out = config::load_security_file(file);
    return "";
  } catch (const std::runtime_error& e) {
    return e.what();
  }
}

}  // namespace hadal::tools
