#include "server_endpoints.h"

#include "hadal/dds/participant.h"
#include "hadal/dds/topic_names.h"
#include "hadal/dds/topic_registry.h"
#include "hadal/physics/ocean.h"
#include "actuator_topics.h"
#include "message_conversion.h"
#include "image_preview.h"
#include "monitor.h"
#include "scene_message.h"
#include "inbound.h"

#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <hadal_msgsPubSubTypes.h>
#include <marine_acoustic_msgsPubSubTypes.h>
#include <geometry_msgsPubSubTypes.h>
#include <nav_msgsPubSubTypes.h>
#include <rosgraph_msgsPubSubTypes.h>
#include <sensor_msgsPubSubTypes.h>
#include <std_msgsPubSubTypes.h>
#include <trajectory_msgsPubSubTypes.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <set>

namespace hadal::dds {

namespace fdds = eprosima::fastdds::dds;

namespace {

constexpr int kCommandHistoryDepth = 32;

std::int64_t source_stamp_ns(const fdds::SampleInfo& info) {
  return info.source_timestamp.to_ns();
}

SourceId source_of(const fdds::SampleInfo& info) {
  SourceId id{};
  const auto& prefix = info.sample_identity.writer_guid().guidPrefix;
  std::copy(std::begin(prefix.value), std::end(prefix.value), id.begin());
  return id;
}

}  // namespace

struct ServerEndpoints::Impl : public fdds::DomainParticipantListener {
  const Model& model;
  fdds::DomainParticipant* participant = nullptr;
  std::unique_ptr<TopicRegistry> registry;

  fdds::DataWriter* clock_writer = nullptr;
  fdds::DataWriter* status_writer = nullptr;
  fdds::DataWriter* reply_writer = nullptr;
  fdds::DataWriter* scene_writer = nullptr;
  std::vector<fdds::DataWriter*> odometry_writers;
  // In waves: the sea state per vehicle.
  std::vector<fdds::DataWriter*> sea_state_writers;
  std::vector<std::size_t> sea_state_slot;
  hadal_msgs::msg::SeaState sea_state_msg;
  // Per vehicle, a writer per actuator kind with a state topic that the vehicle has (actuator_topics.h).
  struct ActuatorStateWriter {
    virtual ~ActuatorStateWriter() = default;
    // Fills the kind's message from the state; returns it for writing.
    virtual void* fill(const VehicleSpec& spec, const VehicleState& state, double time_s) = 0;
    fdds::DataWriter* writer = nullptr;
    std::size_t slot = 0;
  };
  template <class K>
  struct KindStateWriter : ActuatorStateWriter {
    typename ActuatorStateTopic<K>::Message msg;  // reused every sample
    void* fill(const VehicleSpec& spec, const VehicleState& state, double time_s) override {
      fill_actuator_state<K>(spec, state, time_s, msg);
      return &msg;
    }
  };
  std::vector<std::vector<std::unique_ptr<ActuatorStateWriter>>> actuator_state_writers;
  // One per topic of a sensor (sensors/sensor_kind.h, "Topics"): its writer, its slot in `counts` and
  // the topic's message (of the topic's Message type), reused every sample.
  struct SensorTopic {
    fdds::DataWriter* writer = nullptr;
    std::size_t slot = 0;
    std::shared_ptr<void> message;
    // A topic with a preview (sensors::TopicHasPreview): its writer, its slot, when it was last written.
    fdds::DataWriter* preview_writer = nullptr;
    std::size_t preview_slot = 0;
    std::chrono::steady_clock::time_point preview_at{};
  };
  std::vector<std::vector<std::vector<SensorTopic>>> sensors;  // [vehicle][sensor][topic]
  std::vector<fdds::DataReader*> setpoint_readers;
  std::vector<fdds::DataReader*> trajectory_readers;
  std::vector<fdds::DataReader*> packet_readers;
  std::vector<fdds::DataReader*> winch_readers;
  fdds::DataReader* step_reader = nullptr;

  // Counts indexed like topic_names.
  std::vector<std::string> topic_names;
  std::vector<std::uint64_t> counts;
  std::size_t clock_slot = 0, status_slot = 0, reply_slot = 0, scene_slot = 0;
  std::vector<std::size_t> odometry_slot;

  // Reused messages: the publish path does not allocate once strings and sequences have their size.
  rosgraph_msgs::msg::Clock clock_msg;
  // One message per topic, kept until the topic's next write: the monitor serializes the last one when due.
  std::vector<nav_msgs::msg::Odometry> odometry_msgs;
  // Per vehicle: its joint-state writer (null for a rigid vehicle), slot, message and joint names.
  std::vector<fdds::DataWriter*> joint_state_writers;
  std::vector<std::size_t> joint_state_slot;
  std::vector<sensor_msgs::msg::JointState> joint_state_msgs;
  std::vector<JointStateLayout> joint_layouts;
  hadal_msgs::msg::StepReply reply_msg;
  hadal_msgs::msg::SimStatus status_msg;
  hadal_msgs::msg::Scene scene_msg;  // written at start and after every reset
  sensor_msgs::msg::Image preview_msg;

