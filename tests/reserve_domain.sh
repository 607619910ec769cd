# Sourced by the test scripts: reserve_domain FIRST LAST sets DOMAIN to the first DDS domain id in
# FIRST..LAST whose lock file /tmp/hadal-dds-domain-<id>.lock no other process holds, and holds it on file
# descriptor 9 for the life of the calling shell (the same lock files as the C++ tests' DomainLease and
# hadal.server.reserve_domain). Pass `9>&-` to children that must not keep it. Returns 1 if none is free.
reserve_domain() {
  DOMAIN=""
  local n
  for n in $(seq "$1" "$2"); do
    { exec 9>>"/tmp/hadal-dds-domain-$n.lock"; } 2>/dev/null || continue
    if flock -n 9; then
      DOMAIN=$n
      return 0
    fi
    exec 9>&-
  done
  return 1
}
