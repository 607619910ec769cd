// hadal-record-topics: steps a lockstep hadald and records a digest of every topic it publishes, byte
// for byte (tests/regression/README.md).
//
// The recorder knows no message type: through hadal::record::TopicTap it discovers the server's writers
// (topic and DDS type name, from the participant named "hadald"), registers an opaque type under each
// type name and reads the raw serialized samples (CDR, encapsulation header included). Per topic it keeps the sample count and an
// FNV-1a 64 hash over (le64 length || bytes) of each sample in writer order, and checks that the
// writer's sequence numbers arrive without a gap from 1 on, so a lost sample is an error, never a
// silently different digest. Nothing here depends on the server's code, so a digest recorded before a
// refactoring is comparable with one recorded after it.
//
//   hadal-record-topics --domain-id D --steps N [--chunk K] [--command VEHICLE@STEP=v1,v2,...]...
//                       [--packet VEHICLE/MODEM@STEP=DESTINATION:TEXT]... [--exclude TOPIC]... [--out FILE]
//
// Steps the server in requests of K steps (default 5: at 500 Hz no topic publishes more than once per
// request, so the writers' KEEP_LAST histories never overflow). A --command is attached to the request
// that starts at STEP (hadal::Client::set_commands); a --packet is an acoustic modem packet carrying TEXT's bytes, attached to it
// (hadal::Client::attach_packet). rt/hadal/status (wall clock) and
// rt/hadal/step_reply (the client's random request ids) are always excluded.
// Output, one line per topic, sorted: `topic type count hash`. Exit status 0 on success, 1 on a gap, a
// refused step or a timeout, 2 on a usage error.
#include "hadal/record/topic_tap.h"
#include "hadal_client/client.h"

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ULL;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ULL;

std::uint64_t fnv1a(std::uint64_t h, const unsigned char* bytes, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ bytes[i]) * kFnvPrime;
  return h;
}

struct TopicRecord {
  std::string type;
  std::uint64_t count = 0;
  std::uint64_t hash = kFnvOffset;
  std::int64_t last_sequence = 0;  // writer sequence number of the last sample
  std::string error;
};

// Per topic: count, hash and the sequence check of the samples the tap hands over (one at a time).
void digest(std::map<std::string, TopicRecord>& records, const hadal::record::TappedSample& sample) {
  TopicRecord& record = records[sample.topic];
  if (record.error.empty() && sample.sequence != record.last_sequence + 1) {
    record.error = "writer sequence number " + std::to_string(sample.sequence) + " after " +
                   std::to_string(record.last_sequence) + " (a sample was lost)";
  }
  record.last_sequence = sample.sequence;
  unsigned char length[8];
  const auto size = static_cast<std::uint64_t>(sample.bytes.size());
  for (int b = 0; b < 8; ++b) length[b] = static_cast<unsigned char>(size >> (8 * b));
  record.hash = fnv1a(fnv1a(record.hash, length, 8), sample.bytes.data(), sample.bytes.size());
  ++record.count;
}

struct Command {
  std::string vehicle;
  std::uint64_t step = 0;
  std::vector<double> setpoints;
  // A --packet instead: the modem, the destination and the payload.
  std::string modem, destination, text;
  bool packet = false;
};

[[noreturn]] void usage_error(const std::string& message) {
  std::fprintf(stderr,
               "hadal-record-topics: %s\nusage: hadal-record-topics --domain-id D --steps N [--chunk K] "
               "[--command VEHICLE@STEP=v1,v2,...]... [--packet VEHICLE/MODEM@STEP=DESTINATION:TEXT]... "
               "[--exclude TOPIC]... [--out FILE]\n",
               message.c_str());
  std::exit(2);
}

Command parse_command(const std::string& text) {
  const auto at = text.find('@');
  const auto eq = text.find('=');
  if (at == std::string::npos || eq == std::string::npos || eq < at) usage_error("bad --command " + text);
  Command command;
  command.vehicle = text.substr(0, at);
  command.step = std::stoull(text.substr(at + 1, eq - at - 1));
  std::stringstream values(text.substr(eq + 1));
  for (std::string value; std::getline(values, value, ',');) command.setpoints.push_back(std::stod(value));
  return command;
}

Command parse_packet(const std::string& text) {
  const auto slash = text.find('/');
  const auto at = text.find('@');
  const auto eq = text.find('=');
  const auto colon = text.find(':', eq == std::string::npos ? 0 : eq);
  if (slash == std::string::npos || at == std::string::npos || eq == std::string::npos || colon == std::string::npos ||
      !(slash < at && at < eq && eq < colon)) {
    usage_error("bad --packet " + text);
  }
  Command command;
  command.packet = true;
  command.vehicle = text.substr(0, slash);
  command.modem = text.substr(slash + 1, at - slash - 1);
  command.step = std::stoull(text.substr(at + 1, eq - at - 1));
  command.destination = text.substr(eq + 1, colon - eq - 1);
  command.text = text.substr(colon + 1);
  return command;
}

