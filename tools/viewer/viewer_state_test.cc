// ViewerState (viewer_state.h) fed CDR samples as DDS delivers them: what a poll sends the page, and only
// once; trails and series start over when time goes back; a scene sent again changes nothing; camera frames
// go as JPEG at most once per interval, and only 8-bit ones; bytes that do not decode are counted.
#include "viewer_state.h"

#include <fastdds/rtps/common/SerializedPayload.h>
#include <gtest/gtest.h>
#include <hadal_msgsPubSubTypes.h>
#include <nav_msgsPubSubTypes.h>
#include <rosgraph_msgsPubSubTypes.h>
#include <sensor_msgsPubSubTypes.h>

#include <opencv2/imgcodecs.hpp>

#include <set>
#include <string>
#include <vector>

namespace hadal::viewer {
namespace {

template <class PubSubType, class Message>
std::vector<unsigned char> cdr(Message& msg) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&msg)());
  EXPECT_TRUE(type.serialize(&msg, &payload));
  return std::vector<unsigned char>(payload.data, payload.data + payload.length);
}

void add_odometry(ViewerState& state, double t, double x, double z) {
  nav_msgs::msg::Odometry msg;
  msg.header().stamp().sec(static_cast<std::int32_t>(std::floor(t)));
  msg.header().stamp().nanosec(static_cast<std::uint32_t>(std::llround((t - std::floor(t)) * 1e9)));
  msg.pose().pose().position().x(x);
  msg.pose().pose().position().z(z);
  msg.pose().pose().orientation().w(1.0);
  msg.twist().twist().linear().x(1.0);
  const auto bytes = cdr<nav_msgs::msg::OdometryPubSubType>(msg);
  state.add("/auv/odometry", "nav_msgs/msg/Odometry", bytes.data(), bytes.size());
}

