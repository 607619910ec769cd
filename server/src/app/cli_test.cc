#include "cli.h"

#include <gtest/gtest.h>

namespace hadal::app {
namespace {

TEST(CliTest, DefaultsAndAllOptions) {
  CliParse p = parse_cli({"s.yaml"}, nullptr);
  ASSERT_EQ(p.error, "");
  EXPECT_EQ(p.options.scenario_file, "s.yaml");
  EXPECT_EQ(p.options.mode, RunMode::kRealtime);
  EXPECT_FALSE(p.options.duration.has_value());
  EXPECT_EQ(p.options.domain_id, 0);

  p = parse_cli({"--mode", "lockstep", "s.yaml", "--duration", "5", "--rtf", "2.5", "--seed", "7",
                 "--domain-id", "42", "--no-status-line", "--no-cameras", "--threads", "1"},
                nullptr);
  ASSERT_EQ(p.error, "");
  EXPECT_EQ(p.options.mode, RunMode::kLockstep);
  EXPECT_DOUBLE_EQ(*p.options.duration, 5.0);
  EXPECT_DOUBLE_EQ(p.options.real_time_factor, 2.5);
  EXPECT_EQ(*p.options.seed, 7u);
  EXPECT_EQ(p.options.domain_id, 42);
  EXPECT_FALSE(p.options.status_line);
  EXPECT_FALSE(p.options.cameras);
  EXPECT_TRUE(parse_cli({"s.yaml"}, nullptr).options.cameras);
  EXPECT_EQ(*p.options.threads, 1);
  EXPECT_FALSE(parse_cli({"s.yaml"}, nullptr).options.threads.has_value());
  EXPECT_EQ(parse_cli({"s.yaml", "--threads", "0"}, nullptr).error, "--threads must be an integer in 1..256 (got '0')");
  EXPECT_EQ(parse_cli({"s.yaml", "--threads", "two"}, nullptr).error,
            "--threads must be an integer in 1..256 (got 'two')");
  EXPECT_FALSE(p.options.ray_kernels.has_value());
  EXPECT_EQ(parse_cli({"s.yaml", "--ray-kernels", "portable"}, nullptr).options.ray_kernels,
            geometry::RayKernels::kPortable);
  EXPECT_EQ(parse_cli({"s.yaml", "--ray-kernels", "native"}, nullptr).options.ray_kernels,
            geometry::RayKernels::kNative);
  EXPECT_EQ(parse_cli({"s.yaml", "--ray-kernels", "avx2"}, nullptr).error,
            "--ray-kernels must be native or portable (got 'avx2')");
  EXPECT_DOUBLE_EQ(p.options.effective_discovery_wait(), 0.0);
  EXPECT_TRUE(p.options.asset_roots.empty());
  p = parse_cli({"s.yaml", "--asset-root", "/data/meshes", "--asset-root", "../maps"}, nullptr);
  ASSERT_EQ(p.error, "");
  EXPECT_EQ(p.options.asset_roots, (std::vector<std::string>{"/data/meshes", "../maps"}));
  EXPECT_EQ(parse_cli({"s.yaml", "--asset-root"}, nullptr).error, "option --asset-root needs a value");
  EXPECT_TRUE(p.options.overrides.empty());
  // Overrides in their order (the loader checks them: a later one wins).
  EXPECT_EQ(parse_cli({"s.yaml", "--set", "world.seed=3", "--set", "vehicles.auv.command_timeout_s=2"}, nullptr)
                .options.overrides,
            (std::vector<std::string>{"world.seed=3", "vehicles.auv.command_timeout_s=2"}));
  EXPECT_EQ(parse_cli({"s.yaml", "--set"}, nullptr).error, "option --set needs a value");
  EXPECT_EQ(p.options.security_file, "");
  EXPECT_EQ(parse_cli({"s.yaml", "--security", "dds/hadald.yaml"}, nullptr).options.security_file, "dds/hadald.yaml");
  EXPECT_EQ(parse_cli({"s.yaml", "--security"}, nullptr).error, "option --security needs a value");
  EXPECT_FALSE(p.options.check);
  EXPECT_TRUE(parse_cli({"s.yaml", "--check", "--set", "world.seed=3"}, nullptr).options.check);
}

TEST(CliTest, CpusAndSchedulingPolicy) {
  CliParse p = parse_cli({"s.yaml"}, nullptr);
  EXPECT_TRUE(p.options.cpus.empty());
  EXPECT_FALSE(p.options.sched_batch);
  p = parse_cli({"s.yaml", "--cpus", "3,0-1", "--sched", "batch"}, nullptr);
  ASSERT_EQ(p.error, "");
  EXPECT_EQ(p.options.cpus, (std::vector<int>{0, 1, 3}));
  EXPECT_TRUE(p.options.sched_batch);
  EXPECT_FALSE(parse_cli({"s.yaml", "--sched", "batch", "--sched", "other"}, nullptr).options.sched_batch);
  EXPECT_EQ(parse_cli({"s.yaml", "--sched", "fifo"}, nullptr).error, "--sched must be batch or other (got 'fifo')");
  EXPECT_EQ(parse_cli({"s.yaml", "--record", "runs/a"}, nullptr).options.record_dir, "runs/a");
  EXPECT_EQ(parse_cli({"s.yaml"}, nullptr).options.record_dir, "");
  EXPECT_EQ(parse_cli({"s.yaml", "--cpus", "1,x"}, nullptr).error,
            "--cpus: 'x' in '1,x' is not a CPU number (0..1023) or an ascending range of them (as '0-3')");
}

TEST(CliTest, LockstepSpin) {
  EXPECT_EQ(parse_cli({"s.yaml"}, nullptr).options.lockstep_spin_us, 200);
  EXPECT_EQ(parse_cli({"s.yaml", "--lockstep-spin-us", "0"}, nullptr).options.lockstep_spin_us, 0);
  EXPECT_EQ(parse_cli({"s.yaml", "--lockstep-spin-us", "100000"}, nullptr).options.lockstep_spin_us, 100000);
  EXPECT_EQ(parse_cli({"s.yaml", "--lockstep-spin-us", "100001"}, nullptr).error,
            "--lockstep-spin-us must be an integer in 0..100000 (got '100001')");
  EXPECT_EQ(parse_cli({"s.yaml", "--lockstep-spin-us", "-5"}, nullptr).error,
            "--lockstep-spin-us must be an integer in 0..100000 (got '-5')");
}

TEST(CliTest, DiscoveryWaitDefaultsToTwoSecondsInFastMode) {
  EXPECT_DOUBLE_EQ(parse_cli({"s.yaml", "--mode", "fast"}, nullptr).options.effective_discovery_wait(), 2.0);
  EXPECT_DOUBLE_EQ(parse_cli({"s.yaml"}, nullptr).options.effective_discovery_wait(), 0.0);
  EXPECT_DOUBLE_EQ(
      parse_cli({"s.yaml", "--mode", "fast", "--discovery-wait", "0"}, nullptr).options.effective_discovery_wait(),
      0.0);
  EXPECT_EQ(parse_cli({"s.yaml", "--discovery-wait", "-1"}, nullptr).error,
            "--discovery-wait must be a number of seconds >= 0 (got '-1')");
}

TEST(CliTest, DomainFromEnvironmentUnlessGiven) {
  EXPECT_EQ(parse_cli({"s.yaml"}, "17").options.domain_id, 17);
  EXPECT_EQ(parse_cli({"s.yaml", "--domain-id", "3"}, "17").options.domain_id, 3);
  EXPECT_NE(parse_cli({"s.yaml"}, "300").error, "");
}

TEST(CliTest, BadInputIsReported) {
  EXPECT_EQ(parse_cli({}, nullptr).error, "no scenario file given");
  EXPECT_EQ(parse_cli({"s.yaml", "--mode", "turbo"}, nullptr).error,
            "--mode must be realtime, fast or lockstep (got 'turbo')");
  EXPECT_EQ(parse_cli({"s.yaml", "--duration", "-1"}, nullptr).error,
            "--duration must be a number of seconds > 0 (got '-1')");
  EXPECT_EQ(parse_cli({"s.yaml", "--duration", "nan"}, nullptr).error,
            "--duration must be a number of seconds > 0 (got 'nan')");
  EXPECT_EQ(parse_cli({"s.yaml", "--rtf", "0"}, nullptr).error, "--rtf must be a number > 0 (got '0')");
  EXPECT_EQ(parse_cli({"s.yaml", "--seed", "-3"}, nullptr).error,
            "--seed must be a non-negative integer (got '-3')");
  EXPECT_EQ(parse_cli({"s.yaml", "--domain-id", "233"}, nullptr).error,
            "--domain-id must be an integer in 0..232 (got '233')");
  EXPECT_EQ(parse_cli({"s.yaml", "--frobnicate", "1"}, nullptr).error, "unknown option --frobnicate");
  EXPECT_EQ(parse_cli({"s.yaml", "--duration"}, nullptr).error, "option --duration needs a value");
  EXPECT_EQ(parse_cli({"a.yaml", "b.yaml"}, nullptr).error,
            "more than one scenario file given ('a.yaml' and 'b.yaml')");
}

}  // namespace
}  // namespace hadal::app
