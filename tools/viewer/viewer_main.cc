// hadal-viewer: a web page that shows a running hadald, or replays a rosbag2 bag of one
// (docs/ARCHITECTURE.md, "Viewer"; docs/viewer.md).
//
//   hadal-viewer [--domain-id N] [--port 8080] [--bind 127.0.0.1] [--token T] [--bag DIR]
//                [--rate-hz 20] [--image-rate-hz 5] [--nice 10] [--web-root DIR] [--three-root DIR]
//                [--security FILE]
//
// A separate process: it subscribes to the hadald on the domain over DDS like any client (nothing in the
// server knows of it) or reads the bag, keeps what the page shows (viewer_state.h) and pushes it over a
// WebSocket at --rate-hz, camera frames at --image-rate-hz per camera (JPEG). With no page open, a live
// viewer reads only the scene and waits: the server writes nothing more to it (LiveSource). Listens on
// loopback by default; any other address needs --token. Exit status 0 on SIGINT/SIGTERM, 1 when it cannot serve or
// read the bag, 2 on a usage error. --security: DDS Security with the `security:` block of FILE (docs/dds.md,
// "DDS Security"), to watch a secure hadald.
#include "hadal/core/data_dir.h"
#include "hadal/dds/domain_id.h"
#include "hadal/dds/topic_names.h"
#include "hadal/record/rosbag2_reader.h"
#include "hadal/record/rosbag2_writer.h"
#include "hadal/record/topic_tap.h"
#include "cli_args.h"
#include "json_number.h"
#include "parse_number.h"
#include "security_option.h"
#include "viewer_state.h"
#include "web_server.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <cerrno>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace {

using hadal::tools::json_number;
namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void handle_stop_signal(int) { g_stop.store(true); }

const char* const kUsage =
    "usage: hadal-viewer [--domain-id N] [--port 8080] [--bind 127.0.0.1] [--token T] [--bag DIR]\n"
    "                    [--rate-hz 20] [--image-rate-hz 5] [--nice 10] [--web-root DIR] [--three-root DIR]\n"
    "                    [--security FILE]\n";

