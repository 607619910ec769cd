#include "hadal/dds/participant.h"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/attributes/LibrarySettingsAttributes.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>

#include <arpa/inet.h>
#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <netdb.h>
#include <netinet/in.h>

#include <algorithm>
#include <cctype>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace hadal::dds {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastdds::rtps;

namespace {
// RTPS well-known port mapping (DDSI-RTPS 2.x, 9.6.1.1): metatraffic unicast port of participant p
// in domain d is PB + DG*d + d1 + PG*p with PB=7400, DG=250, d1=10, PG=2.
constexpr int kMaxLocalParticipants = 32;
// A participant's first announcements: 20, 0.1 s apart (see create_participant).
constexpr std::uint32_t kInitialAnnouncements = 20;
constexpr std::uint32_t kInitialAnnouncementPeriodNs = 100'000'000;
std::uint32_t metatraffic_unicast_port(int domain_id, int participant_index) {
  return static_cast<std::uint32_t>(7400 + 250 * domain_id + 10 + 2 * participant_index);
}
// A static peer as a dotted IPv4 address: itself, or the first IPv4 address its name resolves to (a
// container's service name). Throws when it has none.
std::string ipv4_address(const std::string& peer) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  addrinfo* found = nullptr;
  if (getaddrinfo(peer.c_str(), nullptr, &hints, &found) != 0 || found == nullptr) {
    throw std::runtime_error("ROS_STATIC_PEERS: '" + peer + "' is no IPv4 address and no name that resolves to one");
  }
  char text[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(found->ai_addr)->sin_addr, text, sizeof(text));
  freeaddrinfo(found);
  return text;
}
bool is_loopback(const std::string& address) { return address.rfind("127.", 0) == 0; }

// Fast DDS's builtin security plugins and their files (the property names of the DDS Security
// specification's builtin plugins). An authentication plugin name Fast DDS does not know would leave the
// participant unauthenticated without an error: create_participant checks the result (is_secure).
void add_security_properties(const SecurityFiles& files, fdds::DomainParticipantQos* qos) {
  auto& properties = qos->properties().properties();
  const auto uri = [](const std::string& path) {  // file:///absolute/path
    return "file://" + std::filesystem::absolute(path).lexically_normal().string();
  };
  properties.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  properties.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_ca", uri(files.identity_ca));
  properties.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_certificate", uri(files.certificate));
  properties.emplace_back("dds.sec.auth.builtin.PKI-DH.private_key", uri(files.private_key));
  properties.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  properties.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions_ca", uri(files.permissions_ca));
  properties.emplace_back("dds.sec.access.builtin.Access-Permissions.governance", uri(files.governance));
  properties.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions", uri(files.permissions));
  properties.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
}
}  // namespace

void disable_intraprocess_delivery() {
  eprosima::fastrtps::LibrarySettingsAttributes settings =
      eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings();
  settings.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
  eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(settings);
}

bool intraprocess_delivery_disabled() {
  return eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings().intraprocess_delivery ==
         eprosima::fastrtps::INTRAPROCESS_OFF;
}

bool non_loopback_interface_running() {
  ifaddrs* interfaces = nullptr;
  if (getifaddrs(&interfaces) != 0) return true;  // unknown: no warning
  bool running = false;
  for (const ifaddrs* i = interfaces; i != nullptr && !running; i = i->ifa_next) {
    running = i->ifa_addr != nullptr && i->ifa_addr->sa_family == AF_INET && (i->ifa_flags & IFF_RUNNING) != 0 &&
              (i->ifa_flags & IFF_LOOPBACK) == 0;
  }
  freeifaddrs(interfaces);
  return running;
}

bool localhost_only_from_environment() {
  const char* only = std::getenv("ROS_LOCALHOST_ONLY");
  if (only != nullptr && std::strcmp(only, "1") == 0) return true;
  const char* range = std::getenv("ROS_AUTOMATIC_DISCOVERY_RANGE");
  return range != nullptr && std::strcmp(range, "LOCALHOST") == 0;
}

std::string user_data_text(const std::vector<unsigned char>& user_data) {
  return std::string(user_data.begin(), user_data.end());
}

