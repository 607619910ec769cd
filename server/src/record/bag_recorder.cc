#include "hadal/record/bag_recorder.h"

#include "hadal/dds/topic_names.h"
#include "hadal/record/rosbag2_writer.h"
#include "hadal/record/topic_tap.h"

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

namespace hadal::record {

namespace {

// builtin_interfaces/Time in a rosgraph_msgs/Clock sample (CDR, 4-byte encapsulation header), in ns.
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

// Whether a hadald type begins with a builtin_interfaces/Time at the start of its CDR body: a std_msgs/Header
// (every type hadald publishes but the step reply) or a rosgraph_msgs/Clock.
bool starts_with_stamp(const std::string& dds_type) {
  if (dds_type == "hadal_msgs::msg::dds_::StepReply_" || dds_type == "hadal_msgs::msg::dds_::StepRequest_") {
    return false;
  }
  for (const char* package : {"sensor_msgs::", "nav_msgs::", "geometry_msgs::", "marine_acoustic_msgs::",
                              "hadal_msgs::", "rosgraph_msgs::msg::dds_::Clock_"}) {
    if (dds_type.rfind(package, 0) == 0) return true;
  }
  return false;
}

}  // namespace

struct BagRecorder::Impl {
  BagRecorderOptions options;
  std::unique_ptr<TopicTap> tap;
  std::unique_ptr<Rosbag2Writer> bag;
  mutable std::mutex mutex;  // the bag: written from DDS's threads, flushed from the flusher
  std::map<std::string, int> topic_ids;  // DDS topic -> bag topic
  std::set<std::string> stamped;          // DDS topics whose samples begin with their stamp (starts_with_stamp)
  std::int64_t sim_ns = 0;
  std::string write_error;
  std::thread flusher;
  std::condition_variable wake;
  bool stopping = false;
  bool stopped = false;
  std::uint64_t final_count = 0;
  std::map<std::string, SequenceGaps> sequences;  // DDS topic -> what was read of its writer

  void on_sample(const TappedSample& sample) {
    std::lock_guard<std::mutex> lock(mutex);
    if (sample.topic == "rt/clock") clock_sample_ns(sample.bytes, &sim_ns);
    const auto id = topic_ids.find(sample.topic);
    if (id == topic_ids.end() || !bag) return;
    // A writer keeps its last few samples only: one the recorder had not read before the writer dropped it
    // is missing from the bag, which must be said rather than left for the reader of the bag to find.
    sequences[sample.topic].add(sample.sequence);
    // Sim time: a sample's own stamp where it has one, so that its bag time does not depend on the order in which
    // the recorder happens to receive the topics (a sample repaired after a loss comes after later clocks);
    // else the latest /clock.
    std::int64_t own_ns = 0;
    const std::int64_t stamp = !options.use_sim_time ? std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                           std::chrono::system_clock::now().time_since_epoch())
                                                           .count()
                               : stamped.count(sample.topic) && clock_sample_ns(sample.bytes, &own_ns) ? own_ns
                                                                                                      : sim_ns;
    if (!bag->write(id->second, stamp, sample.bytes.data(), sample.bytes.size()) && write_error.empty()) {
      write_error = bag->error();
    }
  }

  void flush_every_second() {
    std::unique_lock<std::mutex> lock(mutex);
    while (!stopping) {
      wake.wait_for(lock, std::chrono::seconds(1));
      if (stopping) break;
      if (!bag->flush() && write_error.empty()) write_error = bag->error();
    }
  }
};

BagRecorder::BagRecorder(BagRecorderOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
}

BagRecorder::~BagRecorder() { stop(); }

