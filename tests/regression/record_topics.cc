// hadal-record-topics: steps a lockstep hadald and records a digest of every topic it publishes, byte
// for byte (tests/regression/README.md).
//
// The recorder knows no message type: it discovers the server's writers (topic and DDS type name, from
// the participant named "hadald"), registers an opaque type under each type name and reads the raw
// serialized samples (CDR, encapsulation header included). Per topic it keeps the sample count and an
// FNV-1a 64 hash over (le64 length || bytes) of each sample in writer order, and checks that the
// writer's sequence numbers arrive without a gap from 1 on, so a lost sample is an error, never a
// silently different digest. Nothing here depends on the server's code, so a digest recorded before a
// refactoring is comparable with one recorded after it.
//
//   hadal-record-topics --domain D --steps N [--chunk K] [--command VEHICLE@STEP=v1,v2,...]...
//                       [--exclude TOPIC]... [--out FILE]
//
// Steps the server in requests of K steps (default 5: at 500 Hz no topic publishes more than once per
// request, so the writers' KEEP_LAST histories never overflow). A --command is attached to the request
// that starts at STEP (hadal::Client::set_thrusters). rt/hadal/status (wall clock) and
// rt/hadal/step_reply (the client's random request ids) are always excluded.
// Output, one line per topic, sorted: `topic type count hash`. Exit status 0 on success, 1 on a gap, a
// refused step or a timeout, 2 on a usage error.
#include "hadal/dds/participant.h"
#include "hadal_client/client.h"

#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;
using Clock = std::chrono::steady_clock;

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ULL;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ULL;

std::uint64_t fnv1a(std::uint64_t h, const unsigned char* bytes, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ bytes[i]) * kFnvPrime;
  return h;
}

// A sample as the bytes on the wire.
using Bytes = std::vector<unsigned char>;

// A type that (de)serializes nothing but copies the payload, registered under another type's name.
class OpaqueType : public fdds::TopicDataType {
 public:
  explicit OpaqueType(const std::string& name) {
    setName(name.c_str());
    m_typeSize = 1u << 20;
    m_isGetKeyDefined = false;
    auto_fill_type_object(false);
    auto_fill_type_information(false);
  }
  bool serialize(void* data, rtps::SerializedPayload_t* payload) override {
    const Bytes& bytes = *static_cast<Bytes*>(data);
    if (bytes.size() > payload->max_size) return false;
    std::copy(bytes.begin(), bytes.end(), payload->data);
    payload->length = static_cast<std::uint32_t>(bytes.size());
    return true;
  }
  bool deserialize(rtps::SerializedPayload_t* payload, void* data) override {
    static_cast<Bytes*>(data)->assign(payload->data, payload->data + payload->length);
    return true;
  }
  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
    return [data] { return static_cast<std::uint32_t>(static_cast<Bytes*>(data)->size()); };
  }
  void* createData() override { return new Bytes(); }
  void deleteData(void* data) override { delete static_cast<Bytes*>(data); }
  bool getKey(void*, rtps::InstanceHandle_t*, bool) override { return false; }
};

struct TopicRecord {
  std::string type;
  std::uint64_t count = 0;
  std::uint64_t hash = kFnvOffset;
  std::int64_t last_sequence = 0;  // writer sequence number of the last sample
  std::string error;
};

// DomainParticipantListener is also a DataReaderListener (through SubscriberListener).
struct Recorder : public fdds::DomainParticipantListener {
  std::mutex mutex;
  // The status is a wall-clock heartbeat; a step reply echoes the client's request id, which
  // hadal::Client draws at random (its sim time and step count are the clock's).
  std::set<std::string> excluded{"rt/hadal/status", "rt/hadal/step_reply"};
  rtps::GuidPrefix_t server_prefix;
  bool server_seen = false;
  std::map<std::string, std::string> writers;       // topic -> type of the server's writers
  std::map<fdds::DataReader*, std::string> topic_of;  // reader -> topic
  std::map<std::string, TopicRecord> records;
  Clock::time_point last_change = Clock::now();

  void on_participant_discovery(fdds::DomainParticipant*, rtps::ParticipantDiscoveryInfo&& info) override {
    if (info.status != rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT) return;
    if (info.info.m_participantName.to_string() != "hadald") return;
    std::lock_guard<std::mutex> lock(mutex);
    server_prefix = info.info.m_guid.guidPrefix;
    server_seen = true;
    last_change = Clock::now();
  }

  void on_publisher_discovery(fdds::DomainParticipant*, rtps::WriterDiscoveryInfo&& info) override {
    if (info.status != rtps::WriterDiscoveryInfo::DISCOVERED_WRITER) return;
    std::lock_guard<std::mutex> lock(mutex);
    if (!server_seen || info.info.guid().guidPrefix != server_prefix) return;
    const std::string topic = info.info.topicName().to_string();
    if (excluded.count(topic) > 0) return;
    writers[topic] = info.info.typeName().to_string();
    last_change = Clock::now();
  }

