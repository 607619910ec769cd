// Bad input at run time that the client library never sends, written by a raw DDS participant to a real
// hadald: replayed and duplicate requests, step requests to a server not in lockstep, commands stamped by
// clocks that disagree, writers hadald cannot hear (wrong type, best effort, unknown vehicle), names of any
// length, a request cut short. Each is refused with a reason on rt/hadal/status (rejected_commands,
// last_error) and a log line, or, for a request, in its reply; the server keeps running.
#include "hadal/dds/participant.h"
#include "hadal/dds/topic_names.h"
#include "hadal/dds/topic_registry.h"
#include "lockstep_server.h"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <hadal_msgsPubSubTypes.h>
#include <rosgraph_msgsPubSubTypes.h>
#include <std_msgsPubSubTypes.h>

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>

namespace hadal::test {
namespace {

namespace fdds = eprosima::fastdds::dds;

// A participant of its own on the server's domain: sends step requests and setpoints as written, reads
// the replies.
class RawPeer : public fdds::DataReaderListener {
 public:
  // A requester has a step request writer and a reply reader; a bare peer only what writer() makes.
  explicit RawPeer(int domain_id, bool requester = true)
      : participant_(dds::create_participant(domain_id, "raw_peer")), registry_(participant_) {
    if (!requester) return;
    requests_ = registry_.writer<hadal_msgs::msg::StepRequestPubSubType>(dds::step_request_topic(), 32);
    // The server's kept replies too, as the client library reads them: the two directions of endpoint
    // discovery are independent, and a reply written before hadald's writer matched this reader would
    // otherwise never arrive (topic_registry.h; a CI run lost the reply to the first request so).
    registry_.reader<hadal_msgs::msg::StepReplyPubSubType>(dds::step_reply_topic(), 32, this,
                                                           dds::TopicRegistry::Durability::kKeptSamples);
  }
  ~RawPeer() override { dds::delete_participant(participant_); }

  // Sends `request` once hadald's reader is matched and waits for the reply to its id.
  hadal_msgs::msg::StepReply send(const hadal_msgs::msg::StepRequest& request) {
    EXPECT_TRUE(matched(requests_));
    {
      std::lock_guard<std::mutex> lock(mutex_);
      replies_.erase(request.request_id());
    }
    requests_->write(const_cast<hadal_msgs::msg::StepRequest*>(&request));
    std::optional<hadal_msgs::msg::StepReply> reply;
    EXPECT_TRUE(wait_until(
        [&] {
          std::lock_guard<std::mutex> lock(mutex_);
          const auto found = replies_.find(request.request_id());
          if (found != replies_.end()) reply = found->second;
          return reply.has_value();
        },
        kWait))
        << "no reply to request " << request.request_id();
    return reply.value_or(hadal_msgs::msg::StepReply{});
  }

  // A writer of this participant on `topic` (reliable unless best_effort).
  template <class PubSubType>
  fdds::DataWriter* writer(const std::string& topic, bool best_effort = false) {
    fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
    qos.reliability().kind = best_effort ? fdds::BEST_EFFORT_RELIABILITY_QOS : fdds::RELIABLE_RELIABILITY_QOS;
    dds::apply_transport_environment(qos);
    if (publisher_ == nullptr) publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    return publisher_->create_datawriter(registry_.topic<PubSubType>(topic), qos);
  }

  static bool matched(fdds::DataWriter* writer) {
    return wait_until(
        [&] {
          fdds::PublicationMatchedStatus status;
          writer->get_publication_matched_status(status);
          return status.current_count > 0;
        },
        kWait);
  }

  void on_data_available(fdds::DataReader* reader) override {
    hadal_msgs::msg::StepReply reply;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      std::lock_guard<std::mutex> lock(mutex_);
      replies_[reply.request_id()] = reply;
    }
  }