void add_clock(ViewerState& state, double t) {
  rosgraph_msgs::msg::Clock msg;
  msg.clock().sec(static_cast<std::int32_t>(std::floor(t)));
  msg.clock().nanosec(static_cast<std::uint32_t>(std::llround((t - std::floor(t)) * 1e9)));
  const auto bytes = cdr<rosgraph_msgs::msg::ClockPubSubType>(msg);
  state.add("/clock", "rosgraph_msgs/msg/Clock", bytes.data(), bytes.size());
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The JSON array after `"key":` (flat arrays only).
std::string array_after(const std::string& json, const std::string& key) {
  const std::size_t start = json.find("\"" + key + "\":[");
  if (start == std::string::npos) return "";
  const std::size_t open = json.find('[', start);
  return json.substr(open, json.find(']', open) - open + 1);
}

std::size_t numbers_in(const std::string& array) { return array == "[]" ? 0 : count(array, ",") + 1; }

// The AUV at 1 m/s along x, 96 m down (the water surface at z = 0 without a scene), odometry at 50 Hz for
// 1 s: the pose as it came, a trail point every 5 cm (the first, then every third sample: 0.06 m apart), and
// depth at 10 Hz of sim time.
TEST(ViewerStateTest, OdometryBecomesPoseTrailAndSeriesSentOnce) {
  ViewerState state;
  for (int i = 0; i <= 50; ++i) add_odometry(state, 0.02 * i, 0.02 * i, -96.0);
  PushOutput out = state.poll(0.0);
  // The first poll starts the pages' history: the series so far are in it, not in the update.
  ASSERT_FALSE(out.history_json.empty());
  EXPECT_NE(out.history_json.find("\"auv/depth\":{\"plot\":\"auv depth\",\"label\":\"depth\",\"unit\":\"m\","),
            std::string::npos);
  const std::string depth_times = out.history_json.substr(out.history_json.find("\"auv/depth\""));
  EXPECT_EQ(numbers_in(array_after(depth_times, "t")), 11u);
  EXPECT_EQ(array_after(depth_times, "v").substr(0, 4), "[96,");
  EXPECT_EQ(count(out.update_json, "[\"auv/depth\","), 0u);
  EXPECT_NE(out.update_json.find("\"auv\":{\"stamp\":1,\"p\":[1,0,-96],\"q\":[0,0,0,1]"), std::string::npos)
      << out.update_json;
  EXPECT_EQ(numbers_in(array_after(out.update_json, "trail")), 3u * 17u);

  // The next poll carries only what came since, with what a page needs to plot it.
  add_odometry(state, 1.1, 1.1, -96.5);
  out = state.poll(0.0);
  EXPECT_TRUE(out.history_json.empty());
  EXPECT_EQ(count(out.update_json, "[\"auv/depth\","), 1u);
  EXPECT_NE(out.update_json.find("[\"auv/depth\",56,1.1,96.5]"), std::string::npos) << out.update_json;
  EXPECT_NE(out.update_json.find("\"auv/depth\":{\"plot\":\"auv depth\",\"label\":\"depth\",\"unit\":\"m\"}"),
            std::string::npos);
  EXPECT_NE(out.update_json.find("\"trail_from\":17,\"trail\":[1.1000000"), std::string::npos)
      << out.update_json;
  out = state.poll(0.0);
  EXPECT_EQ(count(out.update_json, "[\"auv/depth\","), 0u);
  EXPECT_EQ(array_after(out.update_json, "trail"), "[]");

  // A page that joins now gets the whole trail and series in its history, and no points twice.
  const PushOutput all = state.everything();
  EXPECT_NE(all.history_json.find("\"auv\":{\"total\":18,\"points\":["), std::string::npos) << all.history_json;
  EXPECT_EQ(count(all.update_json, "[\"auv/depth\","), 0u);
  EXPECT_EQ(state.samples(), 52u);
  EXPECT_EQ(state.undecodable(), 0u);
}

TEST(ViewerStateTest, TimeGoingBackStartsTrailsAndSeriesOver) {
  ViewerState state;
  for (int i = 0; i <= 50; ++i) add_odometry(state, 0.02 * i, 0.02 * i, -96.0);
  state.poll(0.0);
  add_odometry(state, 0.0, 5.0, -90.0);  // a lockstep reset: sim time 0 again
  const PushOutput out = state.poll(0.0);
  ASSERT_FALSE(out.history_json.empty());
  EXPECT_NE(out.history_json.find("\"auv\":{\"total\":1,\"points\":[5,0,-90]}"), std::string::npos)
      << out.history_json;
  EXPECT_NE(out.history_json.find("\"auv/depth\":{\"plot\":\"auv depth\",\"label\":\"depth\",\"unit\":\"m\","
                                  "\"t\":[0],\"v\":[90]}"),
            std::string::npos)
      << out.history_json;
}

// A bag whose recorder took the odometry late, as one under load does: /clock has reached 1.6 s when the
// odometry stamped 1.0 s comes. Topics are not in order among themselves, so that is no reset: the trail
// goes on (one point every 5 cm, the odometry 0.1 m apart), and a topic's own time going back still starts over.
TEST(ViewerStateTest, ATopicLateAgainstAnotherIsNoReset) {
  ViewerState state;
  for (int i = 0; i <= 16; ++i) add_clock(state, 0.1 * i);
  for (int i = 0; i <= 10; ++i) add_odometry(state, 0.1 * i, 0.1 * i, -96.0);
  PushOutput out = state.poll(0.0);
  EXPECT_NE(out.history_json.find("\"auv\":{\"total\":11,"), std::string::npos) << out.history_json;
  add_clock(state, 1.7);
  add_odometry(state, 1.1, 1.1, -96.0);
  out = state.poll(0.0);
  EXPECT_TRUE(out.history_json.empty()) << out.history_json;
  EXPECT_NE(out.update_json.find("\"sim_time\":1.7"), std::string::npos) << out.update_json;
  EXPECT_NE(out.update_json.find("\"trail_from\":11,\"trail\":[1.1"), std::string::npos) << out.update_json;
  add_clock(state, 0.0);  // a lockstep reset: /clock at 0 again
  out = state.poll(0.0);
  EXPECT_FALSE(out.history_json.empty());
  EXPECT_NE(out.update_json.find("\"sim_time\":0,"), std::string::npos) << out.update_json;
}

hadal_msgs::msg::Scene scene(float z) {
  hadal_msgs::msg::Scene msg;
  msg.scenario("test.yaml");
  msg.water_surface_z(10.0);
  msg.vehicle_names({"auv"});
  hadal_msgs::msg::SceneMesh& mesh = msg.meshes().emplace_back();
  mesh.name("seabed");
  mesh.positions({0, 0, z, 1, 0, z, 0, 1, z});
  mesh.indices({0, 1, 2});
  return msg;
}

// An articulated vehicle: the scene's links go to the page with their kinematics, and each vehicle's latest
// joint positions (rt/<vehicle>/joint_states) ride with its pose, by joint name.
TEST(ViewerStateTest, TheScenesLinksAndTheLatestJointPositionsReachThePage) {
  ViewerState state;
  hadal_msgs::msg::Scene msg = scene(-100.0f);
  hadal_msgs::msg::SceneLink& link = msg.links().emplace_back();
  link.vehicle("auv");
  link.name("upper_arm");
  link.parent("base_link");
  link.joint("shoulder");
  link.joint_type("revolute");
  link.pose().position().x(0.5);
  link.pose().orientation().w(1.0);
  link.axis().y(1.0);
  const auto scene_bytes = cdr<hadal_msgs::msg::ScenePubSubType>(msg);
  state.add("/hadal/scene", "hadal_msgs/msg/Scene", scene_bytes.data(), scene_bytes.size());
  const PushOutput first = state.poll(0.0);
  EXPECT_NE(first.scene_json.find("\"links\":[{\"vehicle\":\"auv\",\"name\":\"upper_arm\",\"parent\":\"base_link\","
                                  "\"joint\":\"shoulder\",\"joint_type\":\"revolute\",\"p\":[0.5,0,0],"
                                  "\"q\":[0,0,0,1],\"axis\":[0,1,0]}]"),
            std::string::npos)
      << first.scene_json;

  add_odometry(state, 1.0, 0.0, -96.0);
  for (const double q : {0.25, -0.75}) {
    sensor_msgs::msg::JointState joints;
    joints.header().stamp().sec(1);
    joints.name({"shoulder", "elbow"});
    joints.position({q, 2.0 * q});
    const auto bytes = cdr<sensor_msgs::msg::JointStatePubSubType>(joints);
    state.add("/auv/joint_states", "sensor_msgs/msg/JointState", bytes.data(), bytes.size());
  }
  const PushOutput update = state.poll(1.0);
  EXPECT_NE(update.update_json.find("\"joints\":{\"elbow\":-1.5,\"shoulder\":-0.75}"), std::string::npos)
      << update.update_json;
  EXPECT_EQ(state.undecodable(), 0u);
}

TEST(ViewerStateTest, TheSameSceneAgainChangesNothingAnotherStartsOver) {
  ViewerState state;
  auto first = scene(-100.0f);
  const auto bytes = cdr<hadal_msgs::msg::ScenePubSubType>(first);
  state.add("/hadal/scene", "hadal_msgs/msg/Scene", bytes.data(), bytes.size());
  PushOutput out = state.poll(0.0);
  EXPECT_NE(out.scene_json.find("\"scenario\":\"test.yaml\""), std::string::npos) << out.scene_json;
  ASSERT_EQ(out.mesh_messages.size(), 1u);
  // "MESH", name length 1, "0" padded to 4 bytes, 9 floats, 3 indices, then the data.
  EXPECT_EQ(out.mesh_messages[0].size(), 4u + 4u + 4u + 8u + 9u * 4u + 3u * 4u);
  EXPECT_EQ(out.mesh_messages[0].substr(0, 4), "MESH");
  add_odometry(state, 0.0, 0.0, -96.0);  // depth below the scene's water surface at z = 10
  out = state.poll(0.0);
  EXPECT_NE(out.update_json.find("[\"auv/depth\",1,0,106]"), std::string::npos) << out.update_json;

  state.add("/hadal/scene", "hadal_msgs/msg/Scene", bytes.data(), bytes.size());
  out = state.poll(0.0);
  EXPECT_TRUE(out.scene_json.empty());
  EXPECT_TRUE(out.history_json.empty());

  auto second = scene(-50.0f);
  const auto other = cdr<hadal_msgs::msg::ScenePubSubType>(second);
  state.add("/hadal/scene", "hadal_msgs/msg/Scene", other.data(), other.size());
  out = state.poll(0.0);
  EXPECT_FALSE(out.scene_json.empty());
  EXPECT_FALSE(out.history_json.empty());
}

std::vector<unsigned char> image(const std::string& encoding, int width, int height, int bytes_per_pixel,
                                 unsigned char value) {
  sensor_msgs::msg::Image msg;
  msg.header().stamp().sec(2);
  msg.width(width);
  msg.height(height);
  msg.encoding(encoding);
  msg.step(width * bytes_per_pixel);
  msg.data(std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * bytes_per_pixel, value));
  return cdr<sensor_msgs::msg::ImagePubSubType>(msg);
}

