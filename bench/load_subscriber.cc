// One subscriber of the load benchmark (bench/load.py, docs/benchmarks.md "Soak and load"): joins a DDS domain, finds the
// hadald on it, reads every topic it writes with a reliable keep-all reader (hadal::record::TopicTap: raw
// samples, any type) and counts, per topic, the samples, the bytes and the gaps in the writer's sequence
// numbers (a sample the writer dropped from its history before this reader had it: lost). It stops once
// nothing has arrived for --quiet seconds after the first sample (the server has ended), and prints one
// JSON object:
//   {"topics": {"rt/auv/imu": {"samples": N, "bytes": B, "first": 1, "last": N, "lost": 0}, ...},
//    "ready_s": wall seconds until every reader matched}
//
//   hadal_bench_load_subscriber --domain-id D [--quiet S] [--ready-file PATH]
//
// --ready-file: written once every reader has matched its writer (the driver starts the run then).
#include "hadal/record/topic_tap.h"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace {

struct TopicCount {
  hadal::record::SequenceGaps sequence;  // first 1: nothing missed before matching; lost: skipped after the first
  std::uint64_t bytes = 0;
};

int usage() {
  std::fprintf(stderr, "usage: hadal_bench_load_subscriber --domain-id D [--quiet SECONDS] [--ready-file PATH]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  int domain = -1;
  double quiet_s = 3.0;
  std::string ready_file;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--domain-id") domain = std::atoi(argv[i + 1]);
    else if (arg == "--quiet") quiet_s = std::atof(argv[i + 1]);
    else if (arg == "--ready-file") ready_file = argv[i + 1];
    else return usage();
  }
  if (domain < 0 || argc % 2 == 0) return usage();

  const auto start = std::chrono::steady_clock::now();
  // Declared before the tap, whose callback uses them: destroyed after it (record/topic_tap.h).
  std::mutex mutex;
  std::map<std::string, TopicCount> counts;
  hadal::record::TopicTap tap(domain, "hadal_load_subscriber");
  if (!tap.discover(120.0)) {
    std::fprintf(stderr, "hadal_bench_load_subscriber: no hadald on domain %d\n", domain);
    return 1;
  }
  for (const auto& [topic, writer] : tap.writers()) counts[topic];
  const bool matched = tap.subscribe(
      [&](const hadal::record::TappedSample& sample) {
        std::lock_guard<std::mutex> lock(mutex);
        TopicCount& c = counts[sample.topic];
        c.sequence.add(sample.sequence);
        c.bytes += sample.bytes.size();
      },
      120.0);
  const double ready_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!matched) {
    std::fprintf(stderr, "hadal_bench_load_subscriber: not every reader matched its writer\n");
    return 1;
  }
  if (!ready_file.empty()) std::ofstream(ready_file) << ready_s << "\n";

  // Until the server has published and then gone quiet.
  while (true) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    bool any = false;
    {
      std::lock_guard<std::mutex> lock(mutex);
      for (const auto& [topic, c] : counts) any |= c.sequence.samples > 0;
    }
    if (any && tap.seconds_quiet() > quiet_s) break;
  }
  tap.drain();
  std::lock_guard<std::mutex> lock(mutex);
  std::printf("{\"ready_s\": %.3f, \"topics\": {", ready_s);
  bool first = true;
  for (const auto& [topic, c] : counts) {
    std::printf("%s\"%s\": {\"samples\": %llu, \"bytes\": %llu, \"first\": %lld, \"last\": %lld, \"lost\": %llu}",
                first ? "" : ", ", topic.c_str(), static_cast<unsigned long long>(c.sequence.samples),
                static_cast<unsigned long long>(c.bytes), static_cast<long long>(c.sequence.first),
                static_cast<long long>(c.sequence.last), static_cast<unsigned long long>(c.sequence.lost));
    first = false;
  }
  std::printf("}}\n");
  return 0;
}
