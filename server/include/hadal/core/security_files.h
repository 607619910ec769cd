// The files of DDS Security (authentication, encryption, access control), as a scenario's `security:` block,
// `hadald --security FILE` and the clients name them (docs/dds.md, "DDS Security"; docs/ARCHITECTURE.md). The
// dds layer turns them into a participant's security properties (dds/participant.h); the config layer reads
// them from YAML (config/security_block.h). All empty: security off.
#pragma once

#include <string>

namespace hadal {

struct SecurityFiles {
  std::string identity_ca;     // PEM: the certificate authority that signed every participant's identity
  std::string certificate;     // PEM: this participant's identity certificate (signed by identity_ca)
  std::string private_key;     // PEM: its private key, unencrypted (readable by this process only)
  std::string permissions_ca;  // PEM: the authority that signed governance and permissions
  std::string governance;      // S/MIME-signed governance XML: what the domain protects (the same on every node)
  std::string permissions;     // S/MIME-signed permissions XML holding a grant for this certificate's subject

  bool enabled() const { return !certificate.empty(); }
};

}  // namespace hadal
