#include "viewer_state.h"

#include "json_number.h"

#include <fastdds/rtps/common/SerializedPayload.h>
#include <hadal_msgsPubSubTypes.h>
#include <marine_acoustic_msgsPubSubTypes.h>
#include <nav_msgsPubSubTypes.h>
#include <rosgraph_msgsPubSubTypes.h>
#include <sensor_msgsPubSubTypes.h>

// libjpeg-turbo, not OpenCV: OpenCV's core needs libblas.so.3, which on a machine whose BLAS is OpenBLAS
// brings 60 KiB of static TLS into every thread's stack, and civetweb's worker threads have 100 KiB
// (docs/viewer.md, "How it is tested").
#include <jpeglib.h>

#include <Eigen/Geometry>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <set>

namespace hadal::viewer {
namespace {

using tools::json_number;

// libjpeg reports errors through error_exit, which must not return (its default exits the process): it
// jumps back to encode_jpeg's setjmp.
struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
};
extern "C" void jpeg_error_jump(j_common_ptr info) {
  std::longjmp(reinterpret_cast<JpegError*>(info->err)->jump, 1);
}
extern "C" void jpeg_no_message(j_common_ptr) {}

// height rows of width pixels, `step` bytes apart, as JPEG at `quality` (0..100) into *out; in_color:
// JCS_RGB, JCS_EXT_BGR (libjpeg-turbo) or JCS_GRAYSCALE. False when libjpeg reports an error.
bool encode_jpeg(const unsigned char* data, int width, int height, std::size_t step, int channels,
                 J_COLOR_SPACE in_color, int quality, std::string* out) {
  jpeg_compress_struct info;
  JpegError error;
  unsigned char* buffer = nullptr;  // libjpeg's (malloc), through jpeg_mem_dest
  unsigned long size = 0;
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = jpeg_error_jump;
  error.manager.output_message = jpeg_no_message;
  if (setjmp(error.jump)) {
    jpeg_destroy_compress(&info);
    std::free(buffer);
    return false;
  }
  jpeg_create_compress(&info);
  jpeg_mem_dest(&info, &buffer, &size);
  info.image_width = static_cast<JDIMENSION>(width);
  info.image_height = static_cast<JDIMENSION>(height);
  info.input_components = channels;
  info.in_color_space = in_color;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, quality, TRUE);
  jpeg_start_compress(&info, TRUE);
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(data + static_cast<std::size_t>(info.next_scanline) * step);
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  out->assign(reinterpret_cast<const char*>(buffer), size);
  std::free(buffer);
  return true;
}

constexpr double kSeriesInterval = 0.1;         // sim seconds between two points of a series
constexpr std::size_t kSeriesPoints = 3000;     // per series (5 min at 10 Hz)
constexpr std::size_t kTrailPoints = 20000;     // per vehicle
constexpr double kTrailStep = 0.05;             // [m] between trail points
constexpr double kPi = 3.14159265358979323846;
constexpr std::uint64_t kMaxImageSide = 16384;  // [px]

// Decodes CDR bytes as PubSubType's message; false when they do not decode.
template <class PubSubType, class Message>
bool decode(const unsigned char* data, std::size_t size, Message* msg) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload;
  payload.data = const_cast<unsigned char*>(data);
  payload.length = static_cast<std::uint32_t>(size);
  payload.max_size = static_cast<std::uint32_t>(size);
  bool ok = false;
  try {
    PubSubType type;
    ok = type.deserialize(&payload, msg);
  } catch (const std::exception&) {
    ok = false;
  }
  payload.data = nullptr;  // borrowed
  return ok;
}

double stamp_of(const std_msgs::msg::Header& header) {
  return header.stamp().sec() + 1e-9 * header.stamp().nanosec();
}

// The length of the well-formed UTF-8 sequence at text[i] (Unicode's table of well-formed byte sequences:
// no overlong forms, no surrogates, nothing past U+10FFFF), or 0 where the bytes are not one.
std::size_t utf8_length(const std::string& text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return k < text.size() ? static_cast<unsigned char>(text[k]) : 0; };
  const unsigned char lead = byte(i);
  if (lead < 0x80) return 1;
  std::size_t n = 0;
  unsigned char low = 0x80, high = 0xbf;  // the range of the second byte
  if (lead >= 0xc2 && lead <= 0xdf) {
    n = 2;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    n = 3;
    if (lead == 0xe0) low = 0xa0;
    if (lead == 0xed) high = 0x9f;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    n = 4;
    if (lead == 0xf0) low = 0x90;
    if (lead == 0xf4) high = 0x8f;
  } else {
    return 0;
  }
  if (byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if ((byte(i + k) & 0xc0) != 0x80) return 0;
  }
  return n;
}

