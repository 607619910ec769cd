// hadal-record: records a running hadald's topics into a rosbag2 bag (sqlite3 storage) that `ros2 bag
// info` and `ros2 bag play` read, without ROS 2 installed (docs/ARCHITECTURE.md, "Recording").
//
//   hadal-record BAG_DIR [--domain-id N] [--topics T,...] [--use-sim-time] [--duration S] [--wait S]
//
// Records every topic the hadald on the domain writes (--topics: only these, by ROS 2 name as
// /auv/odometry), each sample as it came over the wire. A message's bag time is its receive time (system
// clock, as `ros2 bag record`), or with --use-sim-time the sim time of the latest /clock sample (as `ros2
// bag record --use-sim-time`). The bag is flushed once per wall second, so a killed recorder loses at
// most the last second; SIGINT/SIGTERM or --duration (wall seconds) close it. Exit status 0, 1 when no
// hadald was found within --wait seconds (default 20) or writing failed, 2 on a usage error.
#include "hadal/record/rosbag2_writer.h"
#include "hadal/record/topic_tap.h"

#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>

namespace {

std::atomic<bool> g_stop{false};
extern "C" void handle_stop_signal(int) { g_stop.store(true); }

const char* const kUsage =
    "usage: hadal-record BAG_DIR [--domain-id N] [--topics T,...] [--use-sim-time] [--duration S] [--wait S]\n";

[[noreturn]] void usage_error(const std::string& message) {
  std::fprintf(stderr, "hadal-record: error: %s\n%s", message.c_str(), kUsage);
  std::exit(2);
}

double parse_seconds(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !(value > 0.0) || value > 1e9) {
    usage_error(option + " must be a number of seconds > 0 (got '" + text + "')");
  }
  return value;
}

