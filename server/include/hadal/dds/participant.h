// DDS participant set-up shared by hadald and the clients.
//
// Transports: shared memory (8 MB segment, so large samples such as camera frames are not
// fragmented, DDS_NOTES.md) plus UDPv4. Discovery scope follows ROS 2's environment conventions:
// with ROS_LOCALHOST_ONLY=1 or ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST, UDP is bound to the loopback
// interface and participants find each other through unicast initial peers on 127.0.0.1, so no
// discovery traffic leaves the machine (a ROS 2 node started with the same variable matches).
//
// Across machines, containers or network namespaces where multicast does not reach (ROS 2's names again):
// ROS_STATIC_PEERS="10.0.0.2;server" adds unicast discovery peers (IPv4 addresses or names that resolve
// to one), beside multicast; FASTDDS_BUILTIN_TRANSPORTS=UDPv4 leaves shared memory out, so two
// participants that share a /dev/shm but not a network (two network namespaces of one machine) talk over
// UDP (Fast DDS 2.9 does not read that variable itself; DEFAULT or unset: shared memory and UDPv4).
// A remote (non-loopback) static peer together with localhost-only discovery is an error; a participant made
// while no interface but loopback is running (it would announce only 127.0.0.1) gets a warning on stderr.
#pragma once

#include "hadal/core/security_files.h"

#include <fastdds/dds/domain/DomainParticipant.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace hadal::dds {

// True when the environment asks for localhost-only discovery (see above).
bool localhost_only_from_environment();
// ROS_STATIC_PEERS, split at ';' (blanks trimmed, empty entries dropped).
std::vector<std::string> static_peers_from_environment();
// True when an IPv4 interface other than loopback is running (IFF_RUNNING), the addresses Fast DDS announces.
bool non_loopback_interface_running();
// False when FASTDDS_BUILTIN_TRANSPORTS=UDPv4; true when unset or DEFAULT; throws std::runtime_error for
// any other value.
bool shared_memory_from_environment();
// Every writer's and reader's QoS goes through this: with FASTDDS_BUILTIN_TRANSPORTS=UDPv4 it also turns
// off data sharing (Fast DDS's delivery through shared-memory files in /dev/shm, beside the transports,
// chosen by itself between endpoints it takes to be on one host; two network namespaces of one machine
// are), so that nothing passes but over UDP.
template <class EndpointQos>
void apply_transport_environment(EndpointQos& qos) {
  if (!shared_memory_from_environment()) qos.data_sharing().off();
}

// What clean_stale_shared_memory removed.
struct StaleSharedMemory {
  int segments = 0;            // Fast DDS shared-memory segments of processes that are gone
  std::uint64_t bytes = 0;     // their size
};
// Removes the shared-memory segments Fast DDS processes killed without a clean exit left in `directory`
// (/dev/shm: RAM, 8 MB per participant here): each segment fastrtps_<16 hex digits> has a lock file
// <segment>_el that its owner holds (flock) while it lives, so a lock file nobody holds marks a segment of a
// dead process (what `fastdds shm clean` does for segments). Lock files younger than `min_age_s` are left
// (their owner may be between creating and locking them); files of other users are left.
StaleSharedMemory clean_stale_shared_memory(const std::string& directory = "/dev/shm", double min_age_s = 10.0);

// Creates an enabled participant on `domain_id` named `name`. Throws std::runtime_error on failure
// (e.g. a domain id out of range: valid ids are 0..232). `listener`, when given, is in place before the
// participant is enabled, so no discovery callback is missed (set later, the participants already on the
// domain can be discovered before it is).
//
// With `security` enabled, the participant uses Fast DDS's builtin DDS Security plugins: PKI-DH
// authentication, Access-Permissions (the signed governance and permissions) and AES-GCM-GMAC
// cryptography. It then talks only to participants whose certificates identity_ca signed and whose grants
// permissions_ca signed; one without security discovers it but never matches an endpoint, so it receives
// nothing and nothing it writes is read. Fast DDS refusing the files (a key not matching its certificate,
// a document signed by another CA or not with `openssl smime -sign -text`, no grant for the certificate's
// subject) is a std::runtime_error that names what to check; so is a participant that came out without
// authentication (an authentication plugin name Fast DDS does not know gives one silently).
//
// `user_data` is announced with the participant (its USER_DATA QoS) for others to show: hadald's says which
// process it is (user_data_text reads it back).
eprosima::fastdds::dds::DomainParticipant* create_participant(
    int domain_id, const std::string& name, eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr,
    const SecurityFiles& security = {}, const std::string& user_data = {});
// A discovered participant's USER_DATA as text.
std::string user_data_text(const std::vector<unsigned char>& user_data);

// True when `participant` authenticates (DDS Security on): its GUID prefix then derives from its certificate
// (first bit set) instead of the vendor id.
bool is_secure(const eprosima::fastdds::dds::DomainParticipant* participant);

// Two participants in one process (a client and a TopicTap in a test or a tool, hadald and its --record tap)
// talk through the transports, never Fast DDS's intraprocess shortcut: with it, Fast DDS 2.9 keeps a pointer
// to the other participant's discovery reader after that participant is deleted, and deleting an endpoint
// of the survivor then crashes in StatefulWriter::intraprocess_gap (seen as a rare SIGSEGV in ~Client after
// a test's TopicTap was deleted; docs/dds.md "Participants in one process"). create_participant calls this
// before each participant; the setting is process-wide.
void disable_intraprocess_delivery();
bool intraprocess_delivery_disabled();

// Deletes the participant and all entities it contains (so shared-memory segments are released).
void delete_participant(eprosima::fastdds::dds::DomainParticipant* participant);

}  // namespace hadal::dds