  // rt/hadal/monitor (dds/monitor.h): the topics it carries, by count slot (-1: not carried).
  fdds::DataWriter* monitor_writer = nullptr;
  // Per cable: the writers of its two end forces and its shape, their slots and messages.
  struct CableTopics {
    std::array<fdds::DataWriter*, 2> ends{};
    std::array<std::size_t, 2> end_slots{};
    fdds::DataWriter* shape = nullptr;
    std::size_t shape_slot = 0;
    geometry_msgs::msg::WrenchStamped wrench;
    nav_msgs::msg::Path path;
    int winch_end = -1;  // its winch's end, or -1
    fdds::DataWriter* winch = nullptr;
    std::size_t winch_slot = 0;
    hadal_msgs::msg::WinchState winch_msg;
  };
  std::vector<CableTopics> cable_topics;
  // rt/hadal/acoustic_links: null when the scenario has no acoustic sensor.
  fdds::DataWriter* links_writer = nullptr;
  std::size_t links_slot = 0;
  hadal_msgs::msg::AcousticLinks links_msg;
  std::chrono::steady_clock::time_point links_at{};
  bool links_sent_empty = false;
  std::size_t monitor_slot = 0;
  MonitorContent monitor;
  std::vector<long> monitor_index;
  hadal_msgs::msg::Monitor monitor_msg;
  std::chrono::steady_clock::time_point monitor_at{};

  // Carries the topic of `writer` (counted in `slot`) in the monitor.
  void carry_in_monitor(fdds::DataWriter* writer, std::size_t slot) {
    const fdds::TypeSupport type_support = writer->get_type();
    std::string topic, type;
    if (!ros_topic_name(topic_names[slot], &topic) || !ros_type_name(type_support.get_type_name(), &type)) return;
    monitor_index[slot] = static_cast<long>(monitor.add(topic, type, type_support));
  }

  // Whether a reader is matched to the writer: the side channels (previews, the monitor) are written only then.
  static bool has_readers(fdds::DataWriter* writer) {
    fdds::PublicationMatchedStatus matched;
    writer->get_publication_matched_status(matched);
    return matched.current_count > 0;
  }

  // The preview of a sample just written (dds/image_preview.h): due in wall time and wanted by a reader; `draw`
  // fills the preview image (false: none).
  template <class Draw>
  void write_preview(SensorTopic& endpoint, Draw&& draw) {
    const auto now = std::chrono::steady_clock::now();
    if (now - endpoint.preview_at < kPreviewInterval) return;
    if (!has_readers(endpoint.preview_writer) || !draw(&preview_msg)) return;
    endpoint.preview_at = now;
    write(endpoint.preview_writer, &preview_msg, endpoint.preview_slot);
  }

  mutable std::mutex mutex;
  std::condition_variable step_ready;
  std::vector<InboundCommand> commands;
  std::uint64_t superseded = 0;  // commands dropped from a full queue (kMaxQueuedCommands)
  std::deque<InboundStepRequest> step_requests;
  std::atomic<bool> step_waiting{false};  // step_requests is not empty (polled without the mutex)
  // The last request id accepted from each writer (its full GUID): ids must increase (no replays).
  std::map<std::array<std::uint8_t, 16>, std::uint64_t> last_request_ids;
  std::vector<std::string> reports;
  std::vector<std::string> warnings;
  int domain_id = 0;
  std::set<std::string> reported_topics;
  bool interrupted = false;

  // A command for the next step; a full queue drops its oldest (kMaxQueuedCommands).
  void enqueue(InboundCommand&& command) {
    std::lock_guard<std::mutex> lock(mutex);
    if (commands.size() >= ServerEndpoints::kMaxQueuedCommands) {
      commands.erase(commands.begin());
      ++superseded;
    }
    commands.push_back(std::move(command));
  }

  // One listener per setpoints reader, so the vehicle index is known without a lookup.
  // A joint controller's listener also names the controller.
  struct SetpointListener : public fdds::DataReaderListener {
    Impl* owner = nullptr;
    int vehicle_index = -1;
    std::string joint_controller;
    void on_data_available(fdds::DataReader* reader) override {
      std_msgs::msg::Float64MultiArray msg;
      fdds::SampleInfo info;
      while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        InboundCommand command = command_from_array(vehicle_index, msg, source_of(info), source_stamp_ns(info));
        command.joint_controller = joint_controller;
        owner->enqueue(std::move(command));
      }
    }
  };
  std::vector<std::unique_ptr<SetpointListener>> setpoint_listeners;

