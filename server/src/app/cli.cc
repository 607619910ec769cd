#include "cli.h"

#include "scheduling.h"

#include "hadal/dds/domain_id.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace hadal::app {

namespace {

bool parse_double(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(text.c_str(), &end);
  return errno == 0 && end == text.c_str() + text.size() && std::isfinite(out);
}

bool parse_uint64(const std::string& text, std::uint64_t& out) {
  if (text.empty() || text[0] == '-' || text[0] == '+') return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtoull(text.c_str(), &end, 10);
  return errno == 0 && end == text.c_str() + text.size();
}

}  // namespace

const char* to_string(RunMode mode) {
  switch (mode) {
    case RunMode::kRealtime: return "realtime";
    case RunMode::kFast: return "fast";
    case RunMode::kLockstep: return "lockstep";
  }
  return "unknown";
}

std::string usage() {
  return "usage: hadald SCENARIO.yaml [--duration SIM_SECONDS] [--mode realtime|fast|lockstep]\n"
         "                            [--rtf FACTOR] [--seed N] [--domain-id N]\n"
         "                            [--discovery-wait SECONDS] [--threads N] [--cpus LIST]\n"
         "                            [--sched batch|other] [--record DIR] [--no-status-line]\n"
         "                            [--no-cameras] [--asset-root DIR]... [--security FILE]\n"
         "                            [--set KEY.PATH=VALUE]...\n"
         "                            [--ray-kernels native|portable] [--lockstep-spin-us US]\n"
         "       hadald --schema [scenario|vehicle|object]\n"
         "       hadald SCENARIO.yaml --check [--set KEY.PATH=VALUE]... [--asset-root DIR]...\n"
         "  --duration S     stop after S seconds of sim time (default: run until Ctrl-C / SIGTERM)\n"
         "  --mode M         realtime (default): hold --rtf; fast: as fast as possible;\n"
         "                   lockstep: advance only on rt/hadal/step_request\n"
         "  --rtf F          real-time factor in realtime mode, > 0 (default 1)\n"
         "  --seed N         override the scenario's world.seed\n"
         "  --domain-id N    DDS domain 0..232 (default: $ROS_DOMAIN_ID, else 0)\n"
         "  --discovery-wait S  wall seconds to let DDS discovery match running subscribers before\n"
         "                   the first step (default 2 in fast mode, 0 otherwise)\n"
         "  --threads N      CPU threads to compute on, 1..256 (default: the scenario's world.threads,\n"
         "                   else one per CPU it may run on); 1 for several servers sharing a machine\n"
         "  --cpus LIST      run all of hadald's threads on these CPUs only, as taskset writes them\n"
         "                   (0 | 0,2 | 1-3); default: any CPU\n"
         "  --lockstep-spin-us US  lockstep: after each reply, poll for the next request this many\n"
         "                   microseconds before sleeping, 0..100000 (default 200; 0 for servers that share\n"
         "                   cores with each other, as hadal.env.VectorEnv's)\n"
         "  --sched P        other (default): the kernel's normal policy; batch: SCHED_BATCH, this\n"
         "                   server's wake-ups do not preempt other threads (a lockstep server sharing\n"
         "                   cores with the client that steps it)\n"
         "  --record DIR     record every topic into the rosbag2 bag DIR (sqlite3 storage; must not\n"
         "                   exist), bag time = sim time, flushed once per wall second\n"
         "  --no-status-line no per-second status line on stderr\n"
         "  --no-cameras     leave the scenario's cameras out (no rendering)\n"
         "  --ray-kernels K  override the scenario's world.ray_kernels: native (Embree's fastest for this\n"
         "                   CPU) or portable (the same ray-cast bits on every x86-64 machine, slower)\n"
         "  --asset-root DIR another directory the scenario's includes, meshes and maps may lie in\n"
         "                   (besides its own tree and hadal's configs; also $HADAL_ASSET_ROOTS, a:b)\n"
         "  --set K=V        override one key of the scenario as if the file said so, checked like it:\n"
         "                   world.water.current.uniform=[0.4,0,0], vehicles.auv.initial_pose.position=[0,0,-50]\n"
         "                   (a list's entry by its name; into a vehicle's included file through its entry;\n"
         "                   repeatable, the last wins; docs/configuration.md, \"Overrides\")\n"
         "  --security FILE  DDS Security (authentication, encryption, access control) with the files of\n"
         "                   FILE's `security:` block, in place of the scenario's (tools/make-security-demo.sh)\n"
         "  --check          load and check the scenario with its overrides, print its errors or\n"
         "                   'ok', exit 1 or 0; nothing starts (no DDS, no physics)\n"
         "  --schema [scenario|vehicle|object]  print the JSON Schema of scenario (default), vehicle or\n"
         "                   object files, for editors (docs/configuration.md), and exit\n"
         "Set ROS_LOCALHOST_ONLY=1 to keep DDS discovery on this machine.\n";
}

