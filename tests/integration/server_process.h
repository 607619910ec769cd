// Test support: a real hadald child process on a DDS domain reserved for this test, and helpers
// to wait for samples without sleeping fixed times.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace hadal::test {

// Reserves a DDS domain id in [first, last] for the life of the object (flock on
// /tmp/hadal-dds-domain-<id>.lock), so tests running concurrently under ctest -j never share one.
class DomainLease {
 public:
  DomainLease(int first = 20, int last = 99);
  ~DomainLease();
  DomainLease(const DomainLease&) = delete;
  DomainLease& operator=(const DomainLease&) = delete;
  int id() const { return id_; }

 private:
  int id_ = -1;
  int fd_ = -1;
};

// Path of a scenario under the repository root.
std::string source_path(const std::string& relative);

class ServerProcess {
 public:
  // Starts `hadald args...` with ROS_LOCALHOST_ONLY=1; stdout/stderr go to files. The server is killed when the
  // thread that started it ends (PR_SET_PDEATHSIG), so a crashed test leaves no server behind.
  explicit ServerProcess(const std::vector<std::string>& args);
  ~ServerProcess();  // SIGKILLs the child if still running
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  int pid() const { return pid_; }
  bool running();
  // Sends `signal` and waits up to timeout_s for the exit. Returns the exit status (or -1 on timeout).
  int stop(int signal, double timeout_s = 20.0);
  // Waits for the child to exit by itself; returns the exit status or -1 on timeout.
  int wait(double timeout_s);
  std::string out() const;  // stdout so far
  std::string err() const;  // stderr so far

 private:
  int pid_ = -1;
  int status_ = -1;
  bool exited_ = false;
  std::string out_path_, err_path_;
};

// Polls `condition` every 5 ms until it holds or timeout_s passes.
bool wait_until(const std::function<bool()>& condition, double timeout_s);

}  // namespace hadal::test