 private:
  fdds::DomainParticipant* participant_;
  dds::TopicRegistry registry_;
  fdds::Publisher* publisher_ = nullptr;
  fdds::DataWriter* requests_ = nullptr;
  std::mutex mutex_;
  std::map<std::uint64_t, hadal_msgs::msg::StepReply> replies_;
};

hadal_msgs::msg::StepRequest request(std::uint64_t id, std::uint32_t steps) {
  hadal_msgs::msg::StepRequest r;
  r.request_id(id);
  r.steps(steps);
  return r;
}

// Waits for a status whose last_error contains `text`; returns it ("" if none came).
std::string status_error(Client& client, const std::string& text) {
  std::string last;
  wait_until(
      [&] {
        const auto status = client.latest_status();
        last = status ? status->last_error : "";
        return last.find(text) != std::string::npos;
      },
      kWait);
  return last;
}

TEST(RuntimeInputTest, ReplayedAndDuplicatedRequestsAreRefusedAndChangeNothing) {
  LockstepServer s;
  s.connect();
  RawPeer peer(s.domain());
  hadal_msgs::msg::StepReply reply = peer.send(request(5, 10));
  ASSERT_TRUE(reply.accepted()) << reply.error();
  EXPECT_NEAR(reply.sim_time_s(), 0.02, 1e-12);

  // The same id again, and an older one: replays, refused; nothing stepped.
  for (std::uint64_t id : {5, 4}) {
    reply = peer.send(request(id, 10));
    EXPECT_FALSE(reply.accepted());
    EXPECT_NE(reply.error().find("request_id " + std::to_string(id) + " replayed"), std::string::npos)
        << reply.error();
    EXPECT_NEAR(reply.sim_time_s(), 0.02, 1e-12);
  }
  // One vehicle's setpoints twice in one request, one vehicle's reset pose twice.
  hadal_msgs::msg::StepRequest twice = request(6, 10);
  twice.vehicle_names({"auv", "auv"});
  twice.setpoint_counts({3, 3});
  twice.setpoints({0.1, 0, 0, 0.9, 0, 0});
  reply = peer.send(twice);
  EXPECT_FALSE(reply.accepted());
  EXPECT_EQ(reply.error(), "vehicle 'auv' has setpoints attached twice");
  hadal_msgs::msg::StepRequest two_poses = request(7, 0);
  two_poses.reset(true);
  two_poses.reset_vehicle_names({"auv", "auv"});
  two_poses.reset_poses({0, 0, -50, 0, 0, 0, 1, 5, 0, -50, 0, 0, 0, 1});
  reply = peer.send(two_poses);
  EXPECT_FALSE(reply.accepted());
  EXPECT_EQ(reply.error(), "reset: vehicle 'auv' has two poses");
  EXPECT_NEAR(reply.sim_time_s(), 0.02, 1e-12);  // no reset happened

  // A name of 10 000 characters is echoed as its first 64.
  hadal_msgs::msg::StepRequest long_name = request(8, 10);
  long_name.vehicle_names({std::string(10000, 'x')});
  long_name.setpoint_counts({0});
  reply = peer.send(long_name);
  EXPECT_FALSE(reply.accepted());
  EXPECT_LT(reply.error().size(), 200u) << reply.error();
  EXPECT_NE(reply.error().find("... (10000 characters)"), std::string::npos) << reply.error();

  // An increasing id is fine again, and the status counts each refusal with the last reason.
  reply = peer.send(request(9, 10));
  EXPECT_TRUE(reply.accepted()) << reply.error();
  EXPECT_NEAR(reply.sim_time_s(), 0.04, 1e-12);
  EXPECT_TRUE(wait_until(
      [&] {
        const auto status = s.client().latest_status();
        return status && status->rejected_commands >= 5;
      },
      kWait));
  EXPECT_TRUE(wait_until([&] { return s.server().err().find("replayed") != std::string::npos; }, kWait))
      << s.server().err();
  // The client library's own requests, with ids of their own writer, are unaffected.
  EXPECT_NEAR(s.client().step(10), 0.06, 1e-12);
}

// Joint-controller commands attached to step requests (tests/integration/scenarios/arm.yaml): malformed
// ones (counts that do not add up, an unknown controller, a position beyond the joint's limit, NaN) are
// refused with the reason and step nothing; the server goes on, and a good one is applied before the step.
TEST(RuntimeInputTest, JointCommandsInStepRequestsAreCheckedBeforeAnythingSteps) {
  LockstepServer s("tests/integration/scenarios/arm.yaml");
  s.connect();
  RawPeer peer(s.domain());
  const auto with_joint_command = [](std::uint64_t id, const std::string& controller, std::vector<double> values,
                                     std::uint32_t count) {
    hadal_msgs::msg::StepRequest r = request(id, 10);
    r.joint_command_vehicles({"arm"});
    r.joint_command_controllers({controller});
    r.joint_command_counts({count});
    r.joint_commands(std::move(values));
    return r;
  };
  const std::vector<std::pair<hadal_msgs::msg::StepRequest, std::string>> refused = {
      {with_joint_command(1, "shoulder_position", {0.1, 0.2}, 1),
       "joint_command_counts add up to 1 but 2 joint commands are attached"},
      {with_joint_command(2, "elbow", {0.1}, 1),
       "arm: vehicle 'arm' has no joint controller 'elbow' (it has shoulder_position, forearm_effort)"},
      {with_joint_command(3, "shoulder_position", {3.0}, 1),
       "arm: vehicle 'arm': joint controller 'shoulder_position': position 3 for 'shoulder' is outside its limits "
       "[-2.0943951023931953, 2.0943951023931953]"},
      {with_joint_command(4, "forearm_effort", {std::nan("")}, 1),
       "arm: vehicle 'arm': joint controller 'forearm_effort': value 0 (forearm) is not finite"}};
  for (const auto& [bad, reason] : refused) {
    const hadal_msgs::msg::StepReply reply = peer.send(bad);
    EXPECT_FALSE(reply.accepted());
    EXPECT_EQ(reply.error(), reason);
    EXPECT_EQ(reply.sim_time_s(), 0.0);
  }
  const hadal_msgs::msg::StepReply reply = peer.send(with_joint_command(5, "forearm_effort", {0.25}, 1));
  ASSERT_TRUE(reply.accepted()) << reply.error();
  EXPECT_NEAR(reply.sim_time_s(), 0.02, 1e-12);
}

TEST(RuntimeInputTest, StepRequestsToAServerNotInLockstepAreRefusedAtOnce) {
  DomainLease domain;
  ServerProcess server({source_path(kClientScenario), "--mode", "realtime", "--domain-id",
                        std::to_string(domain.id()), "--no-status-line"});
  Client client(ClientOptions{domain.id(), "runtime_input_test"});
  ASSERT_TRUE(client.wait_for_server(kWait)) << server.err();
  try {
    client.step(10, kWait);
    ADD_FAILURE() << "a realtime server accepted a step request";
  } catch (const CommandRejected& e) {
    EXPECT_EQ(e.reason(), "hadald runs in realtime mode; step and reset requests need --mode lockstep");
  }
  EXPECT_NE(status_error(client, "need --mode lockstep").find("step request"), std::string::npos);
  EXPECT_TRUE(server.running());
}

// Two senders whose clocks disagree by an hour: the later arrival wins between senders (stamps of different
// clocks are never compared), so the one with the slow clock is not shut out. Within one sender, a sample
// stamped before the one applied last is stale and ignored.
TEST(RuntimeInputTest, CommandsOfSendersWithDifferentClocksAreNeverDroppedByTheirStamps) {
  LockstepServer s;
  std::vector<double> setpoint;
  std::mutex mutex;
  s.client().on_thruster_state("auv", [&](const ThrusterStates& t) {
    std::lock_guard<std::mutex> lock(mutex);
    setpoint = t.setpoint;
  });
  s.connect();
  RawPeer fast_clock(s.domain(), false), slow_clock(s.domain(), false);
  using Setpoints = std_msgs::msg::Float64MultiArrayPubSubType;
  fdds::DataWriter* ahead = fast_clock.writer<Setpoints>(dds::actuator_commands_topic("auv"));
  fdds::DataWriter* behind = slow_clock.writer<Setpoints>(dds::actuator_commands_topic("auv"));
  ASSERT_TRUE(RawPeer::matched(ahead) && RawPeer::matched(behind));
  const auto write_at = [](fdds::DataWriter* writer, double value, std::int64_t stamp_s) {
    std_msgs::msg::Float64MultiArray msg;
    msg.data({value, 0.0, 0.0});
    EXPECT_EQ(writer->write_w_timestamp(&msg, fdds::HANDLE_NIL, eprosima::fastrtps::Time_t(static_cast<std::int32_t>(stamp_s), 0u)),
              ReturnCode_t::RETCODE_OK);
  };
  const std::int64_t now = static_cast<std::int64_t>(std::time(nullptr));
  const auto main_setpoint_after_steps = [&] {
    // Commands are taken at step boundaries; the thruster state (20 Hz) shows the one in force.
    const double t = s.client().step(50);
    EXPECT_TRUE(wait_until(
        [&] {
          std::lock_guard<std::mutex> lock(mutex);
          return !setpoint.empty();
        },
        kWait));
    (void)t;
    std::lock_guard<std::mutex> lock(mutex);
    return setpoint.empty() ? std::nan("") : setpoint[0];
  };
  write_at(ahead, 0.3, now + 3600);
  ASSERT_TRUE(wait_until([&] { return main_setpoint_after_steps() == 0.3; }, kWait));
  write_at(behind, 0.7, now);  // an hour "older" by its stamp, but from another clock: applied
  EXPECT_TRUE(wait_until([&] { return main_setpoint_after_steps() == 0.7; }, kWait));
  write_at(behind, 0.2, now - 10);  // older than its own sender's last: stale, ignored
  write_at(behind, 0.9, now + 1);
  EXPECT_TRUE(wait_until([&] { return main_setpoint_after_steps() == 0.9; }, kWait));
  const std::uint64_t rejected = s.client().latest_status()->rejected_commands;
  EXPECT_EQ(rejected, 0u) << s.client().latest_status()->last_error;
}

TEST(RuntimeInputTest, WritersHadaldCannotHearAreReportedOnTheStatus) {
  LockstepServer s;
  s.connect();
  RawPeer peer(s.domain(), false);
  // Best effort on a reliable reader: DDS never matches them.
  peer.writer<std_msgs::msg::Float64MultiArrayPubSubType>(dds::actuator_commands_topic("auv"), true);
  EXPECT_NE(status_error(s.client(), "best-effort writer").find("rt/auv/actuators/commands"), std::string::npos);
  // Another type on the step request topic.
  peer.writer<rosgraph_msgs::msg::ClockPubSubType>(dds::step_request_topic());
  EXPECT_NE(status_error(s.client(), "rosgraph_msgs::msg::dds_::Clock_").find("are ignored: hadald reads"),
            std::string::npos);
  // A vehicle the scenario does not have.
  peer.writer<std_msgs::msg::Float64MultiArrayPubSubType>(dds::actuator_commands_topic("ghost"));
  EXPECT_NE(status_error(s.client(), "unknown vehicle 'ghost'").find("rt/ghost/actuators/commands"),
            std::string::npos);
  EXPECT_GE(s.client().latest_status()->rejected_commands, 3u);
  EXPECT_NEAR(s.client().step(10), 0.02, 1e-12);
  const std::string err = s.server().err();
  EXPECT_NE(err.find("a best-effort writer on rt/auv/actuators/commands reaches nothing"), std::string::npos) << err;
}

// A type that writes the bytes it is given as the sample, under the DDS type name of a step request: what
// a broken or hostile peer can put on the wire.
class RawStepRequestType : public fdds::TopicDataType {
 public:
  RawStepRequestType() {
    setName(hadal_msgs::msg::StepRequestPubSubType().getName());
    m_typeSize = 65536;
    m_isGetKeyDefined = false;
  }
  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    const auto* bytes = static_cast<const std::string*>(data);
    std::memcpy(payload->data, bytes->data(), bytes->size());
    payload->length = static_cast<std::uint32_t>(bytes->size());
    return true;
  }
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t*, void*) override { return false; }
  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
    return [data] { return static_cast<std::uint32_t>(static_cast<const std::string*>(data)->size()); };
  }
  void* createData() override { return new std::string(); }
  void deleteData(void* data) override { delete static_cast<std::string*>(data); }
  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }
};

