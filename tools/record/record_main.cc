// hadal-record: records a running hadald's topics into a rosbag2 bag (sqlite3 storage) that `ros2 bag
// info` and `ros2 bag play` read, without ROS 2 installed (docs/ARCHITECTURE.md, "Recording").
//
//   hadal-record BAG_DIR [--domain-id N] [--topics T,...] [--use-sim-time] [--duration S] [--wait S]
//                [--security FILE]
//
// Records every topic the hadald on the domain writes but /hadal/monitor, which carries the other topics'
// samples again (--topics: only these, by ROS 2 name as /auv/odometry, the monitor too if named), each
// sample as it came over the wire. A message's bag time is its receive time (system
// clock, as `ros2 bag record`), or with --use-sim-time the sim time of the latest /clock sample (as `ros2
// bag record --use-sim-time`). The bag is flushed once per wall second, so a killed recorder loses at
// most the last second; SIGINT/SIGTERM or --duration (wall seconds) close it. Exit status 0, 1 when no
// hadald was found within --wait seconds (default 20) or writing failed, 2 on a usage error. --security: DDS
// Security with the `security:` block of FILE (docs/dds.md, "DDS Security"), to record a secure hadald.
#include "hadal/record/bag_recorder.h"
#include "hadal/record/rosbag2_writer.h"
#include "parse_number.h"
#include "security_option.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <thread>

namespace {

std::atomic<bool> g_stop{false};
extern "C" void handle_stop_signal(int) { g_stop.store(true); }

const char* const kUsage =
    "usage: hadal-record BAG_DIR [--domain-id N] [--topics T,...] [--use-sim-time] [--duration S] [--wait S]\n"
    "                    [--security FILE]\n";

[[noreturn]] void usage_error(const std::string& message) {
  std::fprintf(stderr, "hadal-record: error: %s\n%s", message.c_str(), kUsage);
  std::exit(2);
}

double parse_seconds(const std::string& option, const std::string& text) {
  double value = 0.0;
  if (!hadal::tools::parse_number(text, &value) || !(value > 0.0) || value > 1e9) {
    usage_error(option + " must be a number of seconds > 0 (got '" + text + "')");
  }
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  hadal::record::BagRecorderOptions options;
  std::string& directory = options.directory;
  int& domain = options.domain_id;
  bool domain_given = false;
  double duration_s = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) usage_error("option " + arg + " needs a value");
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--security") {
      if (const std::string error = hadal::tools::read_security_option(next(), &options.security); !error.empty()) {
        usage_error(error);
      }
    } else if (arg == "--domain-id") {
      if (const std::string error = hadal::tools::parse_domain_id(next(), &domain); !error.empty()) usage_error(error);
      domain_given = true;
    } else if (arg == "--topics") {
      std::stringstream list(next());
      for (std::string topic; std::getline(list, topic, ',');) {
        if (topic.empty() || topic[0] != '/') {
          usage_error("--topics takes ROS 2 names such as /auv/odometry (got '" + topic + "')");
        }
        options.topics.insert(topic);
      }
    } else if (arg == "--use-sim-time") {
      options.use_sim_time = true;
    } else if (arg == "--duration") {
      duration_s = parse_seconds(arg, next());
    } else if (arg == "--wait") {
      options.wait_s = parse_seconds(arg, next());
    } else if (arg.rfind("--", 0) == 0) {
      usage_error("unknown option " + arg);
    } else if (!directory.empty()) {
      usage_error("more than one bag directory given ('" + directory + "' and '" + arg + "')");
    } else {
      directory = arg;
    }
  }
  if (!domain_given) {
    if (const std::string error = hadal::tools::default_domain_id(&domain); !error.empty()) usage_error(error);
  }
  if (directory.empty()) usage_error("no bag directory given");
  if (const std::string error = hadal::record::Rosbag2Writer::existing_directory_error(directory); !error.empty()) {
    usage_error(error);
  }
  std::signal(SIGINT, handle_stop_signal);
  std::signal(SIGTERM, handle_stop_signal);

  hadal::record::BagRecorder recorder(options);
  if (const std::string error = recorder.start(); !error.empty()) {
    std::fprintf(stderr, "hadal-record: error: %s\n", error.c_str());
    return 1;
  }
  std::fprintf(stderr, "hadal-record: recording %zu topic(s) of DDS domain %d into %s\n", recorder.topic_count(),
               domain, directory.c_str());
  const auto start = std::chrono::steady_clock::now();
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (duration_s > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= duration_s) {
      break;
    }
  }
  const std::string error = recorder.stop();
  std::fprintf(stderr, "hadal-record: %llu message(s) on %zu topic(s) in %s\n",
               static_cast<unsigned long long>(recorder.message_count()), recorder.topic_count(), directory.c_str());
  if (const std::string lost = recorder.lost_samples_text(); !lost.empty()) {
    std::fprintf(stderr, "hadal-record: warning: samples lost (the recorder fell behind the writers): %s\n",
                 lost.c_str());
  }
  if (!error.empty()) {
    std::fprintf(stderr, "hadal-record: error: %s\n", error.c_str());
    return 1;
  }
  return 0;
}
