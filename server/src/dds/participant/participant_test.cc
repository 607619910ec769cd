#include "hadal/dds/participant.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace hadal::dds {
namespace {

// Sets an environment variable for one scope (unset when value is null), putting back what was there.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    if (value) ::setenv(name, value, 1); else ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (had_) ::setenv(name_.c_str(), old_.c_str(), 1); else ::unsetenv(name_.c_str());
  }

 private:
  std::string name_, old_;
  bool had_ = false;
};

void fastdds_participant_ok() {
  eprosima::fastdds::dds::DomainParticipant* participant = create_participant(231, "participant_test");
  ASSERT_NE(participant, nullptr);
  delete_participant(participant);
}

TEST(ParticipantEnvironment, StaticPeersAreSplitAtSemicolonsAndTrimmed) {
  {
    ScopedEnv peers("ROS_STATIC_PEERS", nullptr);
    EXPECT_TRUE(static_peers_from_environment().empty());
  }
  ScopedEnv peers("ROS_STATIC_PEERS", " 10.0.0.2 ;;server;\t192.168.1.7");
  EXPECT_EQ(static_peers_from_environment(), (std::vector<std::string>{"10.0.0.2", "server", "192.168.1.7"}));
}

TEST(ParticipantEnvironment, BuiltinTransportsDefaultOrUdpOnly) {
  {
    ScopedEnv transports("FASTDDS_BUILTIN_TRANSPORTS", nullptr);
    EXPECT_TRUE(shared_memory_from_environment());
  }
  {
    ScopedEnv transports("FASTDDS_BUILTIN_TRANSPORTS", "DEFAULT");
    EXPECT_TRUE(shared_memory_from_environment());
  }
  {
    ScopedEnv transports("FASTDDS_BUILTIN_TRANSPORTS", "UDPv4");
    EXPECT_FALSE(shared_memory_from_environment());
  }
  ScopedEnv transports("FASTDDS_BUILTIN_TRANSPORTS", "TCPv4");
  try {
    shared_memory_from_environment();
    ADD_FAILURE() << "TCPv4 accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "FASTDDS_BUILTIN_TRANSPORTS must be DEFAULT or UDPv4 (got 'TCPv4')");
  }
}

// A peer that is no address and resolves to none is an error when the participant is made, not a
// participant that silently never discovers anyone.
TEST(ParticipantEnvironment, AnUnresolvablePeerIsAnError) {
  ScopedEnv peers("ROS_STATIC_PEERS", "no-such-host.invalid");
  try {
    create_participant(231, "participant_test");
    ADD_FAILURE() << "a participant was made";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("ROS_STATIC_PEERS: 'no-such-host.invalid' is no IPv4 address"),
              std::string::npos)
        << e.what();
  }
}

// Localhost-only discovery binds UDP to loopback: a remote static peer could never be reached, so asking for
// both is refused by name rather than a participant that silently finds nobody. Loopback peers are fine.
TEST(ParticipantEnvironment, LocalhostOnlyWithARemotePeerIsAnError) {
  ScopedEnv localhost("ROS_LOCALHOST_ONLY", "1");
  {
    ScopedEnv peers("ROS_STATIC_PEERS", "127.0.0.1");
    fastdds_participant_ok();
  }
  ScopedEnv peers("ROS_STATIC_PEERS", "10.0.0.2");
  try {
    create_participant(231, "participant_test");
    ADD_FAILURE() << "a participant was made";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("ROS_STATIC_PEERS names '10.0.0.2' (10.0.0.2), which localhost-only"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace hadal::dds