  // One listener per position group's trajectory reader.
  struct TrajectoryListener : public fdds::DataReaderListener {
    Impl* owner = nullptr;
    int vehicle_index = -1;
    std::string joint_controller;
    void on_data_available(fdds::DataReader* reader) override {
      trajectory_msgs::msg::JointTrajectory msg;
      fdds::SampleInfo info;
      while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        owner->enqueue(
            command_from_trajectory(vehicle_index, joint_controller, msg, source_of(info), source_stamp_ns(info)));
      }
    }
  };
  std::vector<std::unique_ptr<TrajectoryListener>> trajectory_listeners;

  // One listener per acoustic modem's tx reader.
  struct PacketListener : public fdds::DataReaderListener {
    Impl* owner = nullptr;
    int vehicle_index = -1;
    std::string modem;
    void on_data_available(fdds::DataReader* reader) override {
      hadal_msgs::msg::AcousticPacket msg;
      fdds::SampleInfo info;
      while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        owner->enqueue(command_from_packet(vehicle_index, modem, msg, source_of(info), source_stamp_ns(info)));
      }
    }
  };
  std::vector<std::unique_ptr<PacketListener>> packet_listeners;

  // One listener per winch's command reader.
  struct WinchListener : public fdds::DataReaderListener {
    Impl* owner = nullptr;
    int cable_index = -1;
    void on_data_available(fdds::DataReader* reader) override {
      hadal_msgs::msg::WinchCommand msg;
      fdds::SampleInfo info;
      while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        owner->enqueue(command_from_winch(cable_index, msg, source_of(info), source_stamp_ns(info)));
      }
    }
  };
  std::vector<std::unique_ptr<WinchListener>> winch_listeners;

  struct StepListener : public fdds::DataReaderListener {
    Impl* owner = nullptr;
    void on_data_available(fdds::DataReader* reader) override {
      hadal_msgs::msg::StepRequest msg;
      fdds::SampleInfo info;
      while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        InboundStepRequest request = parse_step_request(owner->model, msg, source_of(info), source_stamp_ns(info));
        std::lock_guard<std::mutex> lock(owner->mutex);
        owner->check_replay(info, request);
        // A flood of requests waits as refusals without payload: what it holds stays small.
        if (owner->step_requests.size() >= kMaxPendingRequests && request.error.empty()) {
          request.error = "more than " + std::to_string(kMaxPendingRequests) + " requests are waiting; refused";
        }
        if (!request.error.empty()) request.commands.clear(), request.reset_X_WB.clear();
        owner->step_requests.push_back(std::move(request));
        owner->step_waiting.store(true, std::memory_order_release);
        owner->step_ready.notify_all();
      }
    }
  } step_listener;

  static constexpr std::size_t kMaxPendingRequests = 256;

  explicit Impl(const Model& m) : model(m) {}

  // Under `mutex`: a request whose id does not exceed the last one its writer sent is a replay (or a
  // duplicate), refused; the first request of a writer and every increasing id pass.
  void check_replay(const fdds::SampleInfo& info, InboundStepRequest& request) {
    std::array<std::uint8_t, 16> writer{};
    const auto& guid = info.sample_identity.writer_guid();
    std::copy(std::begin(guid.guidPrefix.value), std::end(guid.guidPrefix.value), writer.begin());
    std::copy(std::begin(guid.entityId.value), std::end(guid.entityId.value), writer.begin() + 12);
    const auto last = last_request_ids.find(writer);
    if (last != last_request_ids.end() && request.request_id <= last->second) {
      if (request.error.empty()) {
        request.error = "request_id " + std::to_string(request.request_id) + " replayed: ids must increase from " +
                        "one request to the next of a writer (its last was " + std::to_string(last->second) + ")";
      }
      return;
    }
    last_request_ids[writer] = request.request_id;
  }

  // Writers whose samples hadald would never see, reported by name (DDS itself is silent about them): a
  // writer on rt/<name>/actuators/commands for a vehicle the scenario does not have, and a writer on a
  // topic hadald reads (setpoints, step requests) with another type or best-effort reliability (hadald's
  // readers are reliable: DDS never matches them with a best-effort writer).
  void on_publisher_discovery(fdds::DomainParticipant*,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::WriterDiscoveryInfo::DISCOVERED_WRITER) return;
    const std::string topic = info.info.topicName().to_string();
    std::string expected_type;
    if (topic == step_request_topic()) {
      expected_type = hadal_msgs::msg::StepRequestPubSubType().getName();
    } else if (const std::string winch = "/winch/command"; topic.size() > winch.size() &&
                                                           topic.compare(topic.size() - winch.size(), winch.size(), winch) == 0) {
      bool known = false;
      std::string winches;
      for (const physics::CableModel& cable : model.cables) {
        if (cable.winch_end() < 0) continue;
        known = known || topic == winch_command_topic(cable.name);
        winches += (winches.empty() ? "" : ", ") + cable.name;
      }
      if (!known) {
        report_once(topic, "winch commands on " + echoed(topic) + " are ignored: no cable of the scenario has that winch " +
                               "(cables with a winch: " + (winches.empty() ? std::string("none") : winches) + ")");
        return;
      }
      expected_type = hadal_msgs::msg::WinchCommandPubSubType().getName();
    } else if (const std::string tx = "/tx"; topic.size() > 3 + tx.size() && topic.compare(0, 3, "rt/") == 0 &&
                                              topic.compare(topic.size() - tx.size(), tx.size(), tx) == 0) {
      if (!is_modem_tx_topic(topic)) {
        report_once(topic, "packets on " + echoed(topic) + " are ignored: no vehicle of the scenario has that modem " +
                               "(modems: " + modem_names() + ")");
        return;
      }
      expected_type = hadal_msgs::msg::AcousticPacketPubSubType().getName();
    } else {
      const std::string prefix = "rt/";
      const std::string suffix = "/actuators/commands";
      if (topic.size() <= prefix.size() + suffix.size() || topic.compare(0, prefix.size(), prefix) != 0 ||
          topic.compare(topic.size() - suffix.size(), suffix.size(), suffix) != 0) {
        return;
      }
      const std::string vehicle = topic.substr(prefix.size(), topic.size() - prefix.size() - suffix.size());
      if (model.vehicle_index(vehicle) < 0) {
        std::string known;
        for (const auto& v : model.vehicles) known += (known.empty() ? "" : ", ") + v.name;
        report_once(topic, "commands on " + echoed(topic) + " are ignored: unknown vehicle '" + echoed(vehicle) +
                               "' (vehicles: " + known + ")");
        return;
      }
      expected_type = std_msgs::msg::Float64MultiArrayPubSubType().getName();
    }
    const std::string type = info.info.typeName().to_string();
    if (type != expected_type) {
      report_once(topic + "|" + type, "samples on " + topic + " of type " + echoed(type) +
                                          " are ignored: hadald reads " + expected_type + " there");
    } else if (info.info.m_qos.m_reliability.kind == eprosima::fastdds::dds::BEST_EFFORT_RELIABILITY_QOS) {
      report_once(topic + "|best effort", "a best-effort writer on " + topic +
                                              " reaches nothing: hadald's reader is reliable (publish reliable)");
    }
  }

  // Another hadald on this domain: clients would see both servers' topics, and steps and commands would reach
  // both. DDS allows it, so it is said loudly (the other hadald says it too), naming the other process.
  void on_participant_discovery(fdds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT) return;
    if (info.info.m_participantName.to_string() != "hadald") return;
    if (info.info.m_guid.guidPrefix == participant->guid().guidPrefix) return;
    const std::string other = user_data_text(info.info.m_userData.data_vec());
    std::lock_guard<std::mutex> lock(mutex);
    warnings.push_back("another hadald is on DDS domain " + std::to_string(domain_id) + " (" +
                       (other.empty() ? std::string("it does not say which process it is") : other) +
                       "): clients there see both servers' topics, and their commands and step requests reach "
                       "both; stop one, or give each its own --domain-id");
  }

  bool is_modem_tx_topic(const std::string& topic) const {
    for (const VehicleSpec& vehicle : model.vehicles) {
      for (const SensorSpec& sensor : vehicle.sensors) {
        if (std::holds_alternative<sensors::ModemSpec>(sensor.kind) && topic == modem_tx_topic(vehicle.name, sensor.name)) {
          return true;
        }
      }
    }
    return false;
  }
  std::string modem_names() const {
    std::string names;
    for (const VehicleSpec& vehicle : model.vehicles) {
      for (const SensorSpec& sensor : vehicle.sensors) {
        if (!std::holds_alternative<sensors::ModemSpec>(sensor.kind)) continue;
        names += (names.empty() ? "" : ", ") + vehicle.name + "/" + sensor.name;
      }
    }
    return names.empty() ? "none" : names;
  }

  void report_once(const std::string& key, const std::string& report) {
    std::lock_guard<std::mutex> lock(mutex);
    if (reported_topics.insert(key).second) reports.push_back(report);
  }

  std::size_t add_count(const std::string& topic) {
    topic_names.push_back(topic);
    counts.push_back(0);
    monitor_index.push_back(-1);
    return counts.size() - 1;
  }

  void write(fdds::DataWriter* writer, void* msg, std::size_t slot) {
    if (!writer->write(msg)) return;
    ++counts[slot];
    if (monitor_index[slot] >= 0) monitor.note(static_cast<std::size_t>(monitor_index[slot]), msg, counts[slot]);
  }
};