TEST(ViewerStateTest, CameraFramesGoAsJpegAtMostOncePerInterval) {
  ViewerState state(0.2);
  const auto rgb = image("rgb8", 8, 4, 3, 200);
  state.add("/auv/camera/preview", "sensor_msgs/msg/Image", rgb.data(), rgb.size());
  const auto depth = image("32FC1", 8, 4, 4, 0);
  state.add("/auv/camera/depth", "sensor_msgs/msg/Image", depth.data(), depth.size());
  PushOutput out = state.poll(10.0);
  ASSERT_EQ(out.image_messages.size(), 1u);  // the depth image is listed, not sent
  const std::string& message = out.image_messages[0];
  EXPECT_EQ(message.substr(0, 4), "JPEG");
  const std::string name = "/auv/camera/preview";
  const std::size_t offset = 8 + name.size() + (4 - name.size() % 4) % 4;
  EXPECT_EQ(message.substr(8, name.size()), name);
  const cv::Mat decoded = cv::imdecode(std::vector<unsigned char>(message.begin() + offset, message.end()),
                                       cv::IMREAD_COLOR);
  ASSERT_EQ(decoded.cols, 8);
  EXPECT_NEAR(decoded.at<cv::Vec3b>(2, 4)[1], 200, 3);  // JPEG: within a few counts of the flat grey
  EXPECT_NE(out.update_json.find("\"/auv/camera/depth\":{\"frames\":1"), std::string::npos) << out.update_json;

  state.add("/auv/camera/preview", "sensor_msgs/msg/Image", rgb.data(), rgb.size());
  EXPECT_TRUE(state.poll(10.1).image_messages.empty());  // 0.1 s after the last: not yet
  EXPECT_EQ(state.poll(10.25).image_messages.size(), 1u);
  EXPECT_TRUE(state.poll(10.5).image_messages.empty());  // no new frame
  EXPECT_EQ(state.everything().image_messages.size(), 1u);  // the last frame, for a page that joins
}

