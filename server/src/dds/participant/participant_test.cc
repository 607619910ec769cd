#include "hadal/dds/participant.h"

#include <fastrtps/attributes/LibrarySettingsAttributes.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>
#include <chrono>

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

// What creating a participant on domain 231 throws in the present environment ("" and a failure if it
// succeeds: every caller expects a refusal).
std::string creation_error() {
  try {
    delete_participant(create_participant(231, "participant_test"));
    ADD_FAILURE() << "a participant was made";
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// Participants of one process talk through the transports (participant.h): after making one, Fast DDS's
// intraprocess delivery is off, even when it was on before (as an XML profile could set it).
TEST(ParticipantEnvironment, ParticipantsOfOneProcessDoNotUseIntraprocessDelivery) {
  eprosima::fastrtps::LibrarySettingsAttributes on;
  on.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_FULL;
  eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(on);
  ASSERT_FALSE(intraprocess_delivery_disabled());
  fastdds_participant_ok();
  EXPECT_TRUE(intraprocess_delivery_disabled());
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
  const std::string error = creation_error();
  EXPECT_NE(error.find("ROS_STATIC_PEERS: 'no-such-host.invalid' is no IPv4 address"), std::string::npos) << error;
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
  const std::string error = creation_error();
  EXPECT_NE(error.find("ROS_STATIC_PEERS names '10.0.0.2' (10.0.0.2), which localhost-only"), std::string::npos)
      << error;
}

// Segments of dead owners (lock file held by no one) go with their lock files; a segment whose lock is held
// (a live participant), a young lock file (an owner between creating and locking it) and other files stay.
TEST(StaleSharedMemory, OnlySegmentsWhoseLockNobodyHoldsAreRemoved) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("hadal_shm_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto make = [&](const std::string& name, std::size_t bytes) {
    std::ofstream(dir / name) << std::string(bytes, 'x');
  };
  const std::string dead = "fastrtps_0123456789abcdef", live = "fastrtps_fedcba9876543210",
                    young = "fastrtps_00112233445566aa";
  for (const std::string& segment : {dead, live, young}) {
    make(segment, 4096);
    make(segment + "_el", 0);
  }
  make("fastrtps_port7411", 100);
  make("fastrtps_port7411_el", 0);
  make("fastrtps_xyz_el", 0);
  // Everything but the young lock file is an hour old.
  const auto old = fs::file_time_type::clock::now() - std::chrono::hours(1);
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().filename() != young + "_el") fs::last_write_time(entry.path(), old);
  }
  const int held = ::open((dir / (live + "_el")).c_str(), O_RDWR);
  ASSERT_GE(held, 0);
  ASSERT_EQ(::flock(held, LOCK_EX | LOCK_NB), 0);

  const StaleSharedMemory removed = clean_stale_shared_memory(dir.string(), 10.0);
  ::close(held);
  EXPECT_EQ(removed.segments, 1);
  EXPECT_EQ(removed.bytes, 4096u);
  EXPECT_FALSE(fs::exists(dir / dead));
  EXPECT_FALSE(fs::exists(dir / (dead + "_el")));
  for (const std::string& kept : {live, live + "_el", young, young + "_el", std::string("fastrtps_port7411"),
                                  std::string("fastrtps_port7411_el"), std::string("fastrtps_xyz_el")}) {
    EXPECT_TRUE(fs::exists(dir / kept)) << kept;
  }
  // Once its owner is gone, the live one is stale too.
  EXPECT_EQ(clean_stale_shared_memory(dir.string(), 10.0).segments, 1);
  EXPECT_FALSE(fs::exists(dir / live));
  EXPECT_EQ(clean_stale_shared_memory("/no/such/directory").segments, 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hadal::dds
