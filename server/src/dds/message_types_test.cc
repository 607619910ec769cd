// The wire contract with ROS 2 for the message types Hadal publishes: registered type names follow
// ROS 2's DDS convention (pkg::msg::dds_::Type_), filled samples survive a CDR round trip, and the
// encoded layout (XCDR1, final) has the size ROS 2's own encoding gives (alignment of each member to
// its size, 4-byte encapsulation header).
#include <gtest/gtest.h>

#include "hadal/dds/topic_names.h"

#include <fastdds/rtps/common/SerializedPayload.h>
#include <marine_acoustic_msgsPubSubTypes.h>
#include <nav_msgsPubSubTypes.h>
#include <rosgraph_msgsPubSubTypes.h>
#include <sensor_msgsPubSubTypes.h>

#include <string>

namespace {

template <class PubSubType, class Message>
Message round_trip(const Message& message, std::uint32_t* encoded_size) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(
      const_cast<Message*>(&message))());
  EXPECT_TRUE(type.serialize(const_cast<Message*>(&message), &payload));
  *encoded_size = payload.length;
  Message out;
  EXPECT_TRUE(type.deserialize(&payload, &out));
  return out;
}

std_msgs::msg::Header header(const std::string& frame) {
  std_msgs::msg::Header h;
  h.stamp().sec(12);
  h.stamp().nanosec(345000000u);
  h.frame_id(frame);
  return h;
}

TEST(MessageTypesTest, TypeNamesFollowRos2) {
  EXPECT_EQ(std::string(sensor_msgs::msg::ImuPubSubType().getName()), "sensor_msgs::msg::dds_::Imu_");
  EXPECT_EQ(std::string(sensor_msgs::msg::FluidPressurePubSubType().getName()),
            "sensor_msgs::msg::dds_::FluidPressure_");
  EXPECT_EQ(std::string(sensor_msgs::msg::MagneticFieldPubSubType().getName()),
            "sensor_msgs::msg::dds_::MagneticField_");
  EXPECT_EQ(std::string(sensor_msgs::msg::NavSatFixPubSubType().getName()),
            "sensor_msgs::msg::dds_::NavSatFix_");
  EXPECT_EQ(std::string(sensor_msgs::msg::RangePubSubType().getName()), "sensor_msgs::msg::dds_::Range_");
  EXPECT_EQ(std::string(marine_acoustic_msgs::msg::DvlPubSubType().getName()),
            "marine_acoustic_msgs::msg::dds_::Dvl_");
  EXPECT_EQ(std::string(nav_msgs::msg::OdometryPubSubType().getName()), "nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(std::string(rosgraph_msgs::msg::ClockPubSubType().getName()), "rosgraph_msgs::msg::dds_::Clock_");
}

// Range: encapsulation 4 + header (sec 4, nanosec 4, frame_id "alt\0": length 4 + 4) 16 +
// radiation_type 1 + padding to 4 (3) + 4 floats 16 = 40 bytes.
TEST(MessageTypesTest, RangeRoundTripsWithRos2Layout) {
  sensor_msgs::msg::Range range;
  range.header(header("alt"));
  range.radiation_type(sensor_msgs::msg::Range_Constants::ULTRASOUND);
  range.field_of_view(0.05f);
  range.min_range(0.3f);
  range.max_range(120.0f);
  range.range(48.25f);
  std::uint32_t size = 0;
  EXPECT_EQ(round_trip<sensor_msgs::msg::RangePubSubType>(range, &size), range);
  EXPECT_EQ(size, 40u);
}

// NavSatFix: header "gps\0" 16 + status (int8, pad 1, uint16) 4 = 20, padded to 24 for the doubles
// (XCDR1 aligns relative to the end of the 4-byte encapsulation), + 12 doubles 96 + uint8 1 = 121,
// + encapsulation 4 = 125 bytes.
TEST(MessageTypesTest, NavSatFixRoundTrips) {
  sensor_msgs::msg::NavSatFix fix;
  fix.header(header("gps"));
  fix.status().status(sensor_msgs::msg::NavSatStatus_Constants::STATUS_NO_FIX);
  fix.status().service(sensor_msgs::msg::NavSatStatus_Constants::SERVICE_GPS);
  fix.latitude(43.0);
  fix.longitude(5.0);
  fix.altitude(-0.5);
  fix.position_covariance({1, 0, 0, 0, 1, 0, 0, 0, 4});
  fix.position_covariance_type(sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_DIAGONAL_KNOWN);
  std::uint32_t size = 0;
  EXPECT_EQ(round_trip<sensor_msgs::msg::NavSatFixPubSubType>(fix, &size), fix);
  EXPECT_EQ(size, 125u);
}

TEST(MessageTypesTest, DvlAndImuRoundTrip) {
  marine_acoustic_msgs::msg::Dvl dvl;
  dvl.header(header("auv/dvl"));
  dvl.velocity_mode(marine_acoustic_msgs::msg::Dvl_Constants::DVL_MODE_BOTTOM);
  dvl.dvl_type(marine_acoustic_msgs::msg::Dvl_Constants::DVL_TYPE_PISTON);
  dvl.velocity().x(1.2);
  dvl.velocity_covar({1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-4});
  dvl.altitude(12.5);
  dvl.num_good_beams(3);
  dvl.sound_speed(1500.0f);
  dvl.beam_ranges_valid(true);
  dvl.beam_velocities_valid(true);
  dvl.beam_unit_vec()[2].z(-0.866);
  dvl.range({14.4, 14.5, 0.0, 14.3});
  dvl.beam_velocity({0.6f, -0.6f, 0.0f, 0.59f});
  std::uint32_t size = 0;
  EXPECT_EQ(round_trip<marine_acoustic_msgs::msg::DvlPubSubType>(dvl, &size), dvl);

  sensor_msgs::msg::Imu imu;
  imu.header(header("auv/imu"));
  imu.orientation_covariance()[0] = -1.0;  // no orientation estimate (ROS convention)
  imu.angular_velocity().z(0.01);
  imu.linear_acceleration().z(9.81);
  EXPECT_EQ(round_trip<sensor_msgs::msg::ImuPubSubType>(imu, &size), imu);
  // 4 + header ("auv/imu\0": 4 + 8) 16 -> 24 (8-aligned) + quaternion 32 + 9 doubles 72 + vector 24
  // + 72 + 24 + 72 = 324.
  EXPECT_EQ(size, 324u);
}

TEST(TopicNames, DdsNamesToRos2s) {
  std::string name;
  EXPECT_TRUE(hadal::dds::ros_topic_name("rt/auv/odometry", &name));
  EXPECT_EQ(name, "/auv/odometry");
  EXPECT_FALSE(hadal::dds::ros_topic_name("auv/odometry", &name));
  EXPECT_TRUE(hadal::dds::ros_type_name("nav_msgs::msg::dds_::Odometry_", &name));
  EXPECT_EQ(name, "nav_msgs/msg/Odometry");
  EXPECT_TRUE(hadal::dds::ros_type_name("hadal_msgs::msg::dds_::StepReply_", &name));
  EXPECT_EQ(name, "hadal_msgs/msg/StepReply");
  for (const char* bad : {"Odometry", "nav_msgs::msg::Odometry", "nav_msgs::msg::dds_::Odometry", "::msg::dds_::A_"}) {
    EXPECT_FALSE(hadal::dds::ros_type_name(bad, &name)) << bad;
  }
}

}  // namespace