  void on_data_available(fdds::DataReader* reader) override {
    Bytes bytes;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&bytes, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      std::lock_guard<std::mutex> lock(mutex);
      TopicRecord& record = records[topic_of[reader]];
      const std::int64_t sequence = static_cast<std::int64_t>(info.sample_identity.sequence_number().to64long());
      if (record.error.empty() && sequence != record.last_sequence + 1) {
        record.error = "writer sequence number " + std::to_string(sequence) + " after " +
                       std::to_string(record.last_sequence) + " (a sample was lost)";
      }
      record.last_sequence = sequence;
      unsigned char length[8];
      for (int b = 0; b < 8; ++b) length[b] = static_cast<unsigned char>(static_cast<std::uint64_t>(bytes.size()) >> (8 * b));
      record.hash = fnv1a(fnv1a(record.hash, length, 8), bytes.data(), bytes.size());
      ++record.count;
      last_change = Clock::now();
    }
  }
};

struct Command {
  std::string vehicle;
  std::uint64_t step = 0;
  std::vector<double> setpoints;
};

[[noreturn]] void usage_error(const std::string& message) {
  std::fprintf(stderr,
               "hadal-record-topics: %s\nusage: hadal-record-topics --domain D --steps N [--chunk K] "
               "[--command VEHICLE@STEP=v1,v2,...]... [--exclude TOPIC]... [--out FILE]\n",
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

bool wait_for(const std::function<bool()>& condition, double timeout_s) {
  const Clock::time_point end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                   std::chrono::duration<double>(timeout_s));
  while (!condition()) {
    if (Clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

int main(int argc, char** argv) {
  int domain = -1;
  std::uint64_t steps = 0, chunk = 5;
  std::vector<Command> commands;
  std::string out_path;
  Recorder recorder;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) usage_error(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--domain") {
      domain = std::stoi(next());
    } else if (arg == "--steps") {
      steps = std::stoull(next());
    } else if (arg == "--chunk") {
      chunk = std::stoull(next());
    } else if (arg == "--command") {
      commands.push_back(parse_command(next()));
    } else if (arg == "--exclude") {
      recorder.excluded.insert(next());
    } else if (arg == "--out") {
      out_path = next();
    } else {
      usage_error("unknown argument " + arg);
    }
  }
  if (domain < 0 || steps == 0 || chunk == 0) usage_error("--domain and --steps are required");

  fdds::DomainParticipant* participant = hadal::dds::create_participant(domain, "hadal_record_topics");
  participant->set_listener(&recorder, fdds::StatusMask::none());
  hadal::Client client(hadal::ClientOptions{domain, "hadal_record_topics_client"});
  int status = 0;
  {
    if (!client.wait_for_server(20.0)) {
      std::fprintf(stderr, "hadal-record-topics: no hadald on domain %d\n", domain);
      return 1;
    }
    // The server creates every writer before it runs: wait until its set stops growing.
    wait_for([&] {
      std::lock_guard<std::mutex> lock(recorder.mutex);
      return !recorder.writers.empty() && seconds_since(recorder.last_change) > 1.0;
    }, 20.0);
    fdds::Subscriber* subscriber = participant->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    std::vector<fdds::DataReader*> readers;
    std::map<std::string, std::string> writers;
    {
      std::lock_guard<std::mutex> lock(recorder.mutex);
      writers = recorder.writers;
    }
    for (const auto& [topic_name, type_name] : writers) {
      if (participant->find_type(type_name).empty()) {
        fdds::TypeSupport(new OpaqueType(type_name)).register_type(participant);
      }
      fdds::Topic* topic = participant->create_topic(topic_name, type_name, fdds::TOPIC_QOS_DEFAULT);
      fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
      qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
      qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
      qos.history().kind = fdds::KEEP_ALL_HISTORY_QOS;
      qos.endpoint().history_memory_policy = rtps::DYNAMIC_RESERVE_MEMORY_MODE;
      {
        std::lock_guard<std::mutex> lock(recorder.mutex);
        recorder.records[topic_name].type = type_name;
      }
      // The listener only once the reader is known, so every sample finds its topic.
      fdds::DataReader* reader = subscriber->create_datareader(topic, qos, nullptr, fdds::StatusMask::none());
      {
        std::lock_guard<std::mutex> lock(recorder.mutex);
        recorder.topic_of[reader] = topic_name;
      }
      reader->set_listener(&recorder, fdds::StatusMask::data_available());
      readers.push_back(reader);
    }
    const bool matched = wait_for([&] {
      for (fdds::DataReader* reader : readers) {
        fdds::SubscriptionMatchedStatus matched_status;
        reader->get_subscription_matched_status(matched_status);
        if (matched_status.current_count < 1) return false;
      }
      return true;
    }, 20.0);
    if (!matched) {
      std::fprintf(stderr, "hadal-record-topics: not every topic matched the server's writer\n");
      return 1;
    }
    try {
      for (std::uint64_t step = 0; step < steps;) {
        for (const Command& command : commands) {
          if (command.step == step) client.set_thrusters(command.vehicle, command.setpoints);
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
    wait_for([&] {
      std::lock_guard<std::mutex> lock(recorder.mutex);
      return seconds_since(recorder.last_change) > 1.0;
    }, 30.0);
    for (fdds::DataReader* reader : readers) recorder.on_data_available(reader);

    std::ostringstream text;
    std::lock_guard<std::mutex> lock(recorder.mutex);
    for (const auto& [topic, record] : recorder.records) {
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
  }
  participant->set_listener(nullptr);
  hadal::dds::delete_participant(participant);
  return status;
}
