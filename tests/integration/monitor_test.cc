// rt/hadal/monitor end to end (server/src/dds/monitor.h): a lockstep hadald writes no monitor until a reader
// matches; then, within a few wall intervals of a step, a monitor whose odometry entry is, byte for byte, the
// last sample the odometry topic carried, with that topic's count; every entry names its topic's ROS 2 type,
// the status rides along, and nothing large (no camera image) nor the clock, scene or step replies.
// And the forward-looking sonar's preview (dds/image_preview.h): its ping drawn as a fan, written while read.
#include "lockstep_server.h"

#include "hadal/dds/topic_names.h"
#include "hadal/record/topic_tap.h"

#include <fastdds/rtps/common/SerializedPayload.h>
#include <hadal_msgsPubSubTypes.h>
#include <nav_msgsPubSubTypes.h>
#include <sensor_msgsPubSubTypes.h>

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

namespace hadal::test {
namespace {

template <class PubSubType, class Message>
bool decode(const std::vector<unsigned char>& bytes, Message* msg) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  std::copy(bytes.begin(), bytes.end(), payload.data);
  payload.length = static_cast<std::uint32_t>(bytes.size());
  PubSubType type;
  return type.deserialize(&payload, msg);
}

double stamp_of(const std_msgs::msg::Header& header) { return header.stamp().sec() + 1e-9 * header.stamp().nanosec(); }

class Taken {
 public:
  void add(const hadal::record::TappedSample& sample) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (sample.topic == "rt/hadal/monitor") {
      hadal_msgs::msg::Monitor msg;
      EXPECT_TRUE((decode<hadal_msgs::msg::MonitorPubSubType>(sample.bytes, &msg)));
      monitors_.push_back(msg);
    } else {
      odometry_.push_back(sample.bytes);
    }
  }
  std::vector<hadal_msgs::msg::Monitor> monitors() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return monitors_;
  }
  std::vector<std::vector<unsigned char>> odometry() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return odometry_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<hadal_msgs::msg::Monitor> monitors_;
  std::vector<std::vector<unsigned char>> odometry_;
};

const hadal_msgs::msg::MonitorSample* entry(const hadal_msgs::msg::Monitor& monitor, const std::string& topic) {
  for (const auto& sample : monitor.samples()) {
    if (sample.topic() == topic) return &sample;
  }
  return nullptr;
}

TEST(MonitorTest, CarriesEachLightTopicsLatestSampleWhileRead) {
  LockstepServer server("configs/scenarios/default.yaml");
  server.connect();
  server.client().step(50);  // 0.1 s: nobody reads the monitor yet

  // Declared before the tap, whose callback fills it: destroyed after it (record/topic_tap.h). The other way
  // round a monitor arriving while the test ended could meet a destroyed Taken (the likely cause of a crash
  // seen once in CI).
  Taken taken;
  record::TopicTap tap(server.domain(), "monitor_test");
  ASSERT_TRUE(tap.discover(kWait));
  const auto writers = tap.writers();
  ASSERT_EQ(writers.count("rt/hadal/monitor"), 1u);
  EXPECT_EQ(writers.at("rt/hadal/monitor").type, "hadal_msgs::msg::dds_::Monitor_");
  ASSERT_TRUE(tap.subscribe([&](const record::TappedSample& sample) { taken.add(sample); }, kWait, false,
                            [](const std::string& topic, const record::TappedWriter&) {
                              return topic == "rt/hadal/monitor" || topic == "rt/auv/odometry";
                            }));
  // Lockstep: the server waits for requests, and writes the monitor as its wall clock comes by (the status
  // heartbeat changes it ten times a second).
  const double t = server.client().step(450);  // to 1.0 s
  ASSERT_NEAR(t, 1.0, 1e-9);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(kWait);
  const hadal_msgs::msg::MonitorSample* odometry = nullptr;
  hadal_msgs::msg::Monitor last;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto monitors = taken.monitors();
    if (!monitors.empty()) {
      last = monitors.back();
      odometry = entry(last, "/auv/odometry");
      nav_msgs::msg::Odometry odom;
      if (odometry != nullptr && decode<nav_msgs::msg::OdometryPubSubType>(odometry->cdr(), &odom) &&
          std::abs(stamp_of(odom.header()) - 1.0) < 1e-9) {
        break;
      }
    }
    odometry = nullptr;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_NE(odometry, nullptr) << "no monitor with the odometry at t = 1 s; stderr:\n" << server.server().err();
  // Byte for byte the odometry topic's last sample (t = 1 s), and its count: 51 samples at 50 Hz from t = 0.
  const auto odometry_samples = taken.odometry();
  ASSERT_FALSE(odometry_samples.empty());
  EXPECT_EQ(odometry->cdr(), odometry_samples.back());
  EXPECT_EQ(odometry->type(), "nav_msgs/msg/Odometry");
  EXPECT_EQ(odometry->count(), 51u);
  EXPECT_EQ(last.header().frame_id(), "world");
  ASSERT_NE(entry(last, "/hadal/status"), nullptr);
  EXPECT_EQ(entry(last, "/hadal/status")->type(), "hadal_msgs/msg/SimStatus");
  for (const char* carried : {"/auv/imu", "/auv/dvl", "/auv/depth", "/auv/altimeter", "/auv/thrusters/state",
                              "/auv/camera/camera_info"}) {
    EXPECT_NE(entry(last, carried), nullptr) << carried;
  }
  for (const char* left_out : {"/auv/camera/image_raw", "/auv/camera/depth", "/auv/camera/preview", "/clock",
                               "/hadal/scene", "/hadal/step_reply", "/hadal/monitor"}) {
    EXPECT_EQ(entry(last, left_out), nullptr) << left_out;
  }
  // Each entry's type is its topic writer's, in ROS 2's spelling.
  for (const auto& sample : last.samples()) {
    const std::string dds_topic = "rt" + sample.topic();
    ASSERT_EQ(writers.count(dds_topic), 1u) << sample.topic();
    std::string type;
    ASSERT_TRUE(dds::ros_type_name(writers.at(dds_topic).type, &type));
    EXPECT_EQ(sample.type(), type);
    EXPECT_GT(sample.count(), 0u);
  }
}