// --rate-hz, --image-rate-hz: "" when `text` is a rate in (0, 100] Hz (into *out), else the usage error.
std::string read_rate_hz(const std::string& option, const std::string& text, double* out) {
  const hadal::tools::NumberRange range = hadal::tools::NumberRange::left_open(0.0, 100.0);
  if (!hadal::tools::parse_number(text, out) || !range.contains(*out)) {
    return option + " must be a rate " + range.text() + " Hz (got '" + text + "')";
  }
  return "";
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool is_loopback(const std::string& address) { return address == "localhost" || address.rfind("127.", 0) == 0; }

// The page's files: beside the executable in an install tree (P/bin -> P/share/hadal/viewer), else the
// source tree's.
std::string default_web_root() {
  const std::optional<hadal::DataDir> data = hadal::installed_data_dir();
  if (data && fs::is_regular_file(data->path / "viewer" / "index.html")) {
    return (data->path / "viewer").string();
  }
  return HADAL_VIEWER_SOURCE_WEB_ROOT;
}

// Live: the hadald on the domain. A viewer with no page open reads only the scene (written once, before
// anyone joins: reliable, transient-local), so the server writes nothing to it as it runs. From the moment
// a page is requested, while one is open and for kPageLinger after the last one closed (a page reloaded),
// a second participant reads the
// monitor (rt/hadal/monitor: the latest sample of every drawn stream, at most 20 per wall second, written
// by the server only while read; ViewerState::shows) and the camera previews (best effort: the server never
// resends a frame to the viewer), each with a reader that keeps the latest sample. The plots and trails
// thus have a gap where no page was open. hadald's topics are learnt once: a server restarted with another
// scenario needs the viewer restarted.
class LiveSource {
 public:
  static constexpr std::chrono::seconds kPageLinger{10};

  LiveSource(int domain, hadal::SecurityFiles security, hadal::viewer::ViewerState& state)
      : domain_(domain), security_(std::move(security)), state_(state) {}
  // Starts reading (and prints its line once it found hadald).
  void start() { thread_ = std::thread([this] { run(); }); }
  // A page was requested: start reading what it shows now, so that its first state (/first.js) has it.
  void page_loading() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      loading_until_ = std::chrono::steady_clock::now() + kPageLinger;
    }
    wake_.notify_one();
  }
  // Whether hadald was found on the domain (its scene then comes, however slowly a loaded machine reads it).
  bool found() const { return discovered_; }
  // Whether a page's first paint can show the run: the scene, the monitor's status and a frame of every
  // camera preview hadald writes.
  bool first_paint_ready(const hadal::viewer::ViewerState::Contents& contents) {
    if (!discovered_ || !page_streams_ || !contents.scene || !contents.status) return false;
    std::lock_guard<std::mutex> lock(mutex_);
    return std::includes(contents.cameras.begin(), contents.cameras.end(), previews_.begin(), previews_.end());
  }
  // How many pages are open (the push loop tells, each tick and when one connects).
  void set_pages(int pages) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (pages == pages_) return;
      pages_ = pages;
    }
    wake_.notify_one();
  }
  ~LiveSource() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
  }
  // Connected: hadald's writers were found and, once the monitor is read, a sample came within the last 3 s
  // (the monitor carries hadald's status, a 10 Hz wall-clock heartbeat).
  std::string json() const {
    const bool connected = discovered_ && (!reading_pages_ || now_s() - last_sample_s_.load() < 3.0);
    return "{\"kind\":\"live\",\"domain\":" + std::to_string(domain_) +
           ",\"connected\":" + (connected ? "true" : "false") + "}";
  }
  bool failed() const { return failed_; }

 private:
  enum class Streams { kScene, kMonitor, kPreviews };

  void run() {
    try {
      read();
    } catch (const std::exception& e) {  // DDS set-up (e.g. a participant that cannot be made)
      std::fprintf(stderr, "hadal-viewer: error: %s\n", e.what());
      failed_ = true;
    }
  }

  void read() {
    hadal::record::TopicTap tap(domain_, "hadal_viewer", {}, security_);
    while (!stopping() && !tap.discover(1.0)) {
    }
    if (stopping()) return;
    for (const auto& [dds_topic, writer] : tap.writers()) {
      std::string topic, type;
      if (hadal::dds::ros_topic_name(dds_topic, &topic) && hadal::dds::ros_type_name(writer.type, &type)) {
        names_[dds_topic] = {topic, type};
      }
    }
    discovered_ = true;
    if (subscribe(tap, Streams::kScene)) {
      std::printf("hadal-viewer: watching hadald (%zu topics; its monitor and previews are read while a page is "
                  "open)\n", names_.size());
      std::fflush(stdout);
    } else {
      std::fprintf(stderr, "hadal-viewer: hadald's scene did not match within 20 s\n");
    }
    std::unique_ptr<hadal::record::TopicTap> page_tap;
    auto last_page = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      // Idle (no page, no tap to close) until a page opens; else a look each second for the linger's end.
      wake_.wait_for(lock, std::chrono::seconds(1), [&] {
        return stop_ || ((pages_ > 0 || std::chrono::steady_clock::now() < loading_until_) && !page_tap);
      });
      if (stop_) break;
      const auto now = std::chrono::steady_clock::now();
      if (pages_ > 0) last_page = now;
      const bool want = pages_ > 0 || now < loading_until_;
      lock.unlock();
      if (want && !page_tap) {
        page_tap = std::make_unique<hadal::record::TopicTap>(domain_, "hadal_viewer_page",
                                                             std::set<std::string>{}, security_);
        if (page_tap->discover(5.0, 0.2)) {
          last_sample_s_ = now_s();  // found again: give the monitor its 3 s
          reading_pages_ = true;
          const bool matched = subscribe(*page_tap, Streams::kMonitor) && subscribe(*page_tap, Streams::kPreviews);
          if (!matched) std::fprintf(stderr, "hadal-viewer: not every shown topic of hadald matched within 20 s\n");
          page_streams_ = true;
        } else {
          page_tap.reset();  // hadald gone for now: try again
        }
      } else if (!want && page_tap && now - last_page >= kPageLinger) {
        page_tap.reset();
        reading_pages_ = false;
        page_streams_ = false;
      }
      lock.lock();
    }
  }

  bool stopping() {
    std::lock_guard<std::mutex> lock(mutex_);
    return stop_;
  }

  // Of the topics the tap found, those of `streams` (ViewerState::shows says which a viewer reads at all).
  bool subscribe(hadal::record::TopicTap& tap, Streams streams) {
    return tap.subscribe(
        [this](const hadal::record::TappedSample& sample) {
          last_sample_s_ = now_s();
          const auto name = names_.find(sample.topic);
          if (name != names_.end()) {
            state_.add(name->second.first, name->second.second, sample.bytes.data(), sample.bytes.size());
          }
        },
        20.0, streams != Streams::kPreviews,
        [this, streams](const std::string& dds_topic, const hadal::record::TappedWriter&) {
          const auto name = names_.find(dds_topic);
          if (name == names_.end()) return false;
          const auto& [topic, type] = name->second;
          if (!hadal::viewer::ViewerState::shows(topic, type)) return false;
          if (type == "hadal_msgs/msg/Scene") return streams == Streams::kScene;
          if (type == "sensor_msgs/msg/Image") {
            if (streams != Streams::kPreviews) return false;
            std::lock_guard<std::mutex> lock(mutex_);
            previews_.insert(topic);
            return true;
          }
          return streams == Streams::kMonitor;
        },
        true);
  }

  int domain_;
  hadal::SecurityFiles security_;
  hadal::viewer::ViewerState& state_;
  std::map<std::string, std::pair<std::string, std::string>> names_;  // DDS topic -> ROS topic, type
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;  // guarded by mutex_
  int pages_ = 0;      // guarded by mutex_
  std::chrono::steady_clock::time_point loading_until_{};  // guarded by mutex_
  std::set<std::string> previews_;                         // the preview topics read; guarded by mutex_
  // page_streams_: the monitor and previews are subscribed (so previews_ is complete).
  std::atomic<bool> failed_{false}, discovered_{false}, reading_pages_{false}, page_streams_{false};
  std::atomic<double> last_sample_s_{-1e9};
  std::thread thread_;
};

