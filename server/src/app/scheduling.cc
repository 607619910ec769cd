#include "scheduling.h"

#include <sched.h>
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace hadal::app {

namespace {

// 0 (the calling thread) and, with whole_process, the ids of this process's other threads now running
// (/proc/self/task).
std::vector<pid_t> threads_to_schedule(bool whole_process) {
  std::vector<pid_t> tids{0};
  if (!whole_process) return tids;
  const pid_t self = gettid();
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task", error)) {
    const pid_t tid = static_cast<pid_t>(std::atoi(entry.path().filename().c_str()));
    if (tid > 0 && tid != self) tids.push_back(tid);
  }
  return tids;
}

bool parse_cpu(const std::string& text, int& out) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 5) return false;
  out = std::atoi(text.c_str());
  return out < CPU_SETSIZE;
}

}  // namespace

std::vector<int> parse_cpu_list(const std::string& text, std::string* error) {
  std::vector<int> cpus;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::size_t dash = item.find('-');
    int first = 0;
    int last = 0;
    const bool ok = dash == std::string::npos
                        ? parse_cpu(item, first) && parse_cpu(item, last)
                        : parse_cpu(item.substr(0, dash), first) && parse_cpu(item.substr(dash + 1), last) &&
                              first <= last;
    if (!ok) {
      if (error != nullptr) {
        *error = "'" + item + "' in '" + text + "' is not a CPU number (0.." + std::to_string(CPU_SETSIZE - 1) +
                 ") or an ascending range of them (as '0-3')";
      }
      return {};
    }
    for (int cpu = first; cpu <= last; ++cpu) cpus.push_back(cpu);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  std::sort(cpus.begin(), cpus.end());
  cpus.erase(std::unique(cpus.begin(), cpus.end()), cpus.end());
  return cpus;
}

std::string format_cpu_list(const std::vector<int>& cpus) {
  std::string text;
  for (std::size_t i = 0; i < cpus.size();) {
    std::size_t j = i;
    while (j + 1 < cpus.size() && cpus[j + 1] == cpus[j] + 1) ++j;
    if (!text.empty()) text += ',';
    text += std::to_string(cpus[i]);
    if (j > i) text += '-' + std::to_string(cpus[j]);
    i = j + 1;
  }
  return text;
}

std::vector<int> allowed_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<int> cpus;
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return cpus;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (CPU_ISSET(cpu, &set)) cpus.push_back(cpu);
  }
  return cpus;
}

std::string apply_scheduling(const std::vector<int>& cpus, bool batch, bool whole_process) {
  const std::vector<pid_t> tids = threads_to_schedule(whole_process);
  // Of a thread other than the caller, ESRCH means it ended meanwhile: nothing to do.
  auto which = [](pid_t tid) { return tid == 0 ? std::string() : " of thread " + std::to_string(tid); };
  if (!cpus.empty()) {
    const std::vector<int> allowed = allowed_cpus();
    cpu_set_t set;
    CPU_ZERO(&set);
    for (int cpu : cpus) {
      if (!std::binary_search(allowed.begin(), allowed.end(), cpu)) {
        return "--cpus " + format_cpu_list(cpus) + ": CPU " + std::to_string(cpu) +
               " is not one this process may run on (" + format_cpu_list(allowed) + ")";
      }
      CPU_SET(cpu, &set);
    }
    for (const pid_t tid : tids) {
      if (sched_setaffinity(tid, sizeof(set), &set) != 0 && (tid == 0 || errno != ESRCH)) {
        return "--cpus " + format_cpu_list(cpus) + ": sched_setaffinity" + which(tid) + " failed: " +
               std::strerror(errno);
      }
    }
  }
  if (batch) {
    sched_param param{};
    param.sched_priority = 0;
    for (const pid_t tid : tids) {
      if (sched_setscheduler(tid, SCHED_BATCH, &param) != 0 && (tid == 0 || errno != ESRCH)) {
        return "--sched batch: sched_setscheduler" + which(tid) + " failed: " + std::strerror(errno);
      }
    }
  }
  return "";
}

}  // namespace hadal::app
