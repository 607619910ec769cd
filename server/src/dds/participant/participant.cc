#include "hadal/dds/participant.h"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace hadal::dds {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastdds::rtps;

namespace {
// RTPS well-known port mapping (DDSI-RTPS 2.x, 9.6.1.1): metatraffic unicast port of participant p
// in domain d is PB + DG*d + d1 + PG*p with PB=7400, DG=250, d1=10, PG=2.
constexpr int kMaxLocalParticipants = 32;
std::uint32_t metatraffic_unicast_port(int domain_id, int participant_index) {
  return static_cast<std::uint32_t>(7400 + 250 * domain_id + 10 + 2 * participant_index);
}
}  // namespace

bool localhost_only_from_environment() {
  const char* only = std::getenv("ROS_LOCALHOST_ONLY");
  if (only != nullptr && std::strcmp(only, "1") == 0) return true;
  const char* range = std::getenv("ROS_AUTOMATIC_DISCOVERY_RANGE");
  return range != nullptr && std::strcmp(range, "LOCALHOST") == 0;
}

fdds::DomainParticipant* create_participant(int domain_id, const std::string& name,
                                            fdds::DomainParticipantListener* listener) {
  if (domain_id < 0 || domain_id > 232) {
    throw std::runtime_error("DDS domain id must be in 0..232 (got " + std::to_string(domain_id) + ")");
  }
  fdds::DomainParticipantQos qos = fdds::PARTICIPANT_QOS_DEFAULT;
  qos.name(name);
  qos.transport().use_builtin_transports = false;

  auto shm = std::make_shared<rtps::SharedMemTransportDescriptor>();
  shm->segment_size(8 * 1024 * 1024);
  qos.transport().user_transports.push_back(shm);

  auto udp = std::make_shared<rtps::UDPv4TransportDescriptor>();
  if (localhost_only_from_environment()) {
    udp->interfaceWhiteList.emplace_back("127.0.0.1");
    auto& peers = qos.wire_protocol().builtin.initialPeersList;
    for (int p = 0; p < kMaxLocalParticipants; ++p) {
      eprosima::fastrtps::rtps::Locator_t locator;
      eprosima::fastrtps::rtps::IPLocator::setIPv4(locator, 127, 0, 0, 1);
      locator.port = metatraffic_unicast_port(domain_id, p);
      peers.push_back(locator);
    }
  }
  qos.transport().user_transports.push_back(udp);

  fdds::DomainParticipant* participant =
      fdds::DomainParticipantFactory::get_instance()->create_participant(domain_id, qos, listener,
                                                                         fdds::StatusMask::none());
  if (participant == nullptr) {
    throw std::runtime_error("could not create a DDS participant on domain " + std::to_string(domain_id));
  }
  return participant;
}

void delete_participant(fdds::DomainParticipant* participant) {
  if (participant == nullptr) return;
  participant->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(participant);
}

}  // namespace hadal::dds
