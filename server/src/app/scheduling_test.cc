#include "scheduling.h"

#include <gtest/gtest.h>
#include <sched.h>

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

}  // namespace
}  // namespace hadal::app
