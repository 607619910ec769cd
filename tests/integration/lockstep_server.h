// Shared fixtures of the end-to-end tests: a lockstep hadald on its own DDS domain with a client, and a
// thread-safe log of the samples a subscription delivers, keyed by sim time.
#pragma once

#include "hadal_client/client.h"
#include "server_process.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace hadal::test {

// Keep discovery on this machine even when a test binary is run by hand (ctest sets it too).
inline const bool kLocalhostOnly = [] { return ::setenv("ROS_LOCALHOST_ONLY", "1", 1) == 0; }();

inline constexpr double kWait = 20.0;  // generous wall-clock bound for DDS events [s]; not a speed assertion

// The default AUV yawed 30 deg over a plane seabed at -100 m, no schedule (relative to the source tree).
inline const char* kClientScenario = "tests/integration/scenarios/auv_client.yaml";

// Thread-safe log of samples keyed by sim time.
template <class Sample>
class SampleLog {
 public:
  void add(const Sample& s) {
    std::lock_guard<std::mutex> lock(mutex_);
    samples_[s.stamp] = s;
  }
  bool has(double stamp) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = samples_.lower_bound(stamp - 1e-9);
    return it != samples_.end() && it->first <= stamp + 1e-9;
  }
  Sample at(double stamp) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return samples_.lower_bound(stamp - 1e-9)->second;
  }
  std::map<double, Sample> all() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return samples_;
  }

 private:
  mutable std::mutex mutex_;
  std::map<double, Sample> samples_;
};

// A lockstep hadald on its own domain (scenario: a path, absolute or relative to the source tree), with
// a client. Subscribe first, then connect(), then step: a subscription receives the samples the
// server's writer still keeps (its history depth) and everything after (dds/topic_registry.h).
class LockstepServer {
 public:
  explicit LockstepServer(const std::string& scenario = kClientScenario, const std::vector<std::string>& extra = {})
      : server_(args(scenario, extra)), client_(ClientOptions{domain_.id(), "hadal_integration_test"}) {}

  void connect() {
    ASSERT_TRUE(client_.wait_for_server(kWait)) << "no status from hadald; stderr:\n" << server_.err();
    ASSERT_TRUE(client_.wait_for_subscriptions(kWait))
        << "a subscribed topic has no writer: is the sensor in the scenario? stderr:\n"
        << server_.err();
  }

  Client& client() { return client_; }
  int domain() const { return domain_.id(); }
  ServerProcess& server() { return server_; }

 private:
  std::vector<std::string> args(const std::string& scenario, const std::vector<std::string>& extra) {
    std::vector<std::string> a = {scenario.rfind('/', 0) == 0 ? scenario : source_path(scenario), "--mode",
                                  "lockstep", "--domain-id", std::to_string(domain_.id()), "--no-status-line"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }

  DomainLease domain_;
  ServerProcess server_;
  Client client_;
};

}  // namespace hadal::test