CliParse parse_cli(const std::vector<std::string>& args, const char* ros_domain_id_env) {
  CliParse parse;
  CliOptions& o = parse.options;
  if (std::string error = dds::domain_id_from_environment(ros_domain_id_env, &o.domain_id); !error.empty()) {
    parse.error = std::move(error);
    return parse;
  }
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "-h" || arg == "--help") {
      o.help = true;
      return parse;
    }
    if (arg == "--schema") {
      o.schema = "scenario";
      if (i + 1 < args.size() && (args[i + 1] == "scenario" || args[i + 1] == "vehicle" || args[i + 1] == "object")) {
        o.schema = args[++i];
      }
      return parse;
    }
    if (arg == "--check") {
      o.check = true;
      continue;
    }
    if (arg == "--no-status-line") {
      o.status_line = false;
      continue;
    }
    if (arg == "--no-cameras") {
      o.cameras = false;
      continue;
    }
    if (arg.rfind("--", 0) == 0) {
      if (i + 1 >= args.size()) {
        parse.error = "option " + arg + " needs a value";
        return parse;
      }
      const std::string& value = args[++i];
      if (arg == "--duration") {
        double d = 0.0;
        if (!parse_double(value, d) || d <= 0.0) {
          parse.error = "--duration must be a number of seconds > 0 (got '" + value + "')";
          return parse;
        }
        o.duration = d;
      } else if (arg == "--discovery-wait") {
        double w = 0.0;
        if (!parse_double(value, w) || w < 0.0) {
          parse.error = "--discovery-wait must be a number of seconds >= 0 (got '" + value + "')";
          return parse;
        }
        o.discovery_wait = w;
      } else if (arg == "--mode") {
        if (value == "realtime") o.mode = RunMode::kRealtime;
        else if (value == "fast") o.mode = RunMode::kFast;
        else if (value == "lockstep") o.mode = RunMode::kLockstep;
        else {
          parse.error = "--mode must be realtime, fast or lockstep (got '" + value + "')";
          return parse;
        }
      } else if (arg == "--ray-kernels") {
        if (value == "native") o.ray_kernels = geometry::RayKernels::kNative;
        else if (value == "portable") o.ray_kernels = geometry::RayKernels::kPortable;
        else {
          parse.error = "--ray-kernels must be native or portable (got '" + value + "')";
          return parse;
        }
      } else if (arg == "--rtf") {
        if (!parse_double(value, o.real_time_factor) || o.real_time_factor <= 0.0) {
          parse.error = "--rtf must be a number > 0 (got '" + value + "')";
          return parse;
        }
      } else if (arg == "--seed") {
        std::uint64_t seed = 0;
        if (!parse_uint64(value, seed)) {
          parse.error = "--seed must be a non-negative integer (got '" + value + "')";
          return parse;
        }
        o.seed = seed;
      } else if (arg == "--threads") {
        std::uint64_t threads = 0;
        if (!parse_uint64(value, threads) || threads < 1 || threads > 256) {
          parse.error = "--threads must be an integer in 1..256 (got '" + value + "')";
          return parse;
        }
        o.threads = static_cast<int>(threads);
      } else if (arg == "--cpus") {
        std::string why;
        o.cpus = parse_cpu_list(value, &why);
        if (o.cpus.empty()) {
          parse.error = "--cpus: " + why;
          return parse;
        }
      } else if (arg == "--lockstep-spin-us") {
        std::uint64_t spin = 0;
        if (!parse_uint64(value, spin) || spin > 100000) {
          parse.error = "--lockstep-spin-us must be an integer in 0..100000 (got '" + value + "')";
          return parse;
        }
        o.lockstep_spin_us = static_cast<int>(spin);
      } else if (arg == "--sched") {
        if (value == "batch") o.sched_batch = true;
        else if (value == "other") o.sched_batch = false;
        else {
          parse.error = "--sched must be batch or other (got '" + value + "')";
          return parse;
        }
      } else if (arg == "--record") {
        o.record_dir = value;
      } else if (arg == "--security") {
        o.security_file = value;  // read by hadald_main (config::load_security_file)
      } else if (arg == "--asset-root") {
        o.asset_roots.push_back(value);  // checked by the loader (config::asset_roots)
      } else if (arg == "--set") {
        o.overrides.push_back(value);  // KEY.PATH=VALUE, checked by the loader (config::LoadOptions)
      } else if (arg == "--domain-id") {
        if (std::string error = dds::read_domain_id_option(value, &o.domain_id); !error.empty()) {
          parse.error = std::move(error);
          return parse;
        }
      } else {
        parse.error = "unknown option " + arg;
        return parse;
      }
      continue;
    }
    if (!o.scenario_file.empty()) {
      parse.error = "more than one scenario file given ('" + o.scenario_file + "' and '" + arg + "')";
      return parse;
    }
    o.scenario_file = arg;
  }
  if (o.scenario_file.empty()) parse.error = "no scenario file given";
  return parse;
}

}  // namespace hadal::app