// A sample whose sequence claims 2^31 setpoints in 40 bytes (refused by Fast CDR before it allocates) and
// one with an encapsulation no final type has (Fast CDR throws what the generated code does not catch,
// dds/guarded_type.h): both dropped and counted, the server steps on.
TEST(RuntimeInputTest, UndecodableSamplesAreDroppedAndCountedNotACrash) {
  LockstepServer s;
  s.connect();
  fdds::DomainParticipant* participant = dds::create_participant(s.domain(), "raw_bytes");
  fdds::TypeSupport type(new RawStepRequestType());
  type.register_type(participant);
  fdds::Topic* topic = participant->create_topic(dds::step_request_topic(), type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  fdds::Publisher* publisher = participant->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  dds::apply_transport_environment(qos);
  fdds::DataWriter* writer = publisher->create_datawriter(topic, qos);
  ASSERT_TRUE(RawPeer::matched(writer));
  // Little-endian CDR: request_id, steps 1, no vehicle names, no counts, 2^31 setpoints and 8 bytes of them.
  std::string bomb("\x00\x01\x00\x00", 4);
  bomb += std::string("\x01\0\0\0\0\0\0\0" "\x01\0\0\0" "\0\0\0\0" "\0\0\0\0" "\0\0\0\x80", 28);
  bomb += std::string(8, '\0');
  writer->write(&bomb);
  EXPECT_NE(status_error(s.client(), "undecodable").find("1 undecodable sample(s) dropped"), std::string::npos);
  std::string bad_encapsulation("\x00\x07\x00\x00" "\x02\0\0\0\0\0\0\0" "\x01\0\0\0", 16);
  writer->write(&bad_encapsulation);
  EXPECT_TRUE(wait_until([&] { return s.client().latest_status()->rejected_commands >= 2; }, kWait))
      << s.client().latest_status()->last_error;
  EXPECT_TRUE(s.server().running());
  EXPECT_NEAR(s.client().step(10), 0.02, 1e-12);
  dds::delete_participant(participant);
}

TEST(RuntimeInputTest, ARequestCutShortByTheDurationSaysSoInItsReply) {
  LockstepServer s(kClientScenario, {"--duration", "0.1"});
  s.connect();
  try {
    s.client().step(1000);
    ADD_FAILURE() << "a request cut short was accepted";
  } catch (const CommandRejected& e) {
    EXPECT_EQ(e.reason(),
              "stopped after 50 of 1000 steps: the server is shutting down or reached its --duration");
  }
  EXPECT_EQ(s.server().wait(kWait), 0);
}

}  // namespace
}  // namespace hadal::test