// A page's first state (/first.js) has a frame no poll has sent yet: everything() encodes each camera's
// latest frame when no page was sent it (a live viewer's first page, whose previews just started), and
// contents() says which cameras have one.
TEST(ViewerStateTest, TheFirstStateHasEachCamerasLatestFrameUnpolled) {
  ViewerState state(0.2);
  ViewerState::Contents contents = state.contents();
  EXPECT_FALSE(contents.scene || contents.status);
  EXPECT_TRUE(contents.cameras.empty());
  const auto dark = image("rgb8", 8, 4, 3, 20), bright = image("rgb8", 8, 4, 3, 200);
  state.add("/auv/camera/preview", "sensor_msgs/msg/Image", dark.data(), dark.size());
  state.add("/auv/camera/preview", "sensor_msgs/msg/Image", bright.data(), bright.size());
  add_odometry(state, 1.5, 2.0, -96.0);
  contents = state.contents();
  EXPECT_EQ(contents.cameras, std::set<std::string>{"/auv/camera/preview"});
  EXPECT_DOUBLE_EQ(contents.sim_time, 1.5);
  const PushOutput all = state.everything();
  ASSERT_EQ(all.image_messages.size(), 1u);
  const std::string name = "/auv/camera/preview";
  const std::size_t offset = 8 + name.size() + (4 - name.size() % 4) % 4;
  const std::string& jpeg = all.image_messages[0];
  const cv::Mat decoded =
      cv::imdecode(std::vector<unsigned char>(jpeg.begin() + offset, jpeg.end()), cv::IMREAD_COLOR);
  ASSERT_EQ(decoded.cols, 8);
  EXPECT_NEAR(decoded.at<cv::Vec3b>(2, 4)[1], 200, 3);  // the latest frame, not the first
  EXPECT_NE(all.update_json.find("\"width\":8,\"height\":4,\"encoding\":\"rgb8\""), std::string::npos)
      << all.update_json;
  // Encoded for the first state, the frame still goes to the pages already open at their next poll.
  EXPECT_EQ(state.poll(10.0).image_messages.size(), 1u);
}