// A JSON string: escaped, and valid UTF-8 (a browser closes a WebSocket on a text frame that is not), with
// U+FFFD for each byte that does not start a well-formed sequence (a vehicle name a client sent, a path).
void append_string(std::string& out, const std::string& text) {
  out += '"';
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (static_cast<unsigned char>(c) >= 0x80) {
      const std::size_t n = utf8_length(text, i);
      if (n == 0) {
        out += "\ufffd";
      } else {
        out.append(text, i, n);
        i += n - 1;
      }
      continue;
    }
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  out += '"';
}

void append_numbers(std::string& out, const double* values, std::size_t n) {
  out += '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i) out += ',';
    out += json_number(values[i]);
  }
  out += ']';
}

// ,"<prefix>p":[x,y,z],"<prefix>q":[x,y,z,w] of a pose.
void append_pose(std::string& out, const geometry_msgs::msg::Pose& pose, const std::string& prefix = "") {
  const double p[3] = {pose.position().x(), pose.position().y(), pose.position().z()};
  const double q[4] = {pose.orientation().x(), pose.orientation().y(), pose.orientation().z(), pose.orientation().w()};
  out += ",\"" + prefix + "p\":";
  append_numbers(out, p, 3);
  out += ",\"" + prefix + "q\":";
  append_numbers(out, q, 4);
}

// "/auv/dvl" -> ("auv", "dvl"); "/auv/camera/image_raw" -> ("auv", "camera/image_raw").
std::pair<std::string, std::string> split_topic(const std::string& topic) {
  const std::size_t slash = topic.find('/', 1);
  if (topic.empty() || topic[0] != '/' || slash == std::string::npos) return {"", ""};
  return {topic.substr(1, slash - 1), topic.substr(slash + 1)};
}

// An overlay's opening fields: `{"kind":K,"vehicle":V,"sensor":S` (the object left open).
std::string overlay_head(const char* kind, const std::string& vehicle, const std::string& sensor) {
  std::string json = std::string("{\"kind\":\"") + kind + "\",\"vehicle\":";
  append_string(json, vehicle);
  json += ",\"sensor\":";
  append_string(json, sensor);
  return json;
}

void append_u32(std::string& out, std::uint32_t value) { out.append(reinterpret_cast<const char*>(&value), 4); }

}  // namespace

std::string json_string(const std::string& text) {
  std::string out;
  append_string(out, text);
  return out;
}

std::string binary_message(const char (&tag)[5], const std::string& name, const std::string& payload) {
  std::string out(tag, 4);
  append_u32(out, static_cast<std::uint32_t>(name.size()));
  out += name;
  out.append((4 - out.size() % 4) % 4, '\0');
  out += payload;
  return out;
}

std::string base64(const std::string& bytes) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t group = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      group = (group << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    }
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(group >> (18 - 6 * k)) & 0x3f] : '=';
  }
  return out;
}

std::string first_state_script(const PushOutput& all, const std::string& scene_id, const std::string& update_json) {
  const bool scene = !all.scene_json.empty();
  auto blobs = [](const std::vector<std::string>& messages) {
    std::string json = "[";
    for (const std::string& message : messages) json += (json.size() > 1 ? ",\"" : "\"") + base64(message) + '"';
    return json + ']';
  };
  return "window.hadalFirst = {\"scene_id\":" + (scene ? json_string(scene_id) : std::string("null")) +
         ",\"scene\":" + (scene ? all.scene_json : std::string("null")) +
         ",\"meshes\":" + blobs(scene ? all.mesh_messages : std::vector<std::string>{}) +
         ",\"history\":" + all.history_json + ",\"images\":" + blobs(all.image_messages) +
         ",\"update\":" + update_json + "};\n";
}

bool ViewerState::shows(const std::string& topic, const std::string& type) {
  const std::string image_suffix = "/preview";
  return type == "hadal_msgs/msg/Scene" || type == "hadal_msgs/msg/Monitor" ||
         (type == "sensor_msgs/msg/Image" && topic.size() > image_suffix.size() &&
          topic.compare(topic.size() - image_suffix.size(), image_suffix.size(), image_suffix) == 0);
}

