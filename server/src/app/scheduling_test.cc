#include "scheduling.h"

#include <gtest/gtest.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <thread>

namespace hadal::app {
namespace {

TEST(SchedulingTest, ParsesAndFormatsCpuLists) {
  std::string why;
  EXPECT_EQ(parse_cpu_list("0", &why), (std::vector<int>{0}));
  EXPECT_EQ(parse_cpu_list("6,1-3,2", &why), (std::vector<int>{1, 2, 3, 6}));
  EXPECT_EQ(format_cpu_list({0, 1, 2, 5, 7, 8}), "0-2,5,7-8");
  EXPECT_EQ(format_cpu_list(parse_cpu_list("1023", &why)), "1023");
  for (const char* bad : {"", ",", "1,", "-1", "3-1", "1-", "a", "1024", "0x1", " 1", "1..3"}) {
    why.clear();
    EXPECT_TRUE(parse_cpu_list(bad, &why).empty()) << bad;
    EXPECT_NE(why, "") << bad;
  }
}

// Runs on a thread of its own so that the test process keeps its CPUs and policy.
TEST(SchedulingTest, PinsAndBatchesTheCallingThreadAndTheThreadsItStarts) {
  const std::vector<int> allowed = allowed_cpus();
  ASSERT_FALSE(allowed.empty());
  std::thread([&] {
    ASSERT_EQ(apply_scheduling({allowed.back()}, true), "");
    EXPECT_EQ(allowed_cpus(), (std::vector<int>{allowed.back()}));
    EXPECT_EQ(sched_getscheduler(0), SCHED_BATCH);
    std::thread([&] {  // a thread started afterwards inherits both
      EXPECT_EQ(allowed_cpus(), (std::vector<int>{allowed.back()}));
      EXPECT_EQ(sched_getscheduler(0), SCHED_BATCH);
    }).join();
    // Narrowed to one CPU, no other may be asked for; nothing changes.
    const int other = allowed.back() + 1;
    EXPECT_EQ(apply_scheduling({other}, false),
              "--cpus " + std::to_string(other) + ": CPU " + std::to_string(other) +
                  " is not one this process may run on (" + std::to_string(allowed.back()) + ")");
    EXPECT_EQ(allowed_cpus(), (std::vector<int>{allowed.back()}));
  }).join();
  EXPECT_EQ(allowed_cpus(), allowed);
  EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
}

// With whole_process, a thread already running when hadald applies its scheduling (as OpenBLAS's pool,
// started when the library is loaded) is pinned and batched too. In a child process, so that the test
// process keeps its CPUs and policy; the child reports by its exit status (0: as expected; 1..4: which check
// failed). Without whole_process the running thread keeps its CPUs (status 1 then: the check can fail).
int child_status(bool whole_process, int cpu) {
  const pid_t child = fork();
  if (child == 0) {
    std::atomic<pid_t> tid{0};
    std::atomic<bool> done{false};
    std::thread running([&] {
      tid = gettid();
      while (!done) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    });
    while (tid == 0) std::this_thread::yield();
    int status = apply_scheduling({cpu}, true, whole_process) == "" ? 0 : 4;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (status == 0 && sched_getaffinity(tid, sizeof(set), &set) != 0) status = 3;
    if (status == 0 && (CPU_COUNT(&set) != 1 || !CPU_ISSET(cpu, &set))) status = 1;
    if (status == 0 && sched_getscheduler(tid) != SCHED_BATCH) status = 2;
    done = true;
    running.join();
    _exit(status);
  }
  int status = -1;
  waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(SchedulingTest, WholeProcessAlsoPinsAndBatchesThreadsAlreadyRunning) {
  const std::vector<int> allowed = allowed_cpus();
  ASSERT_FALSE(allowed.empty());
  EXPECT_EQ(child_status(true, allowed.back()), 0);
  if (allowed.size() > 1) {
    EXPECT_EQ(child_status(false, allowed.back()), 1);  // the check can tell
  }
}

}  // namespace
}  // namespace hadal::app
