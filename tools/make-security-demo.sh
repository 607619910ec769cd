#!/usr/bin/env bash
# Makes a demo DDS Security set-up for hadal with openssl (docs/dds.md, "DDS Security"): an identity CA, a
# permissions CA, a certificate and key for hadald and for each client, the governance and permissions
# documents signed by the permissions CA, and one YAML file per identity holding its `security:` block, for
# `hadald --security`, ClientOptions::security_file (C++) and hadal.Client(security_file=...) (Python).
#
#   tools/make-security-demo.sh DIR [CLIENT_NAME...]     (clients default: hadal_client)
#
# DIR must not exist. It gets:
#   identity_ca.pem, permissions_ca.pem         the two CAs' certificates (every node needs both)
#   ca/                                         the CAs' private keys: keep them off the nodes
#   governance.xml, governance.p7s              the whole domain (ids 0..232), every topic: authenticated
#                                               participants only, discovery, liveliness, each submessage's
#                                               metadata and data encrypted (AES-GCM), read and write access
#                                               controlled; not whole RTPS messages again (docs/dds.md: Fast
#                                               DDS 2.9 aborts under load with rtps_protection_kind ENCRYPT)
#   permissions.xml, permissions.p7s            one grant per identity (subject = its certificate's
#                                               subject): publish and subscribe every topic
#   <name>/cert.pem, <name>/key.pem             each identity (hadald and the clients), ECDSA P-256
#   <name>.yaml                                 its security: block, paths relative to DIR
#
# Certificates and grants are valid from yesterday (grant times are read as the host's local time) for ten
# years. For finer grants, edit permissions.xml and sign it again with the command at its end below.
# A demo: the keys are unencrypted files readable by their owner only. Needs openssl (Debian: openssl).
set -euo pipefail

if [[ $# -lt 1 || "$1" == -* ]]; then
  echo "usage: $0 DIR [CLIENT_NAME...]" >&2
  exit 2
fi
dir=$1
shift
clients=("$@")
[[ ${#clients[@]} -gt 0 ]] || clients=(hadal_client)
if [[ -e "$dir" ]]; then
  echo "$0: error: $dir exists (choose a new directory)" >&2
  exit 2
fi
for name in "${clients[@]}"; do
  if [[ ! "$name" =~ ^[A-Za-z0-9_][A-Za-z0-9_.-]*$ || "$name" == hadald || "$name" == ca ]]; then
    echo "$0: error: client name '$name' must be letters, digits, _ . - (not first) and not hadald or ca" >&2
    exit 2
  fi
done
command -v openssl > /dev/null || { echo "$0: error: openssl not found (apt-get install openssl)" >&2; exit 2; }

mkdir -p "$dir"  # its parents as usual; what is inside for its owner only until the end
umask 077
mkdir "$dir/ca"
cd "$dir"
organization="Hadal demo"
# Runs a command, showing its output only when it fails (openssl is chatty on success).
quiet() {
  local out
  if ! out=$("$@" 2>&1); then
    echo "$out" >&2
    echo "$0: error: $1 failed" >&2
    return 1
  fi
}
# ECDSA P-256 with SHA-256: one of the signature algorithms Fast DDS's PKI-DH accepts.
new_key() { quiet openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:prime256v1 -out "$1"; }
new_ca() {  # KEY CERT COMMON_NAME
  new_key "$1"
  quiet openssl req -x509 -new -key "$1" -sha256 -days 3650 -subj "/O=$organization/CN=$3" \
    -set_serial "0x$(openssl rand -hex 8)" -out "$2"
}
new_ca ca/identity_ca_key.pem identity_ca.pem "Hadal demo identity CA"
new_ca ca/permissions_ca_key.pem permissions_ca.pem "Hadal demo permissions CA"

not_before=$(date -d yesterday +%Y-%m-%dT%H:%M:%S)
not_after=$(date -d '+10 years' +%Y-%m-%dT%H:%M:%S)
grants=""
for name in hadald "${clients[@]}"; do
  mkdir -p "$name"
  new_key "$name/key.pem"
  quiet openssl req -new -key "$name/key.pem" -subj "/O=$organization/CN=$name" -out "$name/request.csr"
  quiet openssl x509 -req -in "$name/request.csr" -CA identity_ca.pem -CAkey ca/identity_ca_key.pem \
    -set_serial "0x$(openssl rand -hex 8)" -sha256 -days 3650 -out "$name/cert.pem" \
    -extfile <(printf 'basicConstraints=critical,CA:FALSE\nkeyUsage=critical,digitalSignature,keyAgreement\n')
  rm "$name/request.csr"
  quiet openssl verify -CAfile identity_ca.pem "$name/cert.pem"
  # The grant names the subject as Fast DDS compares it: RFC 2253 order (the reverse of -subj).
  subject=$(openssl x509 -in "$name/cert.pem" -noout -subject -nameopt RFC2253 | sed 's/^subject=//')
  grants+="    <grant name=\"$name\">
      <subject_name>$subject</subject_name>
      <validity><not_before>$not_before</not_before><not_after>$not_after</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>232</max></id_range></domains>
        <publish><topics><topic>*</topic></topics><partitions><partition>*</partition></partitions></publish>
        <subscribe><topics><topic>*</topic></topics><partitions><partition>*</partition></partitions></subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
"
  cat > "$name.yaml" << EOF
# DDS Security of $name (made by tools/make-security-demo.sh; paths relative to this file).
security:
  identity_ca: identity_ca.pem
  certificate: $name/cert.pem
  private_key: $name/key.pem
  permissions_ca: permissions_ca.pem
  governance: governance.p7s
  permissions: permissions.p7s
EOF
done

# Fast DDS parses these without a schema but in the schema's element order (an element out of order is an
# error); enable_liveliness_protection is required.
cat > governance.xml << 'EOF'
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-Security/20170801/omg_shared_ca_domain_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>232</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
EOF
cat > permissions.xml << EOF
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-Security/20170801/omg_shared_ca_permissions.xsd">
  <permissions>
$grants  </permissions>
</dds>
EOF

# S/MIME with -text: Fast DDS verifies with PKCS7_TEXT and refuses a document signed without it.
for document in governance permissions; do
  quiet openssl smime -sign -text -in "$document.xml" -signer permissions_ca.pem -inkey ca/permissions_ca_key.pem \
    -out "$document.p7s"
  quiet openssl smime -verify -text -in "$document.p7s" -CAfile permissions_ca.pem -out /dev/null
done
# The certificates and documents are public; the keys stay private.
chmod 644 identity_ca.pem permissions_ca.pem ./*.xml ./*.p7s ./*.yaml ./*/cert.pem
chmod 755 . ./*/
chmod 700 ca

echo "DDS Security demo in $dir: identities hadald ${clients[*]}"
echo "  hadald SCENARIO --security $dir/hadald.yaml"
echo "  hadal.Client(domain_id, security_file=\"$dir/${clients[0]}.yaml\")"