void ViewerState::add(const std::string& topic, const std::string& type, const unsigned char* data, std::size_t size) {
  if (type == "hadal_msgs/msg/Monitor") {
    add_monitor(topic, data, size);
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  ++samples_;
  ++counts_[topic];
  const auto [vehicle, sensor] = split_topic(topic);
  bool ok = true;
  if (type == "hadal_msgs/msg/Scene") {
    // The server writes the same scene again after a reset (the reset itself shows as time going back),
    // and a bag player may feed it ahead of its time: only a different scene starts over.
    if (scene_bytes_.size() == size && std::equal(data, data + size, scene_bytes_.begin())) return;
    hadal_msgs::msg::Scene msg;
    if ((ok = decode<hadal_msgs::msg::ScenePubSubType>(data, size, &msg))) {
      scene_bytes_.assign(data, data + size);
      water_surface_z_ = msg.water_surface_z();
      std::string json = "{\"type\":\"scene\",\"scenario\":";
      append_string(json, msg.scenario());
      json += ",\"frame_id\":";
      append_string(json, msg.header().frame_id());
      json += ",\"water_surface_z\":" + json_number(msg.water_surface_z());
      json += ",\"vehicles\":[";
      for (std::size_t i = 0; i < msg.vehicle_names().size(); ++i) {
        if (i) json += ',';
        json += "{\"name\":";
        append_string(json, msg.vehicle_names()[i]);
        json += ",\"type\":";
        append_string(json, i < msg.vehicle_types().size() ? msg.vehicle_types()[i] : "");
        json += '}';
      }
      json += "],\"meshes\":[";
      mesh_messages_.clear();
      for (std::size_t i = 0; i < msg.meshes().size(); ++i) {
        const auto& mesh = msg.meshes()[i];
        if (i) json += ',';
        json += "{\"name\":";
        append_string(json, mesh.name());
        json += ",\"frame_id\":";
        append_string(json, mesh.frame_id());
        const double color[3] = {mesh.color().r(), mesh.color().g(), mesh.color().b()};
        json += ",\"color\":";
        append_numbers(json, color, 3);
        json += ",\"triangles\":" + std::to_string(mesh.indices().size() / 3) + '}';
        std::string payload;
        append_u32(payload, static_cast<std::uint32_t>(mesh.positions().size()));
        append_u32(payload, static_cast<std::uint32_t>(mesh.indices().size()));
        payload.append(reinterpret_cast<const char*>(mesh.positions().data()), 4 * mesh.positions().size());
        payload.append(reinterpret_cast<const char*>(mesh.indices().data()), 4 * mesh.indices().size());
        mesh_messages_.push_back(binary_message("MESH", std::to_string(i), payload));
      }
      json += "],\"frames\":[";
      for (std::size_t i = 0; i < msg.frames().size(); ++i) {
        const auto& frame = msg.frames()[i];
        if (i) json += ',';
        json += "{\"vehicle\":";
        append_string(json, frame.vehicle());
        json += ",\"name\":";
        append_string(json, frame.name());
        json += ",\"kind\":";
        append_string(json, frame.kind());
        append_pose(json, frame.pose());
        json += ",\"range\":" + json_number(frame.range()) + ",\"half_angle\":" + json_number(frame.half_angle());
        if (!frame.link().empty()) {  // on a moving body: its pose in the body, "link_p" and "link_q"
          json += ",\"link\":";
          append_string(json, frame.link());
          append_pose(json, frame.link_pose(), "link_");
        }
        json += '}';
      }
      json += "],\"links\":[";
      for (std::size_t i = 0; i < msg.links().size(); ++i) {
        const auto& link = msg.links()[i];
        if (i) json += ',';
        json += "{\"vehicle\":";
        append_string(json, link.vehicle());
        json += ",\"name\":";
        append_string(json, link.name());
        json += ",\"parent\":";
        append_string(json, link.parent());
        json += ",\"joint\":";
        append_string(json, link.joint());
        json += ",\"joint_type\":";
        append_string(json, link.joint_type());
        append_pose(json, link.pose());
        const double axis[3] = {link.axis().x(), link.axis().y(), link.axis().z()};
        json += ",\"axis\":";
        append_numbers(json, axis, 3);
        json += '}';
      }
      json += ']';
      if (!msg.wave_components().empty()) {  // the sea state: the page draws the moving surface from it
        json += ",\"waves\":{\"ramp_time\":" + json_number(msg.wave_ramp_time_s()) + ",\"components\":[";
        for (std::size_t i = 0; i < msg.wave_components().size(); ++i) {
          const auto& c = msg.wave_components()[i];
          const double values[5] = {c.amplitude_m(), c.omega_rad_per_s(), c.wave_number_rad_per_m(), c.direction_rad(),
                                    c.phase_rad()};
          if (i) json += ',';
          append_numbers(json, values, 5);
        }
        json += "]}";
      }
      json += '}';
      scene_json_ = std::move(json);
      ++scene_generation_;
      start_over();  // the server writes the scene at start and after a reset
    }
  } else if (type == "nav_msgs/msg/Odometry") {
    nav_msgs::msg::Odometry msg;
    if ((ok = decode<nav_msgs::msg::OdometryPubSubType>(data, size, &msg))) {
      const double t = stamp_of(msg.header());
      note_time(topic, t);
      Vehicle& v = vehicles_[vehicle];
      const auto& pose = msg.pose().pose();
      const auto& twist = msg.twist().twist();
      v.has_pose = true;
      v.stamp = t;
      v.p[0] = pose.position().x(), v.p[1] = pose.position().y(), v.p[2] = pose.position().z();
      v.q[0] = pose.orientation().x(), v.q[1] = pose.orientation().y(), v.q[2] = pose.orientation().z(),
      v.q[3] = pose.orientation().w();
      v.v[0] = twist.linear().x(), v.v[1] = twist.linear().y(), v.v[2] = twist.linear().z();
      v.w[0] = twist.angular().x(), v.w[1] = twist.angular().y(), v.w[2] = twist.angular().z();
      const std::size_t n = v.trail.size();
      if (n == 0 ||
          std::hypot(v.p[0] - v.trail[n - 3], v.p[1] - v.trail[n - 2], v.p[2] - v.trail[n - 1]) >= kTrailStep) {
        if (n / 3 >= kTrailPoints) v.trail.erase(v.trail.begin(), v.trail.begin() + 3 * (kTrailPoints / 10));
        for (const double x : v.p) v.trail.push_back(static_cast<float>(x));
        ++v.trail_total;
      }
      // Roll, pitch, yaw of B in W (z-y-x Euler angles, as REP-103's rpy).
      const Eigen::Quaterniond q(v.q[3], v.q[0], v.q[1], v.q[2]);
      const Eigen::Matrix3d R = q.normalized().toRotationMatrix();
      const double roll = std::atan2(R(2, 1), R(2, 2)), pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0)),
                   yaw = std::atan2(R(1, 0), R(0, 0));
      add_point(vehicle + "/depth", vehicle + " depth", "depth", "m", t, water_surface_z_ - v.p[2]);
      add_point(vehicle + "/speed", vehicle + " speed", "speed", "m/s", t, std::hypot(v.v[0], v.v[1], v.v[2]));
      add_point(vehicle + "/roll", vehicle + " attitude", "roll", "deg", t, roll * 180.0 / kPi);
      add_point(vehicle + "/pitch", vehicle + " attitude", "pitch", "deg", t, pitch * 180.0 / kPi);
      add_point(vehicle + "/yaw", vehicle + " attitude", "yaw", "deg", t, yaw * 180.0 / kPi);
    }
  } else if (type == "hadal_msgs/msg/SimStatus") {
    hadal_msgs::msg::SimStatus msg;
    if ((ok = decode<hadal_msgs::msg::SimStatusPubSubType>(data, size, &msg))) {
      static const char* const kModes[] = {"realtime", "fast", "lockstep"};
      std::string json = "{\"sim_time\":" + json_number(msg.sim_time()) +
                         ",\"rtf\":" + json_number(msg.real_time_factor()) +
                         ",\"steps\":" + std::to_string(msg.step_count()) + ",\"mode\":";
      append_string(json, msg.mode() < 3 ? kModes[msg.mode()] : "unknown");
      json += ",\"faults\":{";
      for (std::size_t i = 0; i < msg.vehicle_names().size() && i < msg.vehicle_faults().size(); ++i) {
        if (i) json += ',';
        append_string(json, msg.vehicle_names()[i]);
        json += ':' + std::to_string(msg.vehicle_faults()[i]);
      }
      json += "},\"rejected_commands\":" + std::to_string(msg.rejected_commands()) + ",\"last_error\":";
      append_string(json, msg.last_error());
      json += ",\"dropped_captures\":" + std::to_string(msg.dropped_captures()) + '}';
      status_json_ = std::move(json);
    }
  } else if (type == "nav_msgs/msg/Path") {
    // A cable's shape (rt/hadal/cables/<name>/shape): its nodes in W, drawn as a line.
    nav_msgs::msg::Path msg;
    if ((ok = decode<nav_msgs::msg::PathPubSubType>(data, size, &msg))) {
      std::vector<double> points;
      for (const geometry_msgs::msg::PoseStamped& pose : msg.poses()) {
        points.insert(points.end(), {pose.pose().position().x(), pose.pose().position().y(), pose.pose().position().z()});
      }
      std::string json;
      append_numbers(json, points.data(), points.size());
      paths_[topic] = std::move(json);
    }
  } else if (type == "hadal_msgs/msg/AcousticLinks") {
    // Every acoustic signal in flight: [kind, emit xyz, target xyz, emit time, duration, sound speed, source,
    // target], drawn by the page as its wavefront's progress along the straight path.
    hadal_msgs::msg::AcousticLinks msg;
    if ((ok = decode<hadal_msgs::msg::AcousticLinksPubSubType>(data, size, &msg))) {
      const double t = stamp_of(msg.header());
      std::string json = "{\"time\":" + json_number(t) + ",\"links\":[";
      for (std::size_t i = 0; i < msg.links().size(); ++i) {
        const hadal_msgs::msg::AcousticLink& link = msg.links()[i];
        const double numbers[9] = {link.emit_position().x(),   link.emit_position().y(),   link.emit_position().z(),
                                   link.target_position().x(), link.target_position().y(), link.target_position().z(),
                                   link.emit_stamp().sec() + 1e-9 * link.emit_stamp().nanosec(),
                                   link.duration(),            link.sound_speed()};
        json += (i ? ",[" : "[") + std::to_string(link.kind()) + ',';
        append_numbers(json, numbers, 9);
        json += ',';
        append_string(json, link.source());
        json += ',';
        append_string(json, link.target());
        json += ']';
      }
      acoustic_json_ = json + "]}";
    }
  } else if (type == "rosgraph_msgs/msg/Clock") {
    rosgraph_msgs::msg::Clock msg;
    if ((ok = decode<rosgraph_msgs::msg::ClockPubSubType>(data, size, &msg))) {
      note_time(topic, msg.clock().sec() + 1e-9 * msg.clock().nanosec());
    }
  } else if (type == "marine_acoustic_msgs/msg/Dvl") {
    marine_acoustic_msgs::msg::Dvl msg;
    if ((ok = decode<marine_acoustic_msgs::msg::DvlPubSubType>(data, size, &msg))) {
      const double t = stamp_of(msg.header());
      std::string json = overlay_head("dvl", vehicle, sensor) + ",\"beams\":[";
      for (int i = 0; i < 4; ++i) {
        const auto& u = msg.beam_unit_vec()[i];
        const double beam[4] = {u.x(), u.y(), u.z(), msg.range()[i]};
        if (i) json += ',';
        append_numbers(json, beam, 4);
      }
      json += "],\"altitude\":" + json_number(msg.altitude()) + '}';
      overlays_[topic] = std::move(json);
      add_point(topic + "/altitude", vehicle + " altitude", sensor + " altitude", "m", t, msg.altitude());
      add_point(topic + "/vx", vehicle + " " + sensor + " velocity", "vx", "m/s", t, msg.velocity().x());
      add_point(topic + "/vy", vehicle + " " + sensor + " velocity", "vy", "m/s", t, msg.velocity().y());
    }
  } else if (type == "sensor_msgs/msg/JointState") {
    // An articulated vehicle's joints (rt/<vehicle>/joint_states): the page poses its moving bodies from them
    // (the scene's links).
    sensor_msgs::msg::JointState msg;
    if ((ok = decode<sensor_msgs::msg::JointStatePubSubType>(data, size, &msg))) {
      note_time(topic, stamp_of(msg.header()));
      Vehicle& v = vehicles_[vehicle];
      for (std::size_t j = 0; j < msg.name().size() && j < msg.position().size(); ++j) {
        v.joints[msg.name()[j]] = msg.position()[j];
      }
    }
  } else if (type == "sensor_msgs/msg/Range") {
    sensor_msgs::msg::Range msg;
    if ((ok = decode<sensor_msgs::msg::RangePubSubType>(data, size, &msg))) {
      std::string json = overlay_head("range", vehicle, sensor) + ",\"range\":" + json_number(msg.range()) +
                         ",\"max_range\":" + json_number(msg.max_range()) + '}';
      overlays_[topic] = std::move(json);
      add_point(topic, vehicle + " altitude", sensor, "m", stamp_of(msg.header()), msg.range());
    }
  } else if (type == "sensor_msgs/msg/FluidPressure") {
    sensor_msgs::msg::FluidPressure msg;
    if ((ok = decode<sensor_msgs::msg::FluidPressurePubSubType>(data, size, &msg))) {
      add_point(topic, vehicle + " pressure", sensor, "kPa", stamp_of(msg.header()), 1e-3 * msg.fluid_pressure());
    }
  } else if (type == "sensor_msgs/msg/Imu") {
    sensor_msgs::msg::Imu msg;
    if ((ok = decode<sensor_msgs::msg::ImuPubSubType>(data, size, &msg))) {
      const double t = stamp_of(msg.header());
      const auto& w = msg.angular_velocity();
      add_point(topic + "/wx", vehicle + " " + sensor + " rate", "wx", "deg/s", t, w.x() * 180.0 / kPi);
      add_point(topic + "/wy", vehicle + " " + sensor + " rate", "wy", "deg/s", t, w.y() * 180.0 / kPi);
      add_point(topic + "/wz", vehicle + " " + sensor + " rate", "wz", "deg/s", t, w.z() * 180.0 / kPi);
    }
  } else if (type == "sensor_msgs/msg/Image") {
    // Decoded when due (poll): most frames are never sent.
    Camera& camera = cameras_[topic];
    camera.bytes.assign(data, data + size);
    ++camera.frames;
  }
  if (!ok) ++undecodable_;
}

