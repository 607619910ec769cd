// DDS participant set-up shared by hadald and the clients.
//
// Transports: shared memory (8 MB segment, so large samples such as camera frames are not
// fragmented, DDS_NOTES.md) plus UDPv4. Discovery scope follows ROS 2's environment conventions:
// with ROS_LOCALHOST_ONLY=1 or ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST, UDP is bound to the loopback
// interface and participants find each other through unicast initial peers on 127.0.0.1, so no
// discovery traffic leaves the machine (a ROS 2 node started with the same variable matches).
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>

#include <string>

namespace hadal::dds {

// True when the environment asks for localhost-only discovery (see above).
bool localhost_only_from_environment();

// Creates an enabled participant on `domain_id` named `name`. Throws std::runtime_error on failure
// (e.g. a domain id out of range: valid ids are 0..232). `listener`, when given, is in place before the
// participant is enabled, so no discovery callback is missed (set later, the participants already on the
// domain can be discovered before it is).
eprosima::fastdds::dds::DomainParticipant* create_participant(
    int domain_id, const std::string& name, eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr);

// Deletes the participant and all entities it contains (so shared-memory segments are released).
void delete_participant(eprosima::fastdds::dds::DomainParticipant* participant);

}  // namespace hadal::dds