// base64 as RFC 4648 section 10 has it, and the first state's script: the join's messages in order, binary
// ones in base64, the scene named for the join that follows.
TEST(ViewerStateTest, TheFirstStateScriptCarriesTheJoinsMessages) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\xff\x00\xfe", 3)), "/wD+");

  PushOutput all;
  all.history_json = "{\"type\":\"history\"}";
  all.image_messages = {"ab"};
  const std::string no_scene = first_state_script(all, "7.1", "{\"type\":\"update\"}");
  EXPECT_EQ(no_scene, "window.hadalFirst = {\"scene_id\":null,\"scene\":null,\"meshes\":[],"
                      "\"history\":{\"type\":\"history\"},\"images\":[\"YWI=\"],\"update\":{\"type\":\"update\"}};\n");
  all.scene_json = "{\"type\":\"scene\"}";
  all.mesh_messages = {"m1", "m2"};
  const std::string with_scene = first_state_script(all, "7.1", "{}");
  EXPECT_NE(with_scene.find("\"scene_id\":\"7.1\",\"scene\":{\"type\":\"scene\"},\"meshes\":[\"bTE=\",\"bTI=\"]"),
            std::string::npos)
      << with_scene;
}

// Images as any writer may send them: empty, absurdly large, rows longer than the data. None is sent, each
// is counted, nothing throws (the push loop would die with it).
TEST(ViewerStateTest, ImpossibleImagesAreCountedNotSent) {
  ViewerState state(0.0);
  sensor_msgs::msg::Image msg;
  msg.encoding("rgb8");
  const auto empty = cdr<sensor_msgs::msg::ImagePubSubType>(msg);
  msg.width(0x80000000u);
  msg.height(2);
  msg.step(0x80000000u * 3u);  // wraps in 32 bits
  msg.data(std::vector<std::uint8_t>(12, 1));
  const auto huge = cdr<sensor_msgs::msg::ImagePubSubType>(msg);
  msg.width(4);
  msg.step(12);
  msg.height(1000);  // 12 000 bytes of rows in 12 bytes of data
  const auto short_data = cdr<sensor_msgs::msg::ImagePubSubType>(msg);
  double now = 0.0;
  for (const auto* bytes : {&empty, &huge, &short_data}) {
    state.add("/auv/camera/preview", "sensor_msgs/msg/Image", bytes->data(), bytes->size());
    EXPECT_TRUE(state.poll(now += 1.0).image_messages.empty());
  }
  EXPECT_EQ(state.undecodable(), 3u);
}