void ViewerState::add_point(const std::string& key, const std::string& plot, const std::string& label,
                            const std::string& unit, double t, double value) {
  auto [it, added] = series_.try_emplace(key);
  Series& series = it->second;
  if (added) series.plot = plot, series.label = label, series.unit = unit;
  if (!series.points.empty() && t < series.points.back().first + kSeriesInterval - 1e-9) return;
  if (series.points.size() >= kSeriesPoints) {
    series.points.pop_front();
    series.seq.pop_front();
  }
  series.points.emplace_back(t, value);
  series.seq.push_back(next_seq_++);
}

void ViewerState::note_time(const std::string& topic, double t) {
  // A lockstep reset starts over at 0 (the scene comes again too; this catches a bag of several runs): a topic's
  // stamp half a second before its own last. Each topic against itself: one writer's samples come in order, but
  // topics keep no order among themselves (a recorder under load can take a run's odometry after a /clock that
  // has passed it, and a bag replays them so).
  const auto last = topic_times_.find(topic);
  if (last != topic_times_.end() && t + 1e-6 < last->second - 0.5) start_over();  // sim_time_ 0, no topic times
  topic_times_[topic] = t;
  sim_time_ = std::max(sim_time_, t);
}

void ViewerState::start_over() {
  for (auto& [name, vehicle] : vehicles_) vehicle.trail.clear(), vehicle.trail_total = vehicle.polled_trail = 0;
  series_.clear();
  overlays_.clear();
  acoustic_json_.clear();
  paths_.clear();
  topic_times_.clear();
  sim_time_ = 0.0;
  ++history_generation_;
}