// tests/integration/scenarios/sonar.yaml: the FLS 20 m above a plane, pitched 30 deg down with a 20 deg
// aperture, hears the seabed from 20 / sin 40 deg = 31 m to 20 / sin 20 deg = 58 m of its 60 m window (noise
// off). Its preview, once read, is that ping as a mono8 fan of FlsSensor::kPreviewHeight = 300 rows (10 px
// margins: 280 / 60 px per m), the sonar at the bottom centre: lit ahead at 45 m, black at 10 m.
TEST(PreviewTest, ForwardLookingSonarPreviewIsItsFanWhileRead) {
  LockstepServer server("tests/integration/scenarios/sonar.yaml");
  server.connect();
  std::mutex mutex;  // these two before the tap, whose callback uses them: destroyed after it
  std::vector<std::vector<unsigned char>> previews;
  record::TopicTap tap(server.domain(), "preview_test");
  ASSERT_TRUE(tap.discover(kWait));
  ASSERT_EQ(tap.writers().count("rt/auv/fls/preview"), 1u);
  ASSERT_TRUE(tap.subscribe(
      [&](const record::TappedSample& sample) {
        std::lock_guard<std::mutex> lock(mutex);
        previews.push_back(sample.bytes);
      },
      kWait, false, [](const std::string& topic, const record::TappedWriter&) { return topic == "rt/auv/fls/preview"; }));
  ASSERT_NEAR(server.client().step(150), 0.3, 1e-9);  // pings at 0 and 0.2 s, published 0.05 s later
  sensor_msgs::msg::Image image;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(kWait);
  bool got = false;
  while (!got && std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      got = !previews.empty() && decode<sensor_msgs::msg::ImagePubSubType>(previews.back(), &image);
    }
    if (!got) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(got) << "no preview; stderr:\n" << server.server().err();
  EXPECT_EQ(image.encoding(), "mono8");
  EXPECT_EQ(image.header().frame_id(), "auv/fls");
  ASSERT_EQ(image.height(), 300u);
  ASSERT_EQ(image.data().size(), static_cast<std::size_t>(image.width()) * image.height());
  const double px_per_m = 280.0 / 60.0;
  const auto grey_at = [&](double range_m) {
    const auto v = static_cast<std::size_t>(290.0 - range_m * px_per_m);
    return image.data()[v * image.width() + image.width() / 2];
  };
  EXPECT_GT(grey_at(45.0), 0);
  EXPECT_EQ(grey_at(10.0), 0);
}

}  // namespace
}  // namespace hadal::test