bool wait_for(const std::function<bool()>& condition, double timeout_s) {
  const Clock::time_point end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                   std::chrono::duration<double>(timeout_s));
  while (!condition()) {
    if (Clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  int domain = -1;
  std::uint64_t steps = 0, chunk = 5;
  std::vector<Command> commands;
  std::string out_path;
  // The status is a wall-clock heartbeat; a step reply echoes the client's request id, which
  // hadal::Client draws at random (its sim time and step count are the clock's).
  std::set<std::string> excluded{"rt/hadal/status", "rt/hadal/step_reply"};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) usage_error(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--domain") {
      usage_error("--domain is now --domain-id");
    } else if (arg == "--domain-id") {
      domain = std::stoi(next());
    } else if (arg == "--steps") {
      steps = std::stoull(next());
    } else if (arg == "--chunk") {
      chunk = std::stoull(next());
    } else if (arg == "--command") {
      commands.push_back(parse_command(next()));
    } else if (arg == "--packet") {
      commands.push_back(parse_packet(next()));
    } else if (arg == "--exclude") {
      excluded.insert(next());
    } else if (arg == "--out") {
      out_path = next();
    } else {
      usage_error("unknown argument " + arg);
    }
  }
  if (domain < 0 || steps == 0 || chunk == 0) usage_error("--domain-id and --steps are required");

  // What the tap's callback writes into, declared before the tap: destroyed after it, so that no sample still
  // arriving can reach it destroyed (record/topic_tap.h).
  std::map<std::string, TopicRecord> records;
  hadal::record::TopicTap tap(domain, "hadal_record_topics", excluded);
  hadal::Client client(hadal::ClientOptions{domain, "hadal_record_topics_client"});
  if (!client.wait_for_server(20.0)) {
    std::fprintf(stderr, "hadal-record-topics: no hadald on domain %d\n", domain);
    return 1;
  }
  // The server creates every writer before it runs: wait until its set stops growing.
  tap.discover(20.0);
  // Camera previews and the monitor are paced in wall time (dds/image_preview.h, dds/monitor.h): not part of a
  // run's output; unread, they are not even written.
  const auto recorded = [](const std::string& topic, const hadal::record::TappedWriter&) {
    const std::string preview = "/preview";
    const bool is_preview =
        topic.size() >= preview.size() && topic.compare(topic.size() - preview.size(), preview.size(), preview) == 0;
    return topic != "rt/hadal/monitor" && topic != "rt/hadal/acoustic_links" && !is_preview;
  };
  for (const auto& [topic, writer] : tap.writers()) {
    if (recorded(topic, writer)) records[topic].type = writer.type;
  }
  // Kept samples too: rt/hadal/scene is written once, when the server starts, before anyone joins.
  if (!tap.subscribe([&](const hadal::record::TappedSample& sample) { digest(records, sample); }, 20.0, true,
                     recorded)) {
    std::fprintf(stderr, "hadal-record-topics: not every topic matched the server's writer\n");
    return 1;
  }
  try {
    for (std::uint64_t step = 0; step < steps;) {
      for (const Command& command : commands) {
        if (command.step != step) continue;
        if (command.packet) {
          client.attach_packet(command.vehicle, command.modem, {command.text.begin(), command.text.end()},
                               command.destination);
        } else {
          client.set_commands(command.vehicle, command.setpoints);
        }
      }
      std::uint64_t n = std::min(chunk, steps - step);
      for (const Command& command : commands) {  // a request ends where the next command starts
        if (command.step > step && command.step < step + n) n = command.step - step;
      }
      client.step(static_cast<std::uint32_t>(n));
      step += n;
    }
  } catch (const hadal::ClientError& e) {
    std::fprintf(stderr, "hadal-record-topics: %s\n", e.what());
    return 1;
  }
  // Everything was written before the last reply; wait until the last samples are in, then take
  // whatever a reader holds without having signalled it.
  wait_for([&] { return tap.seconds_quiet() > 1.0; }, 30.0);
  tap.drain();

  int status = 0;
  std::ostringstream text;
  for (const auto& [topic, record] : records) {
    char hash[17];
    std::snprintf(hash, sizeof(hash), "%016" PRIx64, record.hash);
    text << topic << " " << record.type << " " << record.count << " " << hash << "\n";
    if (!record.error.empty()) {
      std::fprintf(stderr, "hadal-record-topics: %s: %s\n", topic.c_str(), record.error.c_str());
      status = 1;
    }
  }
  if (out_path.empty()) {
    std::fputs(text.str().c_str(), stdout);
  } else {
    std::ofstream(out_path) << text.str();
  }
  return status;
}