// Each sample the monitor carries, once: a topic's sample repeats in the next monitor (same count) until the
// topic is written again. A count that differs, lower included (a server started again), is a new sample.
void ViewerState::add_monitor(const std::string& topic, const unsigned char* data, std::size_t size) {
  hadal_msgs::msg::Monitor msg;
  const bool ok = decode<hadal_msgs::msg::MonitorPubSubType>(data, size, &msg);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++samples_;
    ++counts_[topic];
    if (!ok) {
      ++undecodable_;
      return;
    }
  }
  for (const auto& sample : msg.samples()) {
    if (sample.type() == "hadal_msgs/msg/Monitor") continue;  // a monitor carries no monitors
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto [seen, fresh] = monitor_counts_.emplace(sample.topic(), sample.count());
      if (!fresh && seen->second == sample.count()) continue;
      seen->second = sample.count();
    }
    add(sample.topic(), sample.type(), sample.cdr().data(), sample.cdr().size());
  }
}

void ViewerState::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  monitor_counts_.clear();
  vehicles_.clear();
  cameras_.clear();
  status_json_.clear();
  acoustic_json_.clear();
  start_over();
}

std::string ViewerState::history_json_locked() const {
  std::string json = "{\"type\":\"history\",\"seq\":" + std::to_string(next_seq_ - 1) + ",\"trails\":{";
  bool first = true;
  for (const auto& [name, vehicle] : vehicles_) {
    if (!first) json += ',';
    first = false;
    append_string(json, name);
    json += ":{\"total\":" + std::to_string(vehicle.trail_total) + ",\"points\":";
    append_trail(json, vehicle, 0);
    json += '}';
  }
  json += "},\"series\":{";
  first = true;
  for (const auto& [key, series] : series_) {
    if (!first) json += ',';
    first = false;
    append_string(json, key);
    append_series_info(json, series);
    for (const char* field : {",\"t\":[", "],\"v\":["}) {
      json += field;
      const bool times = field[2] == 't';
      for (std::size_t i = 0; i < series.points.size(); ++i) {
        json += (i ? "," : "") + json_number(times ? series.points[i].first : series.points[i].second);
      }
    }
    json += "]}";
  }
  json += "}}";
  return json;
}