std::string BagRecorder::start() {
  Impl& d = *impl_;
  // Before the search for a hadald, which may take wait_s.
  if (std::string error = Rosbag2Writer::existing_directory_error(d.options.directory); !error.empty()) return error;
  try {
    d.tap = std::make_unique<TopicTap>(d.options.domain_id, d.options.participant_name, std::set<std::string>{},
                                       d.options.security);
  } catch (const std::runtime_error& e) {  // a participant that cannot be made (security files Fast DDS refuses)
    return e.what();
  }
  if (!d.tap->discover(d.options.wait_s, 0.5)) {
    char seconds[32];
    std::snprintf(seconds, sizeof(seconds), "%g", d.options.wait_s);
    return "no hadald on DDS domain " + std::to_string(d.options.domain_id) + " within " + seconds + " s";
  }
  std::string error;
  std::unique_ptr<Rosbag2Writer> bag = Rosbag2Writer::create(d.options.directory, &error);
  if (!bag) return error;
  std::map<std::string, int> topic_ids;
  for (const auto& [dds_topic, writer] : d.tap->writers()) {
    std::string name, type;
    if (!dds::ros_topic_name(dds_topic, &name) || !dds::ros_type_name(writer.type, &type)) {
      std::fprintf(stderr, "hadal-record: skipping %s (%s): not a ROS 2 topic name and type\n", dds_topic.c_str(),
                   writer.type.c_str());
      continue;
    }
    // Every topic, but the monitor (rt/hadal/monitor) unless named: it carries the others' samples again, and
    // reading it would make the server write it.
    if (d.options.topics.empty() ? dds_topic == dds::monitor_topic() : d.options.topics.count(name) == 0) continue;
    const int id = bag->add_topic({name, type, {writer.reliable, writer.transient_local}});
    if (id < 0) return bag->error();
    topic_ids[dds_topic] = id;
    if (starts_with_stamp(writer.type)) d.stamped.insert(dds_topic);
  }
  if (topic_ids.empty()) return "none of the server's topics is to be recorded";
  {
    std::lock_guard<std::mutex> lock(d.mutex);
    d.bag = std::move(bag);
    d.topic_ids = std::move(topic_ids);
  }
  const auto recorded = [&d](const std::string& dds_topic, const TappedWriter&) {
    return d.topic_ids.count(dds_topic) > 0;  // written before the tap's threads start, read-only after
  };
  if (!d.tap->subscribe([&d](const TappedSample& sample) { d.on_sample(sample); }, d.options.wait_s,
                        /*kept_samples=*/true, recorded)) {
    std::fprintf(stderr, "hadal-record: warning: not every topic matched its writer within %g s\n", d.options.wait_s);
  }
  d.flusher = std::thread([&d] { d.flush_every_second(); });
  return "";
}

std::string BagRecorder::lost_samples_text() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  std::string text;
  for (const auto& [topic, gaps] : impl_->sequences) {
    if (gaps.lost > 0) text += (text.empty() ? "" : ", ") + std::to_string(gaps.lost) + " of " + topic;
  }
  return text;
}

std::map<std::string, std::int64_t> BagRecorder::last_sequences() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  std::map<std::string, std::int64_t> last;
  for (const auto& [topic, id] : impl_->topic_ids) {
    const auto read = impl_->sequences.find(topic);
    last[topic] = read == impl_->sequences.end() ? 0 : read->second.last;
  }
  return last;
}

std::size_t BagRecorder::topic_count() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->topic_ids.size();
}

std::string BagRecorder::stop() {
  Impl& d = *impl_;
  if (d.stopped) return d.write_error;
  d.stopped = true;
  {
    std::lock_guard<std::mutex> lock(d.mutex);
    d.stopping = true;
  }
  d.wake.notify_all();
  if (d.flusher.joinable()) d.flusher.join();
  if (d.tap) {
    d.tap->drain();
    d.tap.reset();  // no sample comes after this
  }
  std::lock_guard<std::mutex> lock(d.mutex);
  if (d.bag) {
    d.bag->close();
    d.final_count = d.bag->message_count();
  }
  return d.write_error;
}

std::uint64_t BagRecorder::message_count() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->bag ? impl_->bag->message_count() : impl_->final_count;
}

}  // namespace hadal::record