ServerEndpoints::ServerEndpoints(const Model& model, int domain_id, const std::string& description,
                                 bool recorded)
    : impl_(std::make_unique<Impl>(model)) {
  const int state_history_depth = recorded ? kRecordedStateHistoryDepth : kStateHistoryDepth;
  const int preview_history_depth = recorded ? kRecordedPreviewHistoryDepth : kPreviewHistoryDepth;
  Impl& d = *impl_;
  d.domain_id = domain_id;
  // The listener from the start, so that a hadald already on the domain is seen: what its callbacks touch
  // (the model, the mutex and the reports) exists with Impl.
  d.participant = create_participant(domain_id, "hadald", &d, model.security, description);
  d.registry = std::make_unique<TopicRegistry>(d.participant);
  TopicRegistry& r = *d.registry;

  d.clock_writer = r.writer<rosgraph_msgs::msg::ClockPubSubType>(clock_topic(), state_history_depth);
  d.clock_slot = d.add_count(clock_topic());
  d.status_writer = r.writer<hadal_msgs::msg::SimStatusPubSubType>(status_topic(), state_history_depth);
  d.status_slot = d.add_count(status_topic());
  d.carry_in_monitor(d.status_writer, d.status_slot);
  d.reply_writer = r.writer<hadal_msgs::msg::StepReplyPubSubType>(step_reply_topic(), kCommandHistoryDepth);
  d.reply_slot = d.add_count(step_reply_topic());
  d.scene_writer = r.writer<hadal_msgs::msg::ScenePubSubType>(scene_topic(), 1);
  d.scene_slot = d.add_count(scene_topic());
  fill_scene(model, 0.0, d.scene_msg);
  d.write(d.scene_writer, &d.scene_msg, d.scene_slot);
  d.monitor_writer = r.writer<hadal_msgs::msg::MonitorPubSubType>(monitor_topic(), 1);
  d.monitor_slot = d.add_count(monitor_topic());
  for (const physics::CableModel& cable : model.cables) {
    Impl::CableTopics& topics = d.cable_topics.emplace_back();
    for (std::size_t e = 0; e < 2; ++e) {
      const std::string topic = cable_tension_topic(cable.name, e == 0 ? "from" : "to");
      topics.ends[e] = r.writer<geometry_msgs::msg::WrenchStampedPubSubType>(topic, state_history_depth);
      topics.end_slots[e] = d.add_count(topic);
      d.carry_in_monitor(topics.ends[e], topics.end_slots[e]);
    }
    topics.shape = r.writer<nav_msgs::msg::PathPubSubType>(cable_shape_topic(cable.name), state_history_depth);
    topics.shape_slot = d.add_count(cable_shape_topic(cable.name));
    d.carry_in_monitor(topics.shape, topics.shape_slot);
    topics.winch_end = cable.winch_end();
    if (topics.winch_end < 0) continue;
    topics.winch = r.writer<hadal_msgs::msg::WinchStatePubSubType>(winch_state_topic(cable.name), state_history_depth);
    topics.winch_slot = d.add_count(winch_state_topic(cable.name));
    d.carry_in_monitor(topics.winch, topics.winch_slot);
    auto listener = std::make_unique<Impl::WinchListener>();
    listener->owner = &d;
    listener->cable_index = static_cast<int>(d.cable_topics.size() - 1);
    d.winch_readers.push_back(r.reader<hadal_msgs::msg::WinchCommandPubSubType>(
        winch_command_topic(cable.name), kCommandHistoryDepth, listener.get()));
    d.winch_listeners.push_back(std::move(listener));
  }
  bool acoustic = false;
  for (const VehicleSpec& vehicle : model.vehicles) {
    for (const SensorSpec& sensor : vehicle.sensors) {
      std::visit(
          [&](const auto& spec) {
            acoustic |= sensors::HasAcousticLinks<sensors::KindOf<std::decay_t<decltype(spec)>>>::value;
          },
          sensor.kind);
    }
  }
  if (acoustic) {
    d.links_writer = r.writer<hadal_msgs::msg::AcousticLinksPubSubType>(acoustic_links_topic(), 1);
    d.links_slot = d.add_count(acoustic_links_topic());
    d.carry_in_monitor(d.links_writer, d.links_slot);
  }
  d.odometry_msgs.resize(model.vehicles.size());

  for (std::size_t i = 0; i < model.vehicles.size(); ++i) {
    const std::string& name = model.vehicles[i].name;
    d.odometry_writers.push_back(
        r.writer<nav_msgs::msg::OdometryPubSubType>(odometry_topic(name), state_history_depth));
    d.odometry_slot.push_back(d.add_count(odometry_topic(name)));
    d.carry_in_monitor(d.odometry_writers.back(), d.odometry_slot.back());
    if (model.world.waves.enabled()) {
      d.sea_state_writers.push_back(
          r.writer<hadal_msgs::msg::SeaStatePubSubType>(sea_state_topic(name), state_history_depth));
      d.sea_state_slot.push_back(d.add_count(sea_state_topic(name)));
      d.carry_in_monitor(d.sea_state_writers.back(), d.sea_state_slot.back());
    }
    d.joint_layouts.push_back(joint_state_layout(model.vehicles[i]));
    d.joint_state_msgs.emplace_back();
    if (d.joint_layouts.back().names.empty()) {
      d.joint_state_writers.push_back(nullptr);
      d.joint_state_slot.push_back(0);
    } else {
      d.joint_state_writers.push_back(
          r.writer<sensor_msgs::msg::JointStatePubSubType>(joint_states_topic(name), state_history_depth));
      d.joint_state_slot.push_back(d.add_count(joint_states_topic(name)));
      d.carry_in_monitor(d.joint_state_writers.back(), d.joint_state_slot.back());
    }
    auto& actuator_writers = d.actuator_state_writers.emplace_back();
    physics::ActuatorKinds::for_each([&](auto tag) {
      using K = typename decltype(tag)::type;
      if constexpr (ActuatorStateTopic<K>::kPublished) {
        if (!publishes_state_of_kind<K>(model.vehicles[i])) return;
        auto writer = std::make_unique<Impl::KindStateWriter<K>>();
        const std::string topic = actuator_state_topic(name, K::kListKey);
        writer->writer = r.writer<typename ActuatorStateTopic<K>::PubSubType>(topic, state_history_depth);
        writer->slot = d.add_count(topic);
        d.carry_in_monitor(writer->writer, writer->slot);
        actuator_writers.push_back(std::move(writer));
      }
    });

    std::vector<std::vector<Impl::SensorTopic>>& endpoints = d.sensors.emplace_back();
    for (const SensorSpec& sensor : model.vehicles[i].sensors) {
      std::vector<Impl::SensorTopic>& topics = endpoints.emplace_back();
      std::visit(
          [&](const auto& spec) {
            using Kind = sensors::KindOf<std::decay_t<decltype(spec)>>;
            sensors::TopicsOf<Kind>::for_each([&](auto tag, std::size_t) {
              using Topic = typename decltype(tag)::type;
              std::string topic = sensor_topic(name, sensor.name);
              if (!Topic::kSuffix.empty()) topic += "/" + std::string(Topic::kSuffix);
              Impl::SensorTopic& endpoint = topics.emplace_back();
              endpoint.writer = r.writer<typename Topic::PubSubType>(topic, sensors::TopicHistoryDepth<Topic>::value);
              endpoint.message = std::make_shared<typename Topic::Message>();
              endpoint.slot = d.add_count(topic);
              if constexpr (sensors::TopicInMonitor<Topic>::value) d.carry_in_monitor(endpoint.writer, endpoint.slot);
              if constexpr (sensors::TopicHasPreview<Topic>::value) {
                const std::string preview = sensor_topic(name, sensor.name) + "/preview";
                endpoint.preview_writer = r.writer<sensor_msgs::msg::ImagePubSubType>(preview, preview_history_depth);
                endpoint.preview_slot = d.add_count(preview);
              }
            });
          },
          sensor.kind);
    }

    auto listener = std::make_unique<Impl::SetpointListener>();
    listener->owner = &d;
    listener->vehicle_index = static_cast<int>(i);
    d.setpoint_readers.push_back(r.reader<std_msgs::msg::Float64MultiArrayPubSubType>(
        actuator_commands_topic(name), kCommandHistoryDepth, listener.get()));
    d.setpoint_listeners.push_back(std::move(listener));
    for (const physics::JointControllerSpec& controller : model.vehicles[i].joint_controllers) {
      auto joint_listener = std::make_unique<Impl::SetpointListener>();
      joint_listener->owner = &d;
      joint_listener->vehicle_index = static_cast<int>(i);
      joint_listener->joint_controller = controller.name;
      d.setpoint_readers.push_back(r.reader<std_msgs::msg::Float64MultiArrayPubSubType>(
          joint_commands_topic(name, controller.name), kCommandHistoryDepth, joint_listener.get()));
      d.setpoint_listeners.push_back(std::move(joint_listener));
      if (controller.mode != physics::JointCommandMode::kPosition) continue;
      auto trajectory_listener = std::make_unique<Impl::TrajectoryListener>();
      trajectory_listener->owner = &d;
      trajectory_listener->vehicle_index = static_cast<int>(i);
      trajectory_listener->joint_controller = controller.name;
      d.trajectory_readers.push_back(r.reader<trajectory_msgs::msg::JointTrajectoryPubSubType>(
          joint_trajectory_topic(name, controller.name), kCommandHistoryDepth, trajectory_listener.get()));
      d.trajectory_listeners.push_back(std::move(trajectory_listener));
    }
    for (const SensorSpec& sensor : model.vehicles[i].sensors) {
      if (!std::holds_alternative<sensors::ModemSpec>(sensor.kind)) continue;
      auto packet_listener = std::make_unique<Impl::PacketListener>();
      packet_listener->owner = &d;
      packet_listener->vehicle_index = static_cast<int>(i);
      packet_listener->modem = sensor.name;
      d.packet_readers.push_back(r.reader<hadal_msgs::msg::AcousticPacketPubSubType>(
          modem_tx_topic(name, sensor.name), kCommandHistoryDepth, packet_listener.get()));
      d.packet_listeners.push_back(std::move(packet_listener));
    }
  }
  d.step_listener.owner = &d;
  d.step_reader = r.reader<hadal_msgs::msg::StepRequestPubSubType>(step_request_topic(), kCommandHistoryDepth,
                                                                   &d.step_listener);
}