// `:{"plot":...,"label":...,"unit":...` (the object left open).
void ViewerState::append_series_info(std::string& json, const Series& series) {
  json += ":{\"plot\":";
  append_string(json, series.plot);
  json += ",\"label\":";
  append_string(json, series.label);
  json += ",\"unit\":";
  append_string(json, series.unit);
}

void ViewerState::append_trail(std::string& json, const Vehicle& vehicle, std::uint64_t from) {
  const std::uint64_t first = vehicle.trail_total - vehicle.trail.size() / 3;
  json += '[';
  for (std::size_t i = 3 * (std::max(from, first) - first); i < vehicle.trail.size(); ++i) {
    if (json.back() != '[') json += ',';
    json += json_number(vehicle.trail[i]);
  }
  json += ']';
}

std::string ViewerState::update_json_locked(std::uint64_t since_seq, bool trail_points) const {
  std::string json = "{\"type\":\"update\",\"sim_time\":" + json_number(sim_time_) +
                     ",\"samples\":" + std::to_string(samples_) + ",\"undecodable\":" + std::to_string(undecodable_);
  json += ",\"status\":" + (status_json_.empty() ? std::string("null") : status_json_);
  json += ",\"acoustic\":" + (acoustic_json_.empty() ? std::string("null") : acoustic_json_);
  json += ",\"paths\":{";
  for (auto path = paths_.begin(); path != paths_.end(); ++path) {
    if (path != paths_.begin()) json += ',';
    append_string(json, path->first);
    json += ':' + path->second;
  }
  json += '}';
  json += ",\"vehicles\":{";
  bool first = true;
  for (const auto& [name, v] : vehicles_) {
    if (!v.has_pose) continue;
    if (!first) json += ',';
    first = false;
    append_string(json, name);
    json += ":{\"stamp\":" + json_number(v.stamp) + ",\"p\":";
    append_numbers(json, v.p, 3);
    json += ",\"q\":";
    append_numbers(json, v.q, 4);
    json += ",\"v\":";
    append_numbers(json, v.v, 3);
    json += ",\"w\":";
    append_numbers(json, v.w, 3);
    // The trail's points added since the pages were last sent some: [index of the first, x, y, z, ...].
    const std::uint64_t from = trail_points ? v.polled_trail : v.trail_total;
    json += ",\"trail_from\":" + std::to_string(from) + ",\"trail\":";
    append_trail(json, v, from);
    if (!v.joints.empty()) {
      json += ",\"joints\":{";
      bool first_joint = true;
      for (const auto& [joint, position] : v.joints) {
        if (!first_joint) json += ',';
        first_joint = false;
        append_string(json, joint);
        json += ':' + json_number(position);
      }
      json += '}';
    }
    json += '}';
  }
  json += "},\"overlays\":[";
  first = true;
  for (const auto& [topic, overlay] : overlays_) {
    json += (first ? "" : ",") + overlay;
    first = false;
  }
  json += "],\"cameras\":{";
  first = true;
  for (const auto& [topic, camera] : cameras_) {
    if (!first) json += ',';
    first = false;
    append_string(json, topic);
    json += ":{\"frames\":" + std::to_string(camera.frames) + ",\"stamp\":" + json_number(camera.stamp) +
            ",\"width\":" + std::to_string(camera.width) + ",\"height\":" + std::to_string(camera.height) +
            ",\"encoding\":";
    append_string(json, camera.encoding);
    json += '}';
  }
  // New points as [key, seq, t, value], with what a page needs to plot a series it has not seen yet.
  json += "},\"series\":{";
  first = true;
  for (const auto& [key, series] : series_) {
    if (series.seq.empty() || series.seq.back() <= since_seq) continue;
    if (!first) json += ',';
    first = false;
    append_string(json, key);
    append_series_info(json, series);
    json += '}';
  }
  json += "},\"points\":[";
  first = true;
  for (const auto& [key, series] : series_) {
    const auto newer = std::upper_bound(series.seq.begin(), series.seq.end(), since_seq);
    for (auto i = static_cast<std::size_t>(newer - series.seq.begin()); i < series.seq.size(); ++i) {
      if (!first) json += ',';
      first = false;
      json += '[';
      append_string(json, key);
      json += ',' + std::to_string(series.seq[i]) + ',' + json_number(series.points[i].first) + ',' +
              json_number(series.points[i].second) + ']';
    }
  }
  json += "]}";
  return json;
}

