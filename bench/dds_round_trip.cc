// The bare Fast DDS round trip (issue 45, docs/benchmarks.md "Lockstep round trip and the Python client"): what a
// lockstep step(1) would cost with no physics, no Python and no message building. Two processes on one domain, with
// hadald's participant and endpoint set-up (dds/participant.h, dds/topic_registry.h: shared memory, reliable): this
// one writes a `--bytes` sample (hadal_msgs/MonitorSample's byte sequence) on rt/bench/ping and waits for its echo on
// rt/bench/pong; a child process echoes each sample it reads. Prints one JSON object:
//   {"benchmark": "dds_round_trip", "bytes": B, "round_trips": N, "wall_s": W, "round_trips_per_s": R, "us_each": U}
//
//   hadal_bench_dds_round_trip [--seconds 5] [--bytes 1024] [--domain-id 230]
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <hadal_msgsPubSubTypes.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "hadal/dds/participant.h"
#include "hadal/dds/topic_registry.h"

namespace {

namespace fdds = eprosima::fastdds::dds;
using Sample = hadal_msgs::msg::MonitorSample;
using SampleType = hadal_msgs::msg::MonitorSamplePubSubType;

// Calls `on_sample` with each sample the reader takes, on the DDS thread.
class Taker : public fdds::DataReaderListener {
 public:
  template <class F>
  explicit Taker(F f) : on_sample_(std::move(f)) {}
  void on_data_available(fdds::DataReader* reader) override {
    fdds::SampleInfo info;
    while (reader->take_next_sample(&sample_, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) on_sample_(sample_);
    }
  }

 private:
  std::function<void(const Sample&)> on_sample_;
  Sample sample_;
};

bool wait_matched(fdds::DataWriter* writer, fdds::DataReader* reader, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    fdds::PublicationMatchedStatus w;
    fdds::SubscriptionMatchedStatus r;
    writer->get_publication_matched_status(w);
    reader->get_subscription_matched_status(r);
    if (w.current_count > 0 && r.current_count > 0) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

int echo(int domain) {
  fdds::DomainParticipant* participant = hadal::dds::create_participant(domain, "hadal_bench_echo");
  {
    hadal::dds::TopicRegistry registry(participant);
    fdds::DataWriter* pong = registry.writer<SampleType>("rt/bench/pong", 1);
    Taker taker([pong](const Sample& s) { pong->write(const_cast<Sample*>(&s)); });
    registry.reader<SampleType>("rt/bench/ping", 1, &taker);
    pause();  // until the parent's SIGTERM
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 5.0;
  int bytes = 1024, domain = 230;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--seconds") seconds = std::atof(argv[i + 1]);
    else if (arg == "--bytes") bytes = std::atoi(argv[i + 1]);
    else if (arg == "--domain-id") domain = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: hadal_bench_dds_round_trip [--seconds S] [--bytes B] [--domain-id D]\n");
      return 2;
    }
  }
  if (argc % 2 == 0 || !(seconds > 0.0) || bytes < 0) {
    std::fprintf(stderr, "usage: hadal_bench_dds_round_trip [--seconds S] [--bytes B] [--domain-id D]\n");
    return 2;
  }
  const pid_t child = fork();
  if (child < 0) return 1;
  if (child == 0) {
    signal(SIGTERM, [](int) { _exit(0); });
    return echo(domain);
  }
  int status = 1;
  fdds::DomainParticipant* participant = hadal::dds::create_participant(domain, "hadal_bench_ping");
  {
    hadal::dds::TopicRegistry registry(participant);
    std::mutex mutex;
    std::condition_variable changed;
    std::uint64_t echoed = 0;
    Taker taker([&](const Sample& s) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        echoed = s.count();
      }
      changed.notify_one();
    });
    fdds::DataWriter* ping = registry.writer<SampleType>("rt/bench/ping", 1);
    fdds::DataReader* pong = registry.reader<SampleType>("rt/bench/pong", 1, &taker);
    if (wait_matched(ping, pong, 30.0)) {
      Sample sample;
      sample.cdr().assign(static_cast<std::size_t>(bytes), 0x5a);
      std::uint64_t n = 0;
      const auto round_trip = [&] {
        sample.count(++n);
        ping->write(&sample);
        std::unique_lock<std::mutex> lock(mutex);
        return changed.wait_for(lock, std::chrono::seconds(5), [&] { return echoed == n; });
      };
      bool ok = true;
      for (int k = 0; k < 100 && ok; ++k) ok = round_trip();  // warm up
      const std::uint64_t first = n;
      const auto start = std::chrono::steady_clock::now();
      double wall = 0.0;
      while (ok && wall < seconds) {
        ok = round_trip();
        wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }
      if (ok) {
        const double trips = static_cast<double>(n - first);
        std::printf("{\"benchmark\": \"dds_round_trip\", \"bytes\": %d, \"round_trips\": %.0f, \"wall_s\": %.3f, "
                    "\"round_trips_per_s\": %.1f, \"us_each\": %.2f}\n",
                    bytes, trips, wall, trips / wall, 1e6 * wall / trips);
        status = 0;
      } else {
        std::fprintf(stderr, "hadal_bench_dds_round_trip: an echo did not come back within 5 s\n");
      }
    } else {
      std::fprintf(stderr, "hadal_bench_dds_round_trip: the echo process did not match within 30 s\n");
    }
    kill(child, SIGTERM);
    waitpid(child, nullptr, 0);
  }
  hadal::dds::delete_participant(participant);
  return status;
}