ServerEndpoints::~ServerEndpoints() {
  Impl& d = *impl_;
  d.participant->set_listener(nullptr);
  delete_participant(d.participant);
}

std::vector<InboundCommand> ServerEndpoints::take_commands() {
  std::vector<InboundCommand> taken;
  std::lock_guard<std::mutex> lock(impl_->mutex);
  taken.swap(impl_->commands);
  return taken;
}

std::uint64_t ServerEndpoints::superseded_commands() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->superseded;
}

std::vector<InboundStepRequest> ServerEndpoints::take_step_requests() {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  std::vector<InboundStepRequest> taken(std::make_move_iterator(impl_->step_requests.begin()),
                                        std::make_move_iterator(impl_->step_requests.end()));
  impl_->step_requests.clear();
  impl_->step_waiting.store(false, std::memory_order_release);
  return taken;
}

std::optional<InboundStepRequest> ServerEndpoints::wait_step_request(std::chrono::milliseconds timeout,
                                                                     std::chrono::microseconds spin) {
  if (spin.count() > 0) {
    const auto end = std::chrono::steady_clock::now() + spin;
    while (!impl_->step_waiting.load(std::memory_order_acquire) && std::chrono::steady_clock::now() < end) {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
  }
  std::unique_lock<std::mutex> lock(impl_->mutex);
  impl_->step_ready.wait_for(lock, timeout,
                             [this] { return impl_->interrupted || !impl_->step_requests.empty(); });
  if (impl_->step_requests.empty()) return std::nullopt;
  InboundStepRequest request = std::move(impl_->step_requests.front());
  impl_->step_requests.pop_front();
  impl_->step_waiting.store(!impl_->step_requests.empty(), std::memory_order_release);
  return request;
}

void ServerEndpoints::interrupt() {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->interrupted = true;
  impl_->step_ready.notify_all();
}

std::vector<std::string> ServerEndpoints::take_warnings() {
  std::vector<std::string> taken;
  std::lock_guard<std::mutex> lock(impl_->mutex);
  taken.swap(impl_->warnings);
  return taken;
}

std::vector<std::string> ServerEndpoints::take_reports() {
  std::vector<std::string> taken;
  std::lock_guard<std::mutex> lock(impl_->mutex);
  taken.swap(impl_->reports);
  return taken;
}

void ServerEndpoints::publish_clock(double time_s) {
  impl_->clock_msg.clock(to_time_msg(time_s));
  impl_->write(impl_->clock_writer, &impl_->clock_msg, impl_->clock_slot);
}

void ServerEndpoints::publish_odometry(int vehicle_index, const SimState& state) {
  const auto i = static_cast<std::size_t>(vehicle_index);
  fill_odometry(impl_->model.world.frame_id, impl_->model.vehicles[i].name, state.time,
                state.vehicles[i].body, impl_->odometry_msgs[i]);
  impl_->write(impl_->odometry_writers[i], &impl_->odometry_msgs[i], impl_->odometry_slot[i]);
}

void ServerEndpoints::publish_sea_state(int vehicle_index, const SimState& state, const physics::Ocean& ocean) {
  if (impl_->sea_state_writers.empty()) return;
  const auto i = static_cast<std::size_t>(vehicle_index);
  fill_sea_state(impl_->model.world.frame_id, state.time, ocean.waves(), impl_->model.world.waves,
                 state.vehicles[i].body.X_WB.translation(), impl_->sea_state_msg);
  impl_->write(impl_->sea_state_writers[i], &impl_->sea_state_msg, impl_->sea_state_slot[i]);
}

void ServerEndpoints::publish_joint_states(int vehicle_index, const SimState& state) {
  const auto i = static_cast<std::size_t>(vehicle_index);
  if (!impl_->joint_state_writers[i]) return;
  fill_joint_state(impl_->joint_layouts[i], impl_->model.vehicles[i].name, state.time, state.vehicles[i],
                   impl_->joint_state_msgs[i]);
  impl_->write(impl_->joint_state_writers[i], &impl_->joint_state_msgs[i], impl_->joint_state_slot[i]);
}

void ServerEndpoints::publish_cable(int cable_index, const SimState& state) {
  Impl& d = *impl_;
  const auto c = static_cast<std::size_t>(cable_index);
  Impl::CableTopics& topics = d.cable_topics[c];
  const physics::CableState& cable = state.cables[c];
  const builtin_interfaces::msg::Time stamp = to_time_msg(state.time);
  for (std::size_t e = 0; e < 2; ++e) {
    topics.wrench.header().stamp(stamp);
    topics.wrench.header().frame_id(d.model.world.frame_id);
    topics.wrench.wrench().force().x(cable.f_W_ends[e].x());
    topics.wrench.wrench().force().y(cable.f_W_ends[e].y());
    topics.wrench.wrench().force().z(cable.f_W_ends[e].z());
    d.write(topics.ends[e], &topics.wrench, topics.end_slots[e]);
  }
  topics.path.header().stamp(stamp);
  topics.path.header().frame_id(d.model.world.frame_id);
  topics.path.poses().resize(cable.p_W.size());
  for (std::size_t i = 0; i < cable.p_W.size(); ++i) {
    geometry_msgs::msg::PoseStamped& pose = topics.path.poses()[i];
    pose.header() = topics.path.header();
    pose.pose().position().x(cable.p_W[i].x());
    pose.pose().position().y(cable.p_W[i].y());
    pose.pose().position().z(cable.p_W[i].z());
    pose.pose().orientation().w(1.0);
  }
  d.write(topics.shape, &topics.path, topics.shape_slot);
  if (topics.winch_end < 0) return;
  const auto e = static_cast<std::size_t>(topics.winch_end);
  const physics::WinchSpec& spec = *d.model.cables[c].ends[e].winch;
  hadal_msgs::msg::WinchState& msg = topics.winch_msg;
  msg.header().stamp(stamp);
  msg.header().frame_id(d.model.world.frame_id);
  msg.length_m(cable.length);
  msg.speed_mps(cable.winch.speed);
  msg.command_speed_mps(cable.winch.command_speed);
  msg.target_length_m(cable.winch.target_length);
  msg.drum_length_m(spec.drum_length);
  msg.min_length_m(spec.min_length);
  msg.tension_n(cable.f_W_ends[e].norm());
  msg.at_limit(cable.winch.at_limit);
  d.write(topics.winch, &msg, topics.winch_slot);
}

void ServerEndpoints::publish_actuator_states(int vehicle_index, const SimState& state) {
  const auto i = static_cast<std::size_t>(vehicle_index);
  for (const auto& writer : impl_->actuator_state_writers[i]) {
    impl_->write(writer->writer, writer->fill(impl_->model.vehicles[i], state.vehicles[i], state.time), writer->slot);
  }
}

void ServerEndpoints::publish_sensor(int vehicle_index, int sensor_index, const SimState& state) {
  const auto i = static_cast<std::size_t>(vehicle_index);
  const auto k = static_cast<std::size_t>(sensor_index);
  const SensorSpec& sensor = impl_->model.vehicles[i].sensors[k];
  const SensorState& sample = state.vehicles[i].sensors[k];
  std::vector<Impl::SensorTopic>& topics = impl_->sensors[i][k];
  const sensors::MessageHeader header{sample.stamp, sensor.frame_id, sensor.rate_hz};
  std::visit(
      [&](const auto& spec) {
        using Kind = sensors::KindOf<std::decay_t<decltype(spec)>>;
        const auto& kind_state = std::get<typename Kind::State>(sample.kind);
        sensors::TopicsOf<Kind>::for_each([&](auto tag, std::size_t t) {
          using Topic = typename decltype(tag)::type;
          Impl::SensorTopic& endpoint = topics[t];
          auto& msg = *static_cast<typename Topic::Message*>(endpoint.message.get());
          Topic::fill(spec, kind_state, header, msg);
          impl_->write(endpoint.writer, &msg, endpoint.slot);
          if constexpr (sensors::TopicHasPreview<Topic>::value) {
            if constexpr (sensors::TopicDrawsPreview<Topic>::value) {
              impl_->write_preview(endpoint, [&](sensor_msgs::msg::Image* preview) {
                Topic::fill_preview(spec, kind_state, header, *preview);
                return true;
              });
            } else {
              impl_->write_preview(endpoint, [&](sensor_msgs::msg::Image* preview) { return half_resolution(msg, preview); });
            }
          }
        });
      },
      sensor.kind);
}

void ServerEndpoints::publish_status(const StatusReport& report) {
  hadal_msgs::msg::SimStatus& msg = impl_->status_msg;
  msg.header().stamp(to_time_msg(report.sim_time));
  msg.header().frame_id(impl_->model.world.frame_id);
  msg.sim_time(report.sim_time);
  msg.wall_time(report.wall_time);
  msg.real_time_factor(report.real_time_factor);
  msg.step_count(report.step_count);
  msg.step_size(report.step_size);
  msg.mode(report.mode);
  msg.vehicle_names().clear();
  for (const auto& v : impl_->model.vehicles) msg.vehicle_names().push_back(v.name);
  msg.vehicle_faults(report.vehicle_faults);
  msg.rejected_commands(report.rejected_commands);
  msg.last_error(report.last_error);
  msg.dropped_captures(report.dropped_captures);
  impl_->write(impl_->status_writer, &msg, impl_->status_slot);
}

void ServerEndpoints::publish_step_reply(std::uint64_t request_id, bool accepted, const std::string& error,
                                         const SimState& state, const std::string& unknown_vehicle) {
  hadal_msgs::msg::StepReply& msg = impl_->reply_msg;
  msg.request_id(request_id);
  msg.accepted(accepted);
  msg.error(error);
  msg.unknown_vehicle(unknown_vehicle);
  msg.sim_time(to_time_msg(state.time));
  msg.sim_time_s(state.time);
  msg.step_count(state.step_count);
  fill_reply_states(impl_->model, state, msg);
  impl_->write(impl_->reply_writer, &msg, impl_->reply_slot);
}

void ServerEndpoints::publish_monitor(double sim_time_s) {
  Impl& d = *impl_;
  const auto now = std::chrono::steady_clock::now();
  if (now - d.monitor_at < kMonitorInterval || !d.monitor.changed()) return;
  d.monitor_at = now;
  if (!Impl::has_readers(d.monitor_writer)) return;
  if (d.monitor.fill(sim_time_s, d.model.world.frame_id, &d.monitor_msg)) {
    d.write(d.monitor_writer, &d.monitor_msg, d.monitor_slot);
  }
}

bool ServerEndpoints::acoustic_links_due() {
  Impl& d = *impl_;
  if (d.links_writer == nullptr) return false;
  const auto now = std::chrono::steady_clock::now();
  if (now - d.links_at < kMonitorInterval) return false;
  d.links_at = now;
  return Impl::has_readers(d.links_writer) || Impl::has_readers(d.monitor_writer);
}

void ServerEndpoints::publish_acoustic_links(double sim_time_s, const std::vector<sensors::AcousticLink>& links) {
  Impl& d = *impl_;
  if (d.links_writer == nullptr || (links.empty() && d.links_sent_empty)) return;
  d.links_sent_empty = links.empty();
  hadal_msgs::msg::AcousticLinks& msg = d.links_msg;
  msg.header().stamp(to_time_msg(sim_time_s));
  msg.header().frame_id(d.model.world.frame_id);
  msg.links().resize(links.size());
  for (std::size_t i = 0; i < links.size(); ++i) {
    const sensors::AcousticLink& in = links[i];
    hadal_msgs::msg::AcousticLink& out = msg.links()[i];
    out.kind(static_cast<std::uint8_t>(in.kind));
    out.source(in.source);
    out.target(in.target);
    out.emit_position().x(in.p_Wemit.x());
    out.emit_position().y(in.p_Wemit.y());
    out.emit_position().z(in.p_Wemit.z());
    out.target_position().x(in.p_Wtarget.x());
    out.target_position().y(in.p_Wtarget.y());
    out.target_position().z(in.p_Wtarget.z());
    out.emit_stamp(to_time_msg(in.emit_time));
    out.duration(in.duration);
    out.sound_speed(in.sound_speed);
  }
  d.write(d.links_writer, &msg, d.links_slot);
}

void ServerEndpoints::clear_kept_samples() {
  impl_->registry->clear_kept_samples();
  impl_->write(impl_->scene_writer, &impl_->scene_msg, impl_->scene_slot);  // the scene is the same
}

void ServerEndpoints::flush(double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  std::vector<fdds::DataWriter*> writers = {impl_->clock_writer, impl_->status_writer, impl_->reply_writer,
                                            impl_->scene_writer};
  writers.insert(writers.end(), impl_->odometry_writers.begin(), impl_->odometry_writers.end());
  writers.insert(writers.end(), impl_->sea_state_writers.begin(), impl_->sea_state_writers.end());
  for (fdds::DataWriter* writer : impl_->joint_state_writers) {
    if (writer) writers.push_back(writer);
  }
  for (const auto& vehicle_writers : impl_->actuator_state_writers) {
    for (const auto& writer : vehicle_writers) writers.push_back(writer->writer);
  }
  for (fdds::DataWriter* writer : writers) {
    const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0.0) break;
    writer->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(left));
  }
}

std::vector<TopicCount> ServerEndpoints::published_counts() const {
  std::vector<TopicCount> result;
  std::lock_guard<std::mutex> lock(impl_->mutex);
  for (std::size_t i = 0; i < impl_->topic_names.size(); ++i) {
    result.push_back({impl_->topic_names[i], impl_->counts[i]});
  }
  return result;
}

}  // namespace hadal::dds