// Bag replay: plays the bag in its own time (x speed), seeks on the page's command. A seek feeds what lies
// before the target again (backwards: from the start), every message but the camera frames, of which
// only each camera's last before the target.
class BagPlayer {
 public:
  BagPlayer(std::unique_ptr<hadal::record::Rosbag2Reader> reader, std::string path, hadal::viewer::ViewerState& state)
      : reader_(std::move(reader)), path_(std::move(path)), state_(state) {
    const auto& index = reader_->index();
    if (!index.empty()) start_ns_ = index.front().timestamp_ns, end_ns_ = index.back().timestamp_ns;
    t_ns_ = start_ns_;
    for (const auto& topic : reader_->topics()) is_image_.push_back(topic.type == "sensor_msgs/msg/Image");
    // A first paint shows every camera's first frame: it waits until the player has fed them.
    std::set<int> seen;
    first_frames_ns_ = start_ns_;
    for (const auto& entry : index) {
      if (is_image_[entry.topic] && seen.insert(entry.topic).second) first_frames_ns_ = entry.timestamp_ns;
    }
    thread_ = std::thread([this] { run(); });
  }
  ~BagPlayer() {
    stop_ = true;
    thread_.join();
  }
  void command(const std::string& text) {
    if (text.size() > 200) return;  // a page's commands are short; nothing long reaches the regexes
    static const std::regex cmd_re("\"cmd\"\\s*:\\s*\"(\\w+)\"");
    static const std::regex t_re("\"t\"\\s*:\\s*(-?[0-9.eE+-]+)");
    static const std::regex x_re("\"x\"\\s*:\\s*([0-9.eE+-]+)");
    std::smatch m;
    if (!std::regex_search(text, m, cmd_re)) return;
    const std::string cmd = m[1];
    std::lock_guard<std::mutex> lock(mutex_);
    double value = 0.0;
    if (cmd == "play") {
      if (t_ns_ >= end_ns_) seek_ns_ = start_ns_;
      playing_ = true;
    } else if (cmd == "pause") {
      playing_ = false;
    } else if (cmd == "seek" && std::regex_search(text, m, t_re) && hadal::tools::parse_number(m[1], &value)) {
      seek_ns_ = start_ns_ + static_cast<std::int64_t>(std::clamp(value, 0.0, 1e-9 * (end_ns_ - start_ns_)) * 1e9);
    } else if (cmd == "speed" && std::regex_search(text, m, x_re) && hadal::tools::parse_number(m[1], &value)) {
      speed_ = std::clamp(value, 0.05, 100.0);
    }
  }
  // Whether a page's first paint can show the bag: its scene, and the frames up to every camera's first.
  bool first_paint_ready(const hadal::viewer::ViewerState::Contents& contents) const {
    return contents.scene && fed_ns_.load() >= first_frames_ns_;
  }
  std::string json() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return "{\"kind\":\"bag\",\"path\":" + hadal::viewer::json_string(path_) +
           ",\"duration\":" + json_number(1e-9 * (end_ns_ - start_ns_)) +
           ",\"t\":" + json_number(1e-9 * (t_ns_ - start_ns_)) + ",\"playing\":" + (playing_ ? "true" : "false") +
           ",\"speed\":" + json_number(speed_) + ",\"messages\":" + std::to_string(reader_->index().size()) + "}";
  }

 private:
  // Feeds the messages from next_ up to and including time target_ns; skip_frames: of each camera only
  // its last frame.
  void feed_until(std::int64_t target_ns, bool skip_frames) {
    const auto& index = reader_->index();
    std::size_t end = next_;
    while (end < index.size() && index[end].timestamp_ns <= target_ns) ++end;
    std::map<int, std::size_t> last_frame;
    if (skip_frames) {
      for (std::size_t i = next_; i < end; ++i) {
        if (is_image_[index[i].topic]) last_frame[index[i].topic] = i;
      }
    }
    std::vector<unsigned char> bytes;
    std::string error;
    for (std::size_t i = next_; i < end; ++i) {
      const auto& entry = index[i];
      if (skip_frames && is_image_[entry.topic] && last_frame[entry.topic] != i) continue;
      if (!reader_->read(entry, &bytes, &error)) {
        std::fprintf(stderr, "hadal-viewer: %s\n", error.c_str());
        continue;
      }
      const auto& topic = reader_->topics()[entry.topic];
      state_.add(topic.name, topic.type, bytes.data(), bytes.size());
    }
    next_ = end;
  }

  void run() {
    // The scene first, wherever it lies in the bag: it is written once, before the first step, but a
    // recorder may take it after a few steps of a fast run (its bag time is then later).
    const auto& index = reader_->index();
    for (const auto& entry : index) {
      const auto& topic = reader_->topics()[entry.topic];
      std::vector<unsigned char> bytes;
      std::string error;
      if (topic.type == "hadal_msgs/msg/Scene" && reader_->read(entry, &bytes, &error)) {
        state_.add(topic.name, topic.type, bytes.data(), bytes.size());
        break;
      }
    }
    feed_until(start_ns_, true);
    fed_ns_ = start_ns_;
    double last = now_s();
    while (!stop_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      const double now = now_s();
      std::int64_t target = 0;
      bool seek = false;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (seek_ns_ >= 0) {
          target = seek_ns_;
          seek_ns_ = -1;
          seek = true;
          if (target < t_ns_) {
            state_.clear();
            next_ = 0;
          }
        } else if (playing_) {
          target = std::min(end_ns_, t_ns_ + static_cast<std::int64_t>((now - last) * speed_ * 1e9));
          if (target >= end_ns_) playing_ = false;
        } else {
          target = t_ns_;
        }
        t_ns_ = target;
      }
      last = now;
      feed_until(target, seek);
      fed_ns_ = target;
    }
  }

  std::unique_ptr<hadal::record::Rosbag2Reader> reader_;
  std::string path_;
  hadal::viewer::ViewerState& state_;
  std::vector<bool> is_image_;
  std::int64_t start_ns_ = 0, end_ns_ = 0, first_frames_ns_ = 0;
  std::atomic<std::int64_t> fed_ns_{-1};  // the time up to which the state has the bag's messages
  mutable std::mutex mutex_;
  std::int64_t t_ns_ = 0, seek_ns_ = -1;
  bool playing_ = true;
  double speed_ = 1.0;
  std::size_t next_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace

