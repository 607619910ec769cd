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
#include "hadal/dds/domain_id.h"
#include "hadal/record/bag_recorder.h"
#include "hadal/record/rosbag2_writer.h"
#include "cli_args.h"
#include "parse_number.h"
#include "security_option.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>

namespace {

std::atomic<bool> g_stop{false};
extern "C" void handle_stop_signal(int) { g_stop.store(true); }

const char* const kUsage =
    "usage: hadal-record BAG_DIR [--domain-id N] [--topics T,...] [--use-sim-time] [--duration S] [--wait S]\n"
    "                    [--security FILE]\n";

// "" when `text` is a number of seconds in (0, 1e9] (into *out), else the usage error.
std::string read_seconds(const std::string& option, const std::string& text, double* out) {
  const hadal::tools::NumberRange range = hadal::tools::NumberRange::left_open(0.0, 1e9);
  double value = 0.0;
  if (!hadal::tools::parse_number(text, &value) || !range.contains(value)) {
    return option + " must be a number of seconds > 0 (got '" + text + "')";
  }
  *out = value;
  return "";
}

// --topics T,...: ROS 2 names into *topics; "" when every one is such a name, else the usage error.
std::string read_topics(const std::string& text, std::set<std::string>* topics) {
  std::stringstream list(text);
  for (std::string topic; std::getline(list, topic, ',');) {
    if (topic.empty() || topic[0] != '/') {
      return "--topics takes ROS 2 names such as /auv/odometry (got '" + topic + "')";
    }
    topics->insert(topic);
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  hadal::record::BagRecorderOptions options;
  std::string& directory = options.directory;
  int& domain = options.domain_id;
  bool domain_given = false;
  double duration_s = 0.0;
  hadal::tools::CommandLine command_line("hadal-record", kUsage);
  command_line.error_prefix("error: ")
      .missing_value_words("option %s needs a value")
      .unknown_words("unknown option %s")
      .option_syntax(hadal::tools::OptionSyntax::kDoubleDash)
      .option("--security",
              [&](const std::string& value) { return hadal::tools::read_security_option(value, &options.security); })
      .option("--domain-id",
              [&](const std::string& value) {
                domain_given = true;
                return hadal::dds::read_domain_id_option(value, &domain);
              })
      .option("--topics", [&](const std::string& value) { return read_topics(value, &options.topics); })
      .flag("--use-sim-time", [&] { options.use_sim_time = true; })
      .option("--duration", [&](const std::string& value) { return read_seconds("--duration", value, &duration_s); })
      .option("--wait", [&](const std::string& value) { return read_seconds("--wait", value, &options.wait_s); })
      .one_positional(&directory, "more than one bag directory given ('%s' and '%s')");
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (!domain_given) {
    if (const std::string error = hadal::dds::domain_id_from_environment(std::getenv("ROS_DOMAIN_ID"), &domain); !error.empty()) {
      return command_line.usage_error(error);
    }
  }
  if (directory.empty()) return command_line.usage_error("no bag directory given");
  if (const std::string error = hadal::record::Rosbag2Writer::existing_directory_error(directory); !error.empty()) {
    return command_line.usage_error(error);
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
