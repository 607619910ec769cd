#include "hadal/config/security_block.h"

#include "hadal/config/key_table.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace hadal::config {

const KeyTable<SecurityFiles>& security_keys() {
  return declare_keys<SecurityFiles>([](KeyTable<SecurityFiles>& t) {
    t.describe("security",
               "DDS Security of hadald's participant (docs/dds.md): PKI-DH authentication, AES-GCM-GMAC "
               "encryption, access control; each file relative to the file holding the block");
    const std::pair<const char*, std::string SecurityFiles::*> files[] = {
        {"identity_ca", &SecurityFiles::identity_ca},    {"certificate", &SecurityFiles::certificate},
        {"private_key", &SecurityFiles::private_key},    {"permissions_ca", &SecurityFiles::permissions_ca},
        {"governance", &SecurityFiles::governance},      {"permissions", &SecurityFiles::permissions}};
    const char* docs[] = {
        "PEM certificate of the CA that signed every participant's identity certificate",
        "PEM identity certificate of this participant (ECDSA P-256 or RSA, signed with SHA-256)",
        "its PEM private key, unencrypted",
        "PEM certificate of the CA that signed the governance and permissions documents",
        "S/MIME-signed governance document (openssl smime -sign -text): what the domain protects",
        "S/MIME-signed permissions document with a grant for this certificate's subject"};
    for (std::size_t i = 0; i < 6; ++i) {
      t.file(files[i].first, files[i].second)
          .required()
          .doc(docs[i]);
    }
    // Fast DDS reads the files itself, later, and says only that security could not be set up: name an
    // unreadable one here.
    t.check([files](const KeyReads& reads, SecurityFiles& out, NoContext&) {
      bool ok = true;
      for (const auto& [key, member] : files) {
        if (!reads.has(key) || !reads.ok(key)) continue;
        if (std::FILE* file = std::fopen((out.*member).c_str(), "rb")) {
          std::fclose(file);
        } else {
          reads.map().optional(key)->error("cannot read " + quoted(reads.map().optional(key)->node().Scalar()) +
                                           " (" + std::strerror(errno) + ")");
          ok = false;
        }
      }
      return ok;
    });
  });
}

std::optional<SecurityFiles> read_security_block(const Value& block) {
  SecurityFiles files;
  if (!security_keys().read(block, &files)) return std::nullopt;
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
    const auto source = std::make_shared<const Source>(Source{path, &sink, nullptr, nullptr, {}});
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