int main(int argc, char** argv) {
  hadal::viewer::WebOptions web;
  web.web_root = default_web_root();
  web.three_root = "/usr/share/javascript/three";
  int domain = 0;
  bool domain_given = false;
  std::string bag;
  hadal::SecurityFiles security;
  double rate_hz = 20.0, image_rate_hz = 5.0;
  int nice = 10;
  hadal::tools::CommandLine command_line("hadal-viewer", kUsage);
  command_line.error_prefix("error: ")
      .missing_value_words("option %s needs a value")
      .unknown_words("unknown argument %s")
      .option("--security",
              [&](const std::string& value) { return hadal::tools::read_security_option(value, &security); })
      .option("--domain-id",
              [&](const std::string& value) {
                domain_given = true;
                return hadal::dds::read_domain_id_option(value, &domain);
              })
      .option("--port",
              [&](const std::string& value) -> std::string {
                if (!hadal::tools::parse_int(value, 0, 65535, &web.port)) {
                  return "--port must be an integer in 0..65535 (got '" + value + "'; 0: any free port)";
                }
                return "";
              })
      .text("--bind", &web.bind)
      .option("--token",
              [&](const std::string& value) -> std::string {
                web.token = value;
                const char* const kTokenCharacters =
                    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_.~";
                if (web.token.empty() || web.token.size() > 128 ||
                    web.token.find_first_not_of(kTokenCharacters) != std::string::npos) {
                  return "--token takes 1 to 128 letters, digits and -_.~ (it goes into a URL)";
                }
                return "";
              })
      .text("--bag", &bag)
      .option("--rate-hz", [&](const std::string& value) { return read_rate_hz("--rate-hz", value, &rate_hz); })
      .option("--image-rate-hz",
              [&](const std::string& value) { return read_rate_hz("--image-rate-hz", value, &image_rate_hz); })
      .option("--nice",
              [&](const std::string& value) -> std::string {
                return hadal::tools::parse_int(value, 0, 19, &nice) ? "" : "--nice takes an integer in 0..19";
              })
      .text("--web-root", &web.web_root)
      .text("--three-root", &web.three_root);
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (!domain_given) {
    if (const std::string error = hadal::dds::domain_id_from_environment(std::getenv("ROS_DOMAIN_ID"), &domain); !error.empty()) {
      return command_line.usage_error(error);
    }
  }
  if (!is_loopback(web.bind) && web.token.empty()) {
    return command_line.usage_error("--bind " + web.bind + " lets other machines in: give --token T (the page is "
                                    "then opened as http://HOST:PORT/?token=T), or keep the default 127.0.0.1 and "
                                    "use an SSH tunnel");
  }

  // A monitor must not slow what it watches: on a machine whose CPUs a fast-mode hadald fills, the viewer's
  // threads (all made after this; Linux keeps a nice value per thread and new threads inherit it) yield to
  // the server's. Raising one's own nice value needs no privilege.
  if (nice > 0 && setpriority(PRIO_PROCESS, 0, nice) != 0) {
    std::fprintf(stderr, "hadal-viewer: warning: could not lower its priority (nice %d): %s\n", nice,
                 std::strerror(errno));
  }
  hadal::viewer::ViewerState state(1.0 / image_rate_hz);
  std::unique_ptr<BagPlayer> player;
  std::unique_ptr<LiveSource> live;
  if (!bag.empty()) {
    std::string error;
    auto reader = hadal::record::Rosbag2Reader::open(bag, &error);
    if (!reader) {
      std::fprintf(stderr, "hadal-viewer: error: %s\n", error.c_str());
      return 1;
    }
    player = std::make_unique<BagPlayer>(std::move(reader), bag, state);
  } else {
    live = std::make_unique<LiveSource>(domain, security, state);
  }

  // The scene a page has, named across viewer processes (a page reconnects to a restarted viewer).
  const std::string instance = std::to_string(getpid()) + "." +
                               std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
  auto scene_id = [&](std::uint64_t generation) { return instance + "." + std::to_string(generation); };
  auto with_source = [&](std::string update) {
    const std::string source = player ? player->json() : live->json();
    return update.insert(update.size() - 1, ",\"source\":" + source);
  };

  std::mutex clients_mutex;
  std::condition_variable client_joined;
  struct Joined {
    hadal::viewer::WebServer::ClientId client;
    std::string query;  // "scene=ID": the page has that scene (from /first.js)
  };
  std::vector<Joined> new_clients;
  hadal::viewer::WebCallbacks callbacks;
  callbacks.on_page = [&] {
    if (live) live->page_loading();
  };
  // The page's first state, part of its load: a page (or a one-shot screenshot) shows the run at its load
  // event, not a "waiting" line. Served once the source has what a first paint shows (the scene, the status,
  // a frame of every camera), or the run has not advanced for kIdle (lockstep between steps, a paused bag:
  // no frame will come), or when hadald is not found kNoScene after the request (no hadald yet: the WebSocket
  // brings the scene when there is one; once hadald is found its scene is waited for), or after
  // kFirstPaintWait, whichever is first.
  callbacks.first_state = [&] {
    constexpr double kFirstPaintWait_s = 10.0, kNoScene_s = 2.0, kIdle_s = 1.0, kLook_s = 0.05;
    if (live) live->page_loading();
    const double start = now_s();
    double last_sim_time = -1.0, moved_at = start;
    while (!g_stop.load() && now_s() - start < kFirstPaintWait_s) {
      const hadal::viewer::ViewerState::Contents contents = state.contents();
      if (player ? player->first_paint_ready(contents) : live->first_paint_ready(contents)) break;
      if (!contents.scene && !(live && live->found()) && now_s() - start >= kNoScene_s) break;
      if (contents.sim_time != last_sim_time) {
        last_sim_time = contents.sim_time;
        moved_at = now_s();
      } else if (contents.scene && contents.status && now_s() - moved_at >= kIdle_s) {
        break;
      }
      std::this_thread::sleep_for(std::chrono::duration<double>(kLook_s));
    }
    const hadal::viewer::PushOutput all = state.everything();
    return hadal::viewer::first_state_script(all, scene_id(all.scene_generation), with_source(all.update_json));
  };
  callbacks.on_client = [&](hadal::viewer::WebServer::ClientId client, const std::string& query) {
    {
      std::lock_guard<std::mutex> lock(clients_mutex);
      new_clients.push_back({client, query});
    }
    client_joined.notify_one();
  };
  callbacks.on_command = [&](const std::string& text) {
    if (player) player->command(text);
  };
  std::string error;
  auto server = hadal::viewer::WebServer::start(web, callbacks, &error);
  if (!server) {
    std::fprintf(stderr, "hadal-viewer: error: %s\n", error.c_str());
    return 1;
  }

  std::signal(SIGINT, handle_stop_signal);
  std::signal(SIGTERM, handle_stop_signal);
  const std::string url = "http://" + web.bind + ":" + std::to_string(server->port()) + "/" +
                          (web.token.empty() ? "" : "?token=" + web.token);
  std::printf("hadal-viewer: serving %s (%s; page from %s)\n", url.c_str(),
              player ? ("bag " + bag).c_str() : ("live: DDS domain " + std::to_string(domain)).c_str(),
              web.web_root.c_str());
  std::fflush(stdout);
  if (live) live->start();  // prints its own line once it found hadald

  // The push loop: what changed, at rate_hz, to every page; everything to a page that just connected. With
  // no page open it does nothing but wait for one (looking at the stop flag 4 times a second).
  const auto period = std::chrono::duration<double>(1.0 / rate_hz);
  auto wake = std::chrono::steady_clock::now();
  while (!g_stop.load() && !(live && live->failed())) {
    std::vector<Joined> joined;
    {
      std::unique_lock<std::mutex> lock(clients_mutex);
      if (server->clients() == 0 && new_clients.empty()) {
        if (live) live->set_pages(0);
        client_joined.wait_for(lock, std::chrono::milliseconds(250), [&] { return !new_clients.empty(); });
        wake = std::chrono::steady_clock::now();
        if (new_clients.empty()) continue;
      } else {
        lock.unlock();
        wake += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
        std::this_thread::sleep_until(wake);
        lock.lock();
      }
      joined.swap(new_clients);
    }
    if (live) live->set_pages(server->clients());
    hadal::viewer::PushOutput out = state.poll(now_s());
    if (!out.scene_json.empty()) {
      server->broadcast(out.scene_json, false);
      for (const std::string& mesh : out.mesh_messages) server->broadcast(mesh, true);
    }
    if (!out.history_json.empty()) server->broadcast(out.history_json, false);
    for (const std::string& image : out.image_messages) server->broadcast(image, true);
    server->broadcast(with_source(out.update_json), false);
    for (const auto& [client, query] : joined) {
      const hadal::viewer::PushOutput all = state.everything();
      if (!all.scene_json.empty() && query != "scene=" + scene_id(all.scene_generation)) {
        server->send(client, all.scene_json, false);
        for (const std::string& mesh : all.mesh_messages) server->send(client, mesh, true);
      }
      server->send(client, all.history_json, false);
      for (const std::string& image : all.image_messages) server->send(client, image, true);
      server->send(client, with_source(all.update_json), false);
      server->admit(client);
    }
    if (std::chrono::steady_clock::now() > wake + std::chrono::seconds(1)) wake = std::chrono::steady_clock::now();
  }
  std::fprintf(stderr, "hadal-viewer: %llu sample(s) shown, %llu undecodable\n",
               static_cast<unsigned long long>(state.samples()), static_cast<unsigned long long>(state.undecodable()));
  const bool failed = live && live->failed();
  server.reset();
  player.reset();
  live.reset();
  return failed ? 1 : 0;
}
