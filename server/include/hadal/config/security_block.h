// The `security:` block (docs/dds.md, "DDS Security"): six files, each a path relative to the YAML file holding the
// block. A scenario may hold one (then its files obey the scenario's file rules, docs/ARCHITECTURE.md, "Files a
// scenario may reach"); `hadald --security FILE` and the clients read a file holding only this block, as
// tools/make-security-demo.sh writes them:
//
//   security:
//     identity_ca: identity_ca.pem        # the CA that signed every participant's certificate
//     certificate: hadald/cert.pem        # this participant's identity
//     private_key: hadald/key.pem         # its key (unencrypted PEM)
//     permissions_ca: permissions_ca.pem  # the CA that signed the two documents below
//     governance: governance.p7s          # signed governance: what the domain protects
//     permissions: permissions.p7s        # signed permissions: a grant for this certificate's subject
//
// Every key is required once the block is there; each must name a readable regular file.
#pragma once

#include "hadal/config/yaml_reader.h"
#include "hadal/config/key_table_fwd.h"
#include "hadal/core/security_files.h"

#include <optional>
#include <string>

namespace hadal::config {

// The keys of a `security:` block.
const KeyTable<SecurityFiles>& security_keys();

// Reads a `security:` block's value; reports every problem at its node and returns nullopt then. The paths
// returned are joined to the directory of the file holding the block (dds::create_participant makes them
// absolute for Fast DDS's file:// URIs).
std::optional<SecurityFiles> read_security_block(const Value& block);

// Reads a file whose only top-level key is `security` (paths relative to the file's directory, anywhere:
// the file is the operator's, not a scenario's). Throws std::runtime_error holding every diagnostic, one per
// line, `file:line:col: error: <path>: <what is wrong>`.
SecurityFiles load_security_file(const std::string& path);

}  // namespace hadal::config