// builtin_interfaces/Time in a rosgraph_msgs/Clock sample (CDR, 4-byte encapsulation header): ns.
bool clock_sample_ns(const std::vector<unsigned char>& bytes, std::int64_t* ns) {
  if (bytes.size() < 12) return false;
  const bool little = bytes[1] == 0x01;  // CDR_LE
  auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int b = 0; b < 4; ++b) {
      const std::uint32_t byte = bytes[at + static_cast<std::size_t>(little ? b : 3 - b)];
      v |= byte << (8 * b);
    }
    return v;
  };
  *ns = static_cast<std::int64_t>(static_cast<std::int32_t>(u32(4))) * 1'000'000'000LL + u32(8);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string directory;
  int domain = 0;
  if (const char* env = std::getenv("ROS_DOMAIN_ID"); env != nullptr && *env != '\0') domain = std::atoi(env);
  std::set<std::string> only;  // ROS 2 names
  bool sim_time = false;
  double duration_s = 0.0;
  double wait_s = 20.0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) usage_error("option " + arg + " needs a value");
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--domain-id") {
      const std::string value = next();
      char* end = nullptr;
      const long parsed = std::strtol(value.c_str(), &end, 10);
      if (value.empty() || end != value.c_str() + value.size() || parsed < 0 || parsed > 232) {
        usage_error("--domain-id must be an integer in 0..232 (got '" + value + "')");
      }
      domain = static_cast<int>(parsed);
    } else if (arg == "--topics") {
      std::stringstream list(next());
      for (std::string topic; std::getline(list, topic, ',');) {
        if (topic.empty() || topic[0] != '/') usage_error("--topics takes ROS 2 names such as /auv/odometry (got '" + topic + "')");
        only.insert(topic);
      }
    } else if (arg == "--use-sim-time") {
      sim_time = true;
    } else if (arg == "--duration") {
      duration_s = parse_seconds(arg, next());
    } else if (arg == "--wait") {
      wait_s = parse_seconds(arg, next());
    } else if (arg.rfind("--", 0) == 0) {
      usage_error("unknown option " + arg);
    } else if (!directory.empty()) {
      usage_error("more than one bag directory given ('" + directory + "' and '" + arg + "')");
    } else {
      directory = arg;
    }
  }
  if (directory.empty()) usage_error("no bag directory given");
  struct stat existing {};
  if (stat(directory.c_str(), &existing) == 0) {
    usage_error("bag directory " + directory + " already exists (a rosbag2 bag is never appended to)");
  }
  std::signal(SIGINT, handle_stop_signal);
  std::signal(SIGTERM, handle_stop_signal);

  auto tap = std::make_unique<hadal::record::TopicTap>(domain, "hadal_record");
  if (!tap->discover(wait_s)) {
    std::fprintf(stderr, "hadal-record: error: no hadald on DDS domain %d within %g s\n", domain, wait_s);
    return 1;
  }
  std::string error;
  std::unique_ptr<hadal::record::Rosbag2Writer> bag = hadal::record::Rosbag2Writer::create(directory, &error);
  if (!bag) {
    std::fprintf(stderr, "hadal-record: error: %s\n", error.c_str());
    return 1;
  }
  std::mutex mutex;  // the bag: written from DDS's threads, flushed from this one
  std::map<std::string, int> topic_ids;  // DDS topic -> bag topic
  for (const auto& [dds_topic, writer] : tap->writers()) {
    std::string name, type;
    if (!hadal::record::ros_topic_name(dds_topic, &name) || !hadal::record::ros_type_name(writer.type, &type)) {
      std::fprintf(stderr, "hadal-record: skipping %s (%s): not a ROS 2 topic name and type\n", dds_topic.c_str(),
                   writer.type.c_str());
      continue;
    }
    if (!only.empty() && only.count(name) == 0) continue;
    topic_ids[dds_topic] = bag->add_topic({name, type, {writer.reliable, writer.transient_local}});
  }
  if (topic_ids.empty()) {
    std::fprintf(stderr, "hadal-record: error: none of the server's topics is to be recorded\n");
    return 1;
  }
  std::int64_t sim_ns = 0;
  std::string write_error;
  const bool subscribed = tap->subscribe(
      [&](const hadal::record::TappedSample& sample) {
        std::lock_guard<std::mutex> lock(mutex);
        if (sample.topic == "rt/clock") clock_sample_ns(sample.bytes, &sim_ns);
        const auto id = topic_ids.find(sample.topic);
        if (id == topic_ids.end()) return;
        const std::int64_t stamp =
            sim_time ? sim_ns
                     : std::chrono::duration_cast<std::chrono::nanoseconds>(
                           std::chrono::system_clock::now().time_since_epoch())
                           .count();
        if (!bag->write(id->second, stamp, sample.bytes.data(), sample.bytes.size()) && write_error.empty()) {
          write_error = bag->error();
        }
      },
      wait_s, /*kept_samples=*/true);
  if (!subscribed) std::fprintf(stderr, "hadal-record: warning: not every topic matched its writer within %g s\n", wait_s);
  std::fprintf(stderr, "hadal-record: recording %zu topic(s) of DDS domain %d into %s\n", topic_ids.size(), domain,
               directory.c_str());

  const auto start = std::chrono::steady_clock::now();
  auto last_flush = start;
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const auto now = std::chrono::steady_clock::now();
    if (duration_s > 0.0 && std::chrono::duration<double>(now - start).count() >= duration_s) break;
    if (now - last_flush >= std::chrono::seconds(1)) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!bag->flush() && write_error.empty()) write_error = bag->error();
      last_flush = now;
    }
  }
  tap->drain();
  tap.reset();  // no sample comes after this
  bag->close();
  std::fprintf(stderr, "hadal-record: %llu message(s) on %zu topic(s) in %s\n",
               static_cast<unsigned long long>(bag->message_count()), topic_ids.size(), directory.c_str());
  if (!write_error.empty()) {
    std::fprintf(stderr, "hadal-record: error: %s\n", write_error.c_str());
    return 1;
  }
  return 0;
}
