// MonitorContent (dds/monitor.h): the monitor carries each topic's last written message, serialized as its
// own writer would (it decodes to the same message), with the topic's count; topics never written are left
// out; a fill serializes only what was noted since the last, and changed() says whether anything was.
#include "monitor.h"

#include <fastdds/rtps/common/SerializedPayload.h>
#include <hadal_msgsPubSubTypes.h>
#include <nav_msgsPubSubTypes.h>
#include <gtest/gtest.h>

namespace hadal::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;

template <class PubSubType, class Message>
Message decode(const std::vector<std::uint8_t>& cdr) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(cdr.size()));
  std::copy(cdr.begin(), cdr.end(), payload.data);
  payload.length = static_cast<std::uint32_t>(cdr.size());
  Message msg;
  PubSubType type;
  EXPECT_TRUE(type.deserialize(&payload, &msg));
  return msg;
}

TEST(MonitorContentTest, CarriesEachTopicsLastMessageAsItsWriterWouldSerializeIt) {
  MonitorContent monitor;
  const std::size_t odometry = monitor.add("/auv/odometry", "nav_msgs/msg/Odometry",
                                           fdds::TypeSupport(new nav_msgs::msg::OdometryPubSubType()));
  const std::size_t status = monitor.add("/hadal/status", "hadal_msgs/msg/SimStatus",
                                         fdds::TypeSupport(new hadal_msgs::msg::SimStatusPubSubType()));
  EXPECT_FALSE(monitor.changed());

  nav_msgs::msg::Odometry odom;
  odom.header().frame_id("world");
  odom.child_frame_id("auv/base_link");
  odom.pose().pose().position().x(1.25);
  odom.pose().pose().position().z(-3.5);
  odom.twist().twist().angular().z(0.1);
  monitor.note(odometry, &odom, 7);
  EXPECT_TRUE(monitor.changed());

  hadal_msgs::msg::Monitor out;
  ASSERT_TRUE(monitor.fill(2.5, "world", &out));
  EXPECT_FALSE(monitor.changed());
  EXPECT_EQ(out.header().stamp().sec(), 2);
  EXPECT_EQ(out.header().stamp().nanosec(), 500000000u);
  EXPECT_EQ(out.header().frame_id(), "world");
  ASSERT_EQ(out.samples().size(), 1u);  // the status was never written
  EXPECT_EQ(out.samples()[0].topic(), "/auv/odometry");
  EXPECT_EQ(out.samples()[0].type(), "nav_msgs/msg/Odometry");
  EXPECT_EQ(out.samples()[0].count(), 7u);
  EXPECT_EQ((decode<nav_msgs::msg::OdometryPubSubType, nav_msgs::msg::Odometry>(out.samples()[0].cdr())), odom);
  // What a writer puts on the wire: the 4-byte encapsulation header (CDR little endian) first.
  nav_msgs::msg::OdometryPubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t wire(type.getSerializedSizeProvider(&odom)());
  ASSERT_TRUE(type.serialize(&odom, &wire));
  EXPECT_EQ(out.samples()[0].cdr(), std::vector<std::uint8_t>(wire.data, wire.data + wire.length));

  // The odometry message changes after the fill without a note (it is not written): the monitor keeps
  // what was serialized. Then the status is written: both are carried, the odometry as before.
  odom.pose().pose().position().x(99.0);
  hadal_msgs::msg::SimStatus sim_status;
  sim_status.step_count(42);
  monitor.note(status, &sim_status, 3);
  ASSERT_TRUE(monitor.fill(2.6, "world", &out));
  ASSERT_EQ(out.samples().size(), 2u);
  EXPECT_EQ(out.samples()[0].count(), 7u);
  EXPECT_EQ((decode<nav_msgs::msg::OdometryPubSubType, nav_msgs::msg::Odometry>(out.samples()[0].cdr()))
                .pose().pose().position().x(), 1.25);
  EXPECT_EQ(out.samples()[1].topic(), "/hadal/status");
  EXPECT_EQ(out.samples()[1].count(), 3u);
  EXPECT_EQ((decode<hadal_msgs::msg::SimStatusPubSubType, hadal_msgs::msg::SimStatus>(out.samples()[1].cdr()))
                .step_count(), 42u);

  // Two notes before a fill: the latest is carried.
  odom.pose().pose().position().x(2.0);
  monitor.note(odometry, &odom, 8);
  odom.pose().pose().position().x(3.0);
  monitor.note(odometry, &odom, 9);
  ASSERT_TRUE(monitor.fill(2.7, "world", &out));
  EXPECT_EQ(out.samples()[0].count(), 9u);
  EXPECT_EQ((decode<nav_msgs::msg::OdometryPubSubType, nav_msgs::msg::Odometry>(out.samples()[0].cdr()))
                .pose().pose().position().x(), 3.0);
}

}  // namespace
}  // namespace hadal::dds