fdds::DomainParticipant* create_participant(int domain_id, const std::string& name,
                                            fdds::DomainParticipantListener* listener, const SecurityFiles& security,
                                            const std::string& user_data) {
  if (domain_id < 0 || domain_id > 232) {
    throw std::runtime_error("DDS domain id must be in 0..232 (got " + std::to_string(domain_id) + ")");
  }
  // Loads the XML profiles (once) before the library setting below, which a profile could set otherwise.
  fdds::DomainParticipantFactory::get_instance()->load_profiles();
  disable_intraprocess_delivery();
  fdds::DomainParticipantQos qos = fdds::PARTICIPANT_QOS_DEFAULT;
  qos.name(name);
  if (!user_data.empty()) qos.user_data().setValue(std::vector<unsigned char>(user_data.begin(), user_data.end()));
  qos.transport().use_builtin_transports = false;

  if (shared_memory_from_environment()) {
    auto shm = std::make_shared<rtps::SharedMemTransportDescriptor>();
    shm->segment_size(8 * 1024 * 1024);
    qos.transport().user_transports.push_back(shm);
  }

  // Unicast discovery peers: every participant index's metatraffic port at each address.
  auto& peers = qos.wire_protocol().builtin.initialPeersList;
  auto add_peer = [&](const std::string& address) {
    for (int p = 0; p < kMaxLocalParticipants; ++p) {
      eprosima::fastrtps::rtps::Locator_t locator;
      eprosima::fastrtps::rtps::IPLocator::setIPv4(locator, address);
      locator.port = metatraffic_unicast_port(domain_id, p);
      peers.push_back(locator);
    }
  };
  auto udp = std::make_shared<rtps::UDPv4TransportDescriptor>();
  const bool localhost_only = localhost_only_from_environment();
  if (localhost_only) {
    udp->interfaceWhiteList.emplace_back("127.0.0.1");
    add_peer("127.0.0.1");
  }
  bool remote_peers = false;
  for (const std::string& peer : static_peers_from_environment()) {
    const std::string address = ipv4_address(peer);
    if (!is_loopback(address)) {
      // UDP bound to loopback never reaches another machine: the two settings contradict each other.
      if (localhost_only) {
        throw std::runtime_error("ROS_STATIC_PEERS names '" + peer + "' (" + address +
                                 "), which localhost-only discovery (ROS_LOCALHOST_ONLY=1 or "
                                 "ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST) can never reach; unset one of them");
      }
      remote_peers = true;
    }
    add_peer(address);
  }
  // Fast DDS announces the addresses of the interfaces running now, and only 127.0.0.1 when none is: a
  // participant made before its network is up stays unreachable for its whole life.
  if (remote_peers && !non_loopback_interface_running()) {
    std::fprintf(stderr,
                 "%s: warning: ROS_STATIC_PEERS names remote peers, but no network interface other than loopback "
                 "is running: this participant announces only 127.0.0.1 and no remote peer can reach it (start it "
                 "once the network is up)\n",
                 name.c_str());
  }
  qos.transport().user_transports.push_back(udp);
  // Fast DDS sends a participant's first announcements (5, 0.1 s apart) and then one every 3 s. A peer whose
  // participant appears after the first burst learns of this one only from the next periodic one: a client
  // made just before the hadald it waits for (hadal.Server's readiness probe, when the two share a CPU and
  // hadald's start-up stretches past the burst) waited ~3 s for it. 2 s of first announcements cover a
  // peer that starts beside this one (docs/dds.md, "Discovery").
  qos.wire_protocol().builtin.discovery_config.initial_announcements.count = kInitialAnnouncements;
  qos.wire_protocol().builtin.discovery_config.initial_announcements.period = {0, kInitialAnnouncementPeriodNs};
  if (security.enabled()) add_security_properties(security, &qos);

  fdds::DomainParticipant* participant =
      fdds::DomainParticipantFactory::get_instance()->create_participant(domain_id, qos, listener,
                                                                         fdds::StatusMask::none());
  if (participant == nullptr) {
    if (security.enabled()) {
      throw std::runtime_error(
          "could not create a DDS participant on domain " + std::to_string(domain_id) +
          " with DDS Security: Fast DDS refused the security files (see its message above). Check that " +
          security.private_key + " belongs to " + security.certificate + ", that " + security.identity_ca +
          " signed that certificate, that " + security.permissions_ca + " signed " + security.governance + " and " +
          security.permissions + " (openssl smime -sign -text), and that the permissions grant the certificate's "
          "subject (openssl x509 -noout -subject -nameopt RFC2253) on domain " + std::to_string(domain_id));
    }
    throw std::runtime_error("could not create a DDS participant on domain " + std::to_string(domain_id));
  }
  if (security.enabled() && !is_secure(participant)) {
    delete_participant(participant);
    throw std::runtime_error("DDS Security was asked for, but Fast DDS made participant '" + name +
                             "' without it (a Fast DDS built without security?)");
  }
  return participant;
}