// Names that are not UTF-8 (a vehicle name a client sent, echoed in the status) still make valid JSON text.
TEST(ViewerStateTest, JsonStringsAreEscapedAndValidUtf8) {
  EXPECT_EQ(json_string("a\"b\\c\n"), "\"a\\\"b\\\\c\\n\"");
  EXPECT_EQ(json_string("t\xc3\xa9l\xff"), "\"t\xc3\xa9l\xef\xbf\xbd\"");  // é kept, a stray byte replaced
  EXPECT_EQ(json_string("\xe2\x82"), "\"\xef\xbf\xbd\xef\xbf\xbd\"");           // a cut sequence
  EXPECT_EQ(json_string(std::string("\x01", 1)), "\"\\u0001\"");
  EXPECT_EQ(json_string("\xc0\x80"), "\"\xef\xbf\xbd\xef\xbf\xbd\"");  // an overlong NUL
  EXPECT_EQ(json_string("\xed\xa0\x80"), "\"\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd\"");  // a surrogate
  EXPECT_EQ(json_string("\xf0\x9f\x90\x99"), "\"\xf0\x9f\x90\x99\"");  // U+1F419 kept
}

TEST(ViewerStateTest, BytesThatDoNotDecodeAreCountedAndWhatIsShownIsKnown) {
  ViewerState state;
  const std::vector<unsigned char> garbage{0, 1, 0, 0, 7};
  state.add("/auv/odometry", "nav_msgs/msg/Odometry", garbage.data(), garbage.size());
  state.add("/auv/magnetometer", "sensor_msgs/msg/MagneticField", garbage.data(), garbage.size());
  EXPECT_EQ(state.samples(), 2u);
  EXPECT_EQ(state.undecodable(), 1u);  // the magnetometer is not drawn, so not decoded
  EXPECT_TRUE(ViewerState::shows("/auv/camera/preview", "sensor_msgs/msg/Image"));
  EXPECT_FALSE(ViewerState::shows("/auv/camera/image_raw", "sensor_msgs/msg/Image"));
  EXPECT_FALSE(ViewerState::shows("/auv/camera/depth", "sensor_msgs/msg/Image"));
  EXPECT_FALSE(ViewerState::shows("/auv/magnetometer", "sensor_msgs/msg/MagneticField"));
  EXPECT_TRUE(ViewerState::shows("/hadal/scene", "hadal_msgs/msg/Scene"));
  // Live, the drawn streams come in the monitor, not on their own topics.
  EXPECT_TRUE(ViewerState::shows("/hadal/monitor", "hadal_msgs/msg/Monitor"));
  EXPECT_FALSE(ViewerState::shows("/auv/odometry", "nav_msgs/msg/Odometry"));
  EXPECT_FALSE(ViewerState::shows("/hadal/status", "hadal_msgs/msg/SimStatus"));
}

