#include "hadal/record/topic_tap.h"

#include "hadal/dds/participant.h"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <algorithm>
#include <mutex>
#include <thread>

namespace hadal::record {

namespace {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;
using Clock = std::chrono::steady_clock;
using Bytes = std::vector<unsigned char>;

// A type that (de)serializes nothing but copies the payload, registered under another type's name.
class OpaqueType : public fdds::TopicDataType {
 public:
  explicit OpaqueType(const std::string& name) {
    setName(name.c_str());
    m_typeSize = 1u << 24;  // the largest sample a reader takes: a 4K rgb8 image fits
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

bool wait_for(const std::function<bool()>& condition, double timeout_s) {
  const Clock::time_point end =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  while (!condition()) {
    if (Clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

}  // namespace

// DomainParticipantListener is also a DataReaderListener (through SubscriberListener).
struct TopicTap::Impl : public fdds::DomainParticipantListener {
  mutable std::mutex mutex;
  std::set<std::string> excluded;
  fdds::DomainParticipant* participant = nullptr;
  fdds::Subscriber* subscriber = nullptr;
  rtps::GuidPrefix_t server_prefix;
  bool server_seen = false;
  std::map<std::string, TappedWriter> writers;
  std::map<fdds::DataReader*, std::string> topic_of;
  std::vector<fdds::DataReader*> readers;
  std::function<void(const TappedSample&)> on_sample;
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
    TappedWriter& writer = writers[topic];
    writer.type = info.info.typeName().to_string();
    writer.reliable = info.info.m_qos.m_reliability.kind == fdds::RELIABLE_RELIABILITY_QOS;
    writer.transient_local = info.info.m_qos.m_durability.kind != fdds::VOLATILE_DURABILITY_QOS;
    last_change = Clock::now();
  }

  void on_data_available(fdds::DataReader* reader) override {
    Bytes bytes;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&bytes, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      std::lock_guard<std::mutex> lock(mutex);
      const auto sequence = static_cast<std::int64_t>(info.sample_identity.sequence_number().to64long());
      if (on_sample) on_sample(TappedSample{topic_of[reader], bytes, sequence});
      last_change = Clock::now();
    }
  }
};

TopicTap::TopicTap(int domain_id, const std::string& participant_name, std::set<std::string> excluded,
                   const SecurityFiles& security)
    : impl_(std::make_unique<Impl>()) {
  impl_->excluded = std::move(excluded);
  // The listener from the start: hadald may be discovered as the participant is enabled.
  impl_->participant = dds::create_participant(domain_id, participant_name, impl_.get(), security);
}

TopicTap::~TopicTap() {
  impl_->participant->set_listener(nullptr);
  for (fdds::DataReader* reader : impl_->readers) reader->set_listener(nullptr);
  dds::delete_participant(impl_->participant);
}

bool TopicTap::discover(double timeout_s, double quiet_s) {
  return wait_for(
      [&] {
        std::lock_guard<std::mutex> lock(impl_->mutex);
        return !impl_->writers.empty() &&
               std::chrono::duration<double>(Clock::now() - impl_->last_change).count() > quiet_s;
      },
      timeout_s);
}

std::map<std::string, TappedWriter> TopicTap::writers() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->writers;
}

bool TopicTap::subscribe(std::function<void(const TappedSample&)> on_sample, double timeout_s, bool kept_samples,
                         const std::function<bool(const std::string&, const TappedWriter&)>& wanted,
                         bool latest_only) {
  Impl& d = *impl_;
  {
    std::lock_guard<std::mutex> lock(d.mutex);
    d.on_sample = std::move(on_sample);
  }
  if (d.subscriber == nullptr) d.subscriber = d.participant->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  for (const auto& [topic_name, writer] : writers()) {
    if (wanted && !wanted(topic_name, writer)) continue;
    if (d.participant->find_type(writer.type).empty()) {
      fdds::TypeSupport(new OpaqueType(writer.type)).register_type(d.participant);
    }
    fdds::Topic* topic = d.participant->create_topic(topic_name, writer.type, fdds::TOPIC_QOS_DEFAULT);
    fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
    const bool kept = kept_samples && writer.transient_local;
    qos.reliability().kind = kept || !latest_only ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
    qos.durability().kind = kept ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
    qos.history().kind = latest_only ? fdds::KEEP_LAST_HISTORY_QOS : fdds::KEEP_ALL_HISTORY_QOS;
    qos.history().depth = 1;
    qos.endpoint().history_memory_policy = rtps::DYNAMIC_RESERVE_MEMORY_MODE;
    dds::apply_transport_environment(qos);
    // The listener only once the reader is known, so every sample finds its topic.
    fdds::DataReader* reader = d.subscriber->create_datareader(topic, qos, nullptr, fdds::StatusMask::none());
    {
      std::lock_guard<std::mutex> lock(d.mutex);
      d.topic_of[reader] = topic_name;
      d.readers.push_back(reader);
    }
    reader->set_listener(&d, fdds::StatusMask::data_available());
  }
  return wait_for(
      [&] {
        for (fdds::DataReader* reader : d.readers) {
          fdds::SubscriptionMatchedStatus matched;
          reader->get_subscription_matched_status(matched);
          if (matched.current_count < 1) return false;
        }
        return true;
      },
      timeout_s);
}

void TopicTap::drain() {
  for (fdds::DataReader* reader : impl_->readers) impl_->on_data_available(reader);
}

double TopicTap::seconds_quiet() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return std::chrono::duration<double>(Clock::now() - impl_->last_change).count();
}

}  // namespace hadal::record
