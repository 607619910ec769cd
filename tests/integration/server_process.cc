#include "server_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace hadal::test {

DomainLease::DomainLease(int first, int last) {
  for (int id = first; id <= last; ++id) {
    const std::string path = "/tmp/hadal-dds-domain-" + std::to_string(id) + ".lock";
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {
      id_ = id;
      fd_ = fd;
      return;
    }
    ::close(fd);
  }
  throw std::runtime_error("no free DDS domain id for the test");
}

DomainLease::~DomainLease() {
  if (fd_ >= 0) ::close(fd_);
}

std::string source_path(const std::string& relative) { return std::string(HADAL_SOURCE_DIR) + "/" + relative; }

namespace {
std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

ServerProcess::ServerProcess(const std::vector<std::string>& args) {
  static int counter = 0;
  const std::string stem = "/tmp/hadald-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  out_path_ = stem + ".out";
  err_path_ = stem + ".err";
  const pid_t parent = ::getpid();
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    // hadald dies with the test: a test that crashes must not leave a server running on a domain whose lease
    // died with it (the next test to take the domain would talk to both). Checked again after the call, in
    // case the parent died before it.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);
    const int out = ::open(out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, 1);
    ::dup2(err, 2);
    ::setenv("ROS_LOCALHOST_ONLY", "1", 1);
    std::vector<char*> argv;
    std::string exe = HADALD_PATH;
    argv.push_back(exe.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
}

ServerProcess::~ServerProcess() {
  if (running()) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, &status_, 0);
  }
  ::unlink(out_path_.c_str());
  ::unlink(err_path_.c_str());
}

bool ServerProcess::running() {
  if (exited_) return false;
  const pid_t r = ::waitpid(pid_, &status_, WNOHANG);
  if (r == pid_) exited_ = true;
  return !exited_;
}

int ServerProcess::wait(double timeout_s) {
  if (!wait_until([this] { return !running(); }, timeout_s)) return -1;
  return WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
}

int ServerProcess::stop(int signal, double timeout_s) {
  if (running()) ::kill(pid_, signal);
  return wait(timeout_s);
}

std::string ServerProcess::out() const { return read_file(out_path_); }
std::string ServerProcess::err() const { return read_file(err_path_); }

bool wait_until(const std::function<bool()>& condition, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return condition();
}

}  // namespace hadal::test