// The camera's latest frame as a JPEG message, decoded and encoded now; "" when it is no 8-bit image.
std::string ViewerState::image_message_locked(const std::string& topic, Camera& camera) {
  sensor_msgs::msg::Image msg;
  if (!decode<sensor_msgs::msg::ImagePubSubType>(camera.bytes.data(), camera.bytes.size(), &msg)) {
    ++undecodable_;
    return "";
  }
  camera.stamp = stamp_of(msg.header());
  camera.encoding = msg.encoding();
  int channels = 0;
  if (msg.encoding() == "rgb8" || msg.encoding() == "bgr8") channels = 3;
  if (msg.encoding() == "mono8") channels = 1;
  // Sizes as any writer may send them: 1..16384 px, rows that hold their pixels, data that holds its rows
  // (in 64 bits, so nothing wraps).
  const std::uint64_t width = msg.width(), height = msg.height(), step = msg.step();
  const bool sane = width >= 1 && width <= kMaxImageSide && height >= 1 && height <= kMaxImageSide &&
                    step >= width * static_cast<std::uint64_t>(channels) && msg.data().size() >= step * height;
  camera.width = sane ? static_cast<int>(width) : 0;
  camera.height = sane ? static_cast<int>(height) : 0;
  if (channels == 0) return "";  // depth images (32FC1) and anything else are listed, not shown
  if (!sane) {
    ++undecodable_;
    return "";
  }
  const J_COLOR_SPACE in_color = channels == 1 ? JCS_GRAYSCALE : msg.encoding() == "rgb8" ? JCS_RGB : JCS_EXT_BGR;
  std::string jpeg;
  if (!encode_jpeg(msg.data().data(), camera.width, camera.height, step, channels, in_color, 85, &jpeg)) {
    ++undecodable_;
    return "";
  }
  camera.last_jpeg = std::move(jpeg);
  camera.jpeg_frame = camera.frames;
  return binary_message("JPEG", topic, camera.last_jpeg);
}