bool is_secure(const fdds::DomainParticipant* participant) {
  // PKI-DH replaces the GUID prefix by a hash of the certificate's subject, first bit set; otherwise the
  // prefix starts with the vendor id (0x01 for eProsima).
  return (participant->guid().guidPrefix.value[0] & 0x80) != 0;
}

std::vector<std::string> static_peers_from_environment() {
  std::vector<std::string> peers;
  const char* list = std::getenv("ROS_STATIC_PEERS");
  if (list == nullptr) return peers;
  const std::string text = list;
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t end = std::min(text.find(';', start), text.size());
    std::string peer = text.substr(start, end - start);
    peer.erase(0, peer.find_first_not_of(" \t"));
    peer.erase(peer.find_last_not_of(" \t") + 1);
    if (!peer.empty()) peers.push_back(peer);
    start = end + 1;
  }
  return peers;
}

bool shared_memory_from_environment() {
  const char* transports = std::getenv("FASTDDS_BUILTIN_TRANSPORTS");
  if (transports == nullptr || *transports == '\0' || std::strcmp(transports, "DEFAULT") == 0) return true;
  if (std::strcmp(transports, "UDPv4") == 0) return false;
  throw std::runtime_error("FASTDDS_BUILTIN_TRANSPORTS must be DEFAULT or UDPv4 (got '" + std::string(transports) +
                           "')");
}

namespace {
// fastrtps_ followed by 16 lowercase hex digits and `suffix`.
bool is_segment_name(const std::string& name, const std::string& suffix) {
  const std::string prefix = "fastrtps_";
  if (name.size() != prefix.size() + 16 + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return false;
  }
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(prefix.size()),
                     name.begin() + static_cast<std::ptrdiff_t>(prefix.size() + 16),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || (c >= 'a' && c <= 'f'); });
}
}  // namespace

StaleSharedMemory clean_stale_shared_memory(const std::string& directory, double min_age_s) {
  StaleSharedMemory removed;
  DIR* dir = opendir(directory.c_str());
  if (dir == nullptr) return removed;
  std::vector<std::string> lock_files;
  while (const dirent* entry = readdir(dir)) {
    if (is_segment_name(entry->d_name, "_el")) lock_files.emplace_back(entry->d_name);
  }
  closedir(dir);
  const std::time_t now = std::time(nullptr);
  for (const std::string& lock_name : lock_files) {
    const std::string lock_path = directory + "/" + lock_name;
    const std::string segment_path = lock_path.substr(0, lock_path.size() - 3);
    struct stat lock_stat{};
    if (stat(lock_path.c_str(), &lock_stat) != 0 || lock_stat.st_uid != geteuid() ||
        std::difftime(now, lock_stat.st_mtime) < min_age_s) {
      continue;
    }
    const int fd = open(lock_path.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0) continue;
    // Held by a live owner: the lock is refused and the segment is in use.
    if (flock(fd, LOCK_EX | LOCK_NB) == 0) {
      struct stat segment_stat{};
      const bool has_segment = stat(segment_path.c_str(), &segment_stat) == 0;
      if ((!has_segment || unlink(segment_path.c_str()) == 0) && unlink(lock_path.c_str()) == 0) {
        ++removed.segments;
        if (has_segment) removed.bytes += static_cast<std::uint64_t>(segment_stat.st_size);
      }
    }
    close(fd);
  }
  return removed;
}

void delete_participant(fdds::DomainParticipant* participant) {
  if (participant == nullptr) return;
  participant->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(participant);
}

}  // namespace hadal::dds