// A monitor (rt/hadal/monitor) carries each topic's latest sample until the topic is written again: the
// viewer takes each sample once (by its count), so a repeated odometry adds no trail point and no series
// point, and a count that went down (a server started again) is a new sample. A monitor that does not
// decode is counted.
TEST(ViewerStateTest, AMonitorsSamplesAreTakenOnceEach) {
  ViewerState state;
  hadal_msgs::msg::Monitor monitor;
  const auto carry = [&](double t, double x, std::uint64_t count) {
    nav_msgs::msg::Odometry odom;
    odom.header().stamp().sec(static_cast<std::int32_t>(std::floor(t)));
    odom.header().stamp().nanosec(static_cast<std::uint32_t>(std::llround((t - std::floor(t)) * 1e9)));
    odom.pose().pose().position().x(x);
    odom.pose().pose().position().z(-96.0);
    odom.pose().pose().orientation().w(1.0);
    hadal_msgs::msg::MonitorSample sample;
    sample.topic("/auv/odometry");
    sample.type("nav_msgs/msg/Odometry");
    sample.count(count);
    sample.cdr(cdr<nav_msgs::msg::OdometryPubSubType>(odom));
    monitor.samples().clear();
    monitor.samples().push_back(sample);
    const auto bytes = cdr<hadal_msgs::msg::MonitorPubSubType>(monitor);
    state.add("/hadal/monitor", "hadal_msgs/msg/Monitor", bytes.data(), bytes.size());
  };
  carry(0.0, 0.0, 1);
  carry(0.0, 0.0, 1);  // the same sample again: nothing new
  carry(0.5, 1.0, 26);
  PushOutput out = state.poll(0.0);
  EXPECT_EQ(state.samples(), 5u);  // three monitors and the two odometry samples they brought
  EXPECT_NE(out.update_json.find("\"auv\":{\"stamp\":0.5,\"p\":[1,0,-96]"), std::string::npos) << out.update_json;
  const std::string depth = out.history_json.substr(out.history_json.find("\"auv/depth\""));
  EXPECT_EQ(array_after(depth, "t"), "[0,0.5]");
  carry(0.5, 1.0, 26);
  EXPECT_EQ(state.samples(), 6u);
  carry(0.02, 2.0, 2);  // a server started again: its counts start again
  EXPECT_EQ(state.samples(), 8u);
  out = state.poll(0.0);
  EXPECT_NE(out.update_json.find("\"p\":[2,0,-96]"), std::string::npos) << out.update_json;
  const std::vector<unsigned char> garbage{0, 1, 0, 0, 7};
  state.add("/hadal/monitor", "hadal_msgs/msg/Monitor", garbage.data(), garbage.size());
  EXPECT_EQ(state.undecodable(), 1u);
}

// The acoustic signals in flight reach the page as they came: per link its kind, where it left and where its
// receiver is, when it left, its duration and sound speed, its ends' names; none: null.
TEST(ViewerStateTest, AcousticLinksReachThePage) {
  ViewerState state;
  EXPECT_NE(state.poll(0.0).update_json.find("\"acoustic\":null"), std::string::npos);
  hadal_msgs::msg::AcousticLinks msg;
  msg.header().stamp().sec(12);
  msg.header().stamp().nanosec(500000000);
  hadal_msgs::msg::AcousticLink& link = msg.links().emplace_back();
  link.kind(2);
  link.source("auv");
  link.target("vessel/usbl");
  link.emit_position().x(600.0);
  link.emit_position().y(300.0);
  link.emit_position().z(-1500.0);
  link.target_position().z(-0.5);
  link.emit_stamp().sec(11);
  link.duration(0.0);
  link.sound_speed(1490.5);
  const auto bytes = cdr<hadal_msgs::msg::AcousticLinksPubSubType>(msg);
  state.add("/hadal/acoustic_links", "hadal_msgs/msg/AcousticLinks", bytes.data(), bytes.size());
  const std::string json = state.poll(0.0).update_json;
  EXPECT_NE(json.find("\"acoustic\":{\"time\":12.5,\"links\":[[2,[600,300,-1500,0,0,-0.5,11,0,1490.5],\"auv\","
                      "\"vessel/usbl\"]]}"),
            std::string::npos)
      << json;
  EXPECT_EQ(state.undecodable(), 0u);
}

// A cable's shape reaches the page as its nodes' coordinates, by topic.
TEST(ViewerStateTest, ACablesShapeReachesThePage) {
  ViewerState state;
  nav_msgs::msg::Path msg;
  for (int i = 0; i < 3; ++i) {
    geometry_msgs::msg::PoseStamped& pose = msg.poses().emplace_back();
    pose.pose().position().x(i);
    pose.pose().position().z(-5.0 - 10.0 * i);
  }
  const auto bytes = cdr<nav_msgs::msg::PathPubSubType>(msg);
  state.add("/hadal/cables/lift_line/shape", "nav_msgs/msg/Path", bytes.data(), bytes.size());
  const std::string json = state.poll(0.0).update_json;
  EXPECT_NE(json.find("\"paths\":{\"/hadal/cables/lift_line/shape\":[0,0,-5,1,0,-15,2,0,-25]}"), std::string::npos)
      << json;
}

}  // namespace
}  // namespace hadal::viewer