PushOutput ViewerState::poll(double now_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  PushOutput out;
  out.scene_generation = scene_generation_;
  if (polled_scene_ != scene_generation_) {
    polled_scene_ = scene_generation_;
    out.scene_json = scene_json_;
    out.mesh_messages = mesh_messages_;
  }
  if (polled_history_ != history_generation_) {
    polled_history_ = history_generation_;
    out.history_json = history_json_locked();
    polled_seq_ = next_seq_ - 1;
  }
  for (auto& [topic, camera] : cameras_) {
    if (camera.frames == camera.sent_frame || now_s - camera.sent_at < image_interval_s_) continue;
    camera.sent_frame = camera.frames;
    camera.sent_at = now_s;
    std::string message = image_message_locked(topic, camera);
    if (!message.empty()) out.image_messages.push_back(std::move(message));
  }
  out.update_json = update_json_locked(polled_seq_, true);
  polled_seq_ = next_seq_ - 1;
  for (auto& [name, vehicle] : vehicles_) vehicle.polled_trail = vehicle.trail_total;
  return out;
}

PushOutput ViewerState::everything() {
  std::lock_guard<std::mutex> lock(mutex_);
  PushOutput out;
  out.scene_generation = scene_generation_;
  out.scene_json = scene_json_;
  out.mesh_messages = mesh_messages_;
  out.history_json = history_json_locked();
  for (auto& [topic, camera] : cameras_) {
    if (camera.frames != camera.jpeg_frame) image_message_locked(topic, camera);
    if (!camera.last_jpeg.empty()) out.image_messages.push_back(binary_message("JPEG", topic, camera.last_jpeg));
  }
  out.update_json = update_json_locked(next_seq_ - 1, false);  // the trails are in the history
  return out;
}

ViewerState::Contents ViewerState::contents() const {
  std::lock_guard<std::mutex> lock(mutex_);
  Contents contents;
  contents.scene = !scene_json_.empty();
  contents.status = !status_json_.empty();
  contents.sim_time = sim_time_;
  for (const auto& [topic, camera] : cameras_) {
    if (camera.frames > 0) contents.cameras.insert(topic);
  }
  return contents;
}

std::uint64_t ViewerState::samples() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return samples_;
}
std::uint64_t ViewerState::undecodable() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return undecodable_;
}
double ViewerState::sim_time() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sim_time_;
}

}  // namespace hadal::viewer
