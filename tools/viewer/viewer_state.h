// What hadal-viewer shows, kept from the samples it is handed (live from DDS or replayed from a bag):
// the scene (rt/hadal/scene), each vehicle's latest pose and twist (odometry) and its trail, the status
// line (rt/hadal/status), DVL beams and altimeter ranges, the acoustic signals in flight (rt/hadal/acoustic_links), cables' shapes (nav_msgs/Path), the latest camera frame per image topic, and
// time series for the plots (depth, speed, attitude, sensor streams). The push loop polls it at a bounded
// rate and sends what changed to the page as JSON text and binary blobs (tools/viewer/web/viewer.js
// reads them; docs/ARCHITECTURE.md, "Viewer").
//
// Frames and units as on the wire: W (ENU, z up), poses of B in W [m, unit quaternion], twists in B
// [m/s, rad/s]; series in the unit they name (attitude in degrees, for people).
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace hadal::viewer {

// One binary message to the page: a 4-byte tag, the name (length-prefixed, padded to 4 bytes), then the
// payload. "MESH": u32 float count, u32 index count, float32 positions, uint32 indices. "JPEG": the image.
std::string binary_message(const char (&tag)[5], const std::string& name, const std::string& payload);

// `text` as a JSON string: quoted, escaped, and valid UTF-8 (U+FFFD for bytes that are not).
std::string json_string(const std::string& text);

// `bytes` in base64 (RFC 4648, with padding).
std::string base64(const std::string& bytes);

struct PushOutput;
// /first.js: the page's first state as one script, so that it is part of the page's load (a browser's load
// event, and a one-shot screenshot, waits for it):
//   window.hadalFirst = {"scene_id": ID or null, "scene": {...} or null, "meshes": [base64, ...],
//                        "history": {...}, "images": [base64, ...], "update": {...}};
// the same messages, in the same order, as a WebSocket join sends (binary ones in base64). update_json: the
// update message to send (`all.update_json` with the source added). scene_id names the scene for the join
// that follows (ws?scene=ID skips it).
std::string first_state_script(const PushOutput& all, const std::string& scene_id, const std::string& update_json);

struct PushOutput {
  std::uint64_t scene_generation = 0;                      // which scene the state holds (0: none yet)
  std::string scene_json;                                  // set when the scene changed
  std::vector<std::string> mesh_messages;                  // with it, one binary message per mesh
  std::string history_json;                                // set when trails and series started over
  std::string update_json;                                 // the latest state, and new series points
  std::vector<std::string> image_messages;                 // camera frames due
};

class ViewerState {
 public:
  // image_interval_s: the shortest wall interval between two frames of one camera sent to the page.
  explicit ViewerState(double image_interval_s = 0.2) : image_interval_s_(image_interval_s) {}

  // One sample: its ROS 2 topic ("/auv/odometry") and type ("nav_msgs/msg/Odometry") and its CDR bytes.
  // Draws the scene, odometry, joint states (an articulated vehicle's moving bodies), status, DVL, ranges,
  // pressure, IMU, /clock (a bag's time) and any 8-bit image; a hadal_msgs/Monitor is taken apart into the
  // samples it carries, each once. Types the viewer does not draw are counted and otherwise ignored; a sample
  // that does not decode is counted as such.
  // Thread-safe.
  void add(const std::string& topic, const std::string& type, const unsigned char* data, std::size_t size);
  // The topics a live viewer reads: the scene, the monitor (rt/hadal/monitor: the latest sample of each light
  // topic, at most 20 per wall second, written by the server while read: server/src/dds/monitor.h) and camera
  // previews (<camera>/preview, half resolution, paced by the server: server/src/dds/image_preview.h). So a
  // viewer costs the server a few samples per wall second, not every stream delivered to one more reader.
  static bool shows(const std::string& topic, const std::string& type);
  // Forgets everything but the scene (a bag player seeking backwards).
  void clear();

  // What changed since the last poll (wall time now_s for the image rate). Thread-safe.
  PushOutput poll(double now_s);
  // Everything a newly connected page needs: the scene, the history and each camera's latest frame (encoded
  // now when no page has been sent it yet).
  PushOutput everything();

  // What the state holds so far (whether a page's first paint can show the run). Thread-safe.
  struct Contents {
    bool scene = false;           // a scene came
    bool status = false;          // a SimStatus came
    double sim_time = 0.0;        // the latest sim time seen [s]
    std::set<std::string> cameras;  // image topics with a frame
  };
  Contents contents() const;

  // Samples taken and samples that did not decode (for the status line and tests).
  std::uint64_t samples() const;
  std::uint64_t undecodable() const;
  double sim_time() const;

 private:
  struct Vehicle {
    bool has_pose = false;
    double p[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, v[3] = {0, 0, 0}, w[3] = {0, 0, 0};
    double stamp = 0;
    std::vector<float> trail;         // x y z per point, the latest kTrailPoints
    std::uint64_t trail_total = 0;    // points ever added (the first kept is trail_total - trail.size() / 3)
    std::uint64_t polled_trail = 0;   // points sent to the pages so far
    std::map<std::string, double> joints;  // the latest joint_states: each joint's position [rad or m]
  };
  struct Series {
    std::string plot, label, unit;
    std::deque<std::pair<double, double>> points;  // (sim time, value)
    std::deque<std::uint64_t> seq;                  // each point's sequence number
  };
  struct Camera {
    std::vector<unsigned char> bytes;  // the latest Image sample
    double stamp = 0;
    std::uint64_t frames = 0;
    std::uint64_t sent_frame = 0;
    double sent_at = -1e9;
    std::string last_jpeg;
    std::uint64_t jpeg_frame = 0;  // the frame last_jpeg is
    int width = 0, height = 0;
    std::string encoding;
  };

  void add_point(const std::string& key, const std::string& plot, const std::string& label, const std::string& unit,
                 double t, double value);
  void start_over();  // trails and series (new scene, or time went backwards)
  void note_time(const std::string& topic, double t);
  void add_monitor(const std::string& topic, const unsigned char* data, std::size_t size);
  std::string history_json_locked() const;
  // Series points after since_seq; with trail_points, the trail points not yet polled (else none).
  std::string update_json_locked(std::uint64_t since_seq, bool trail_points) const;
  static void append_trail(std::string& json, const Vehicle& vehicle, std::uint64_t from);
  static void append_series_info(std::string& json, const Series& series);
  std::string image_message_locked(const std::string& topic, Camera& camera);

  mutable std::mutex mutex_;
  double image_interval_s_;
  std::vector<unsigned char> scene_bytes_;  // the scene message as it came
  std::string scene_json_;
  std::vector<std::string> mesh_messages_;
  double water_surface_z_ = 0.0;
  std::uint64_t scene_generation_ = 0, polled_scene_ = 0;
  std::uint64_t history_generation_ = 1, polled_history_ = 0;
  std::map<std::string, Vehicle> vehicles_;
  std::map<std::string, Series> series_;
  std::uint64_t next_seq_ = 1, polled_seq_ = 0;
  std::map<std::string, Camera> cameras_;
  std::string status_json_;                       // the last SimStatus as JSON
  std::string acoustic_json_;                     // the last AcousticLinks as JSON (signals in flight)
  std::map<std::string, std::string> paths_;      // a cable's shape topic -> its points as a JSON array
  std::map<std::string, std::string> overlays_;   // "/auv/dvl" -> its JSON (beams, ranges)
  std::map<std::string, std::uint64_t> counts_;   // per topic
  std::map<std::string, double> topic_times_;  // per topic its latest stamp [s] (note_time)
  std::map<std::string, std::uint64_t> monitor_counts_;  // per topic carried by a monitor: the count last taken
  double sim_time_ = 0.0;
  std::uint64_t samples_ = 0, undecodable_ = 0;
};

}  // namespace hadal::viewer
