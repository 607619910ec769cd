// Registers message types and creates topics once per participant (Fast DDS refuses a second
// create_topic with the same name), plus the QoS Hadal uses on every endpoint.
//
// QoS: writers are RELIABLE + TRANSIENT_LOCAL with KEEP_LAST history, which matches reliable and
// best-effort, volatile and transient-local readers (ROS 2 sensor-data QoS included). A sample the
// transport lost (a full shared-memory port on a loaded machine) is resent when the reader asks for
// it, which it does after the writer's next heartbeat: writers send one every kHeartbeatPeriod_s
// (Fast DDS's default of 3 s let a writer overwrite the lost sample in its history before the
// request came, and the reader then saw a gap). Readers are
// RELIABLE, VOLATILE by default (a command reader must never see what was written before it existed);
// a reader of state and sensor topics may ask for the writer's kept samples (kKeptSamples): the two
// directions of endpoint discovery are independent, so a reader can match a writer before the writer
// matches it, and whatever is written in between would otherwise never reach it.
#pragma once

#include "hadal/dds/guarded_type.h"
#include "hadal/dds/participant.h"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace hadal::dds {

class TopicRegistry {
 public:
  explicit TopicRegistry(eprosima::fastdds::dds::DomainParticipant* participant)
      : participant_(participant) {
    publisher_ = participant_->create_publisher(eprosima::fastdds::dds::PUBLISHER_QOS_DEFAULT);
    subscriber_ = participant_->create_subscriber(eprosima::fastdds::dds::SUBSCRIBER_QOS_DEFAULT);
    if (publisher_ == nullptr || subscriber_ == nullptr) {
      throw std::runtime_error("could not create a DDS publisher/subscriber");
    }
  }

  // The topic `name` of message type PubSubType (a fastddsgen XxxPubSubType). Throws
  // std::invalid_argument when `name` already exists with another type (reading its samples as this
  // type would misinterpret their bytes).
  template <class PubSubType>
  eprosima::fastdds::dds::Topic* topic(const std::string& name) {
    eprosima::fastdds::dds::TypeSupport type(new GuardedType<PubSubType>());  // dds/guarded_type.h
    const std::string type_name = type.get_type_name();
    auto found = topics_.find(name);
    if (found != topics_.end()) {
      if (found->second->get_type_name() != type_name) {
        throw std::invalid_argument("DDS topic " + name + " has type " + found->second->get_type_name() +
                                    ", not " + type_name);
      }
      return found->second;
    }
    if (participant_->find_type(type_name).empty()) {
      type.register_type(participant_);
    }
    eprosima::fastdds::dds::Topic* created =
        participant_->create_topic(name, type_name, eprosima::fastdds::dds::TOPIC_QOS_DEFAULT);
    if (created == nullptr) throw std::runtime_error("could not create DDS topic " + name);
    topics_.emplace(name, created);
    return created;
  }

  static constexpr double kHeartbeatPeriod_s = 0.1;

  template <class PubSubType>
  eprosima::fastdds::dds::DataWriter* writer(const std::string& topic_name, int history_depth,
                                            eprosima::fastdds::dds::DataWriterListener* listener = nullptr) {
    eprosima::fastdds::dds::DataWriterQos qos = eprosima::fastdds::dds::DATAWRITER_QOS_DEFAULT;
    set_endpoint_qos(qos, history_depth);
    qos.durability().kind = eprosima::fastdds::dds::TRANSIENT_LOCAL_DURABILITY_QOS;
    qos.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(kHeartbeatPeriod_s);
    auto* writer = publisher_->create_datawriter(topic<PubSubType>(topic_name), qos, listener);
    if (writer == nullptr) throw std::runtime_error("could not create a DDS writer on " + topic_name);
    writers_.push_back(writer);
    return writer;
  }

  // Drops the samples every writer kept, so a reader that matches from now on receives none of them (a
  // lockstep reset: the kept samples belong to the run before it, with stamps the new run will repeat).
  void clear_kept_samples() {
    for (auto* writer : writers_) {
      std::size_t removed = 0;
      writer->clear_history(&removed);
    }
  }

  // What a reader receives on matching a writer: only what is written from then on, or also the
  // samples the writer kept (its last history_depth).
  enum class Durability { kNewSamples, kKeptSamples };

  template <class PubSubType>
  eprosima::fastdds::dds::DataReader* reader(const std::string& topic_name, int history_depth,
                                            eprosima::fastdds::dds::DataReaderListener* listener,
                                            Durability durability = Durability::kNewSamples) {
    eprosima::fastdds::dds::DataReaderQos qos = eprosima::fastdds::dds::DATAREADER_QOS_DEFAULT;
    set_endpoint_qos(qos, history_depth);
    if (durability == Durability::kKeptSamples) {
      qos.durability().kind = eprosima::fastdds::dds::TRANSIENT_LOCAL_DURABILITY_QOS;
    }
    auto* reader = subscriber_->create_datareader(topic<PubSubType>(topic_name), qos, listener);
    if (reader == nullptr) throw std::runtime_error("could not create a DDS reader on " + topic_name);
    return reader;
  }

 private:
  // RELIABLE + VOLATILE + KEEP_LAST(depth); writers then keep their samples (above).
  template <class EndpointQos>
  static void set_endpoint_qos(EndpointQos& qos, int history_depth) {
    qos.reliability().kind = eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS;
    qos.durability().kind = eprosima::fastdds::dds::VOLATILE_DURABILITY_QOS;
    qos.history().kind = eprosima::fastdds::dds::KEEP_LAST_HISTORY_QOS;
    qos.history().depth = history_depth;
    apply_transport_environment(qos);
  }

  eprosima::fastdds::dds::DomainParticipant* participant_;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  std::vector<eprosima::fastdds::dds::DataWriter*> writers_;
};

}  // namespace hadal::dds
