// hadald command line:
//   hadald SCENARIO.yaml [--duration SIM_SECONDS] [--mode realtime|fast|lockstep] [--rtf FACTOR]
//          [--seed N] [--domain-id N] [--discovery-wait SECONDS] [--threads N] [--cpus LIST]
//          [--sched batch|other] [--record DIR] [--no-status-line] [--no-cameras]
//          [--ray-kernels native|portable] [--lockstep-spin-us MICROSECONDS]
//   hadald --schema [scenario|vehicle]
// --domain-id defaults to $ROS_DOMAIN_ID (as ROS 2), else 0. --seed overrides world.seed. --no-cameras
// leaves the scenario's cameras out (learning and benchmark runs that do not look at images).
// --ray-kernels overrides world.ray_kernels (geometry/ray_kernels.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hadal/geometry/ray_kernels.h"

namespace hadal::app {

enum class RunMode { kRealtime, kFast, kLockstep };

const char* to_string(RunMode mode);

struct CliOptions {
  std::string scenario_file;
  std::optional<double> duration;  // sim seconds; none: run until stopped
  RunMode mode = RunMode::kRealtime;
  double real_time_factor = 1.0;   // realtime mode: sim seconds per wall second
  std::optional<std::uint64_t> seed;
  std::optional<geometry::RayKernels> ray_kernels;  // --ray-kernels: overrides world.ray_kernels
  int domain_id = 0;
  bool status_line = true;
  bool cameras = true;  // false: --no-cameras
  std::optional<int> threads;  // --threads N: overrides world.threads
  std::vector<int> cpus;       // --cpus LIST: the CPUs all of hadald's threads run on (empty: any); scheduling.h
  bool sched_batch = false;    // --sched batch: SCHED_BATCH, wake-ups do not preempt; scheduling.h
  // --lockstep-spin-us: after each step reply a lockstep server polls for the next request this long before it
  // sleeps, so that a client stepping in a tight loop does not pay the server's wake-up (docs/benchmarks.md,
  // "Lockstep round trip and the Python client"). 0: sleep at once (servers sharing cores: hadal.env.VectorEnv).
  int lockstep_spin_us = 200;
  std::string record_dir;      // --record DIR: a rosbag2 bag of every topic (hadal/record/bag_recorder.h)
  std::vector<std::string> asset_roots;  // --asset-root DIR...: config::LoadOptions
  std::vector<std::string> overrides;    // --set KEY.PATH=VALUE...: config::LoadOptions
  std::string security_file;             // --security FILE: its `security:` block replaces the scenario's
  // Wall seconds to wait after start-up before the first step, so subscribers that are already
  // running are matched before the first samples (a fast run can be over before DDS discovery is).
  // Default: 2 s in fast mode (Fast DDS <-> Cyclone DDS first contact sometimes takes
  // ~1.05 s, DDS_NOTES.md), 0 otherwise.
  std::optional<double> discovery_wait;

  double effective_discovery_wait() const {
    return discovery_wait ? *discovery_wait : (mode == RunMode::kFast ? 2.0 : 0.0);
  }
  bool help = false;
  // --schema [scenario|vehicle]: print the JSON Schema of scenario (or vehicle) files and exit.
  std::string schema;
  // --check: load and check the scenario (with its overrides), report, exit; nothing starts.
  bool check = false;
};

struct CliParse {
  CliOptions options;
  std::string error;  // non-empty: print it with the usage and exit 2
};

// `args` excludes argv[0]. `ros_domain_id_env` is $ROS_DOMAIN_ID (or null).
CliParse parse_cli(const std::vector<std::string>& args, const char* ros_domain_id_env);

std::string usage();

}  // namespace hadal::app
