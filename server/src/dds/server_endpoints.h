// hadald's DDS side: every topic the server publishes or subscribes (docs/topics.md).
//
// Publishes rt/clock, rt/hadal/status, rt/hadal/step_reply, rt/hadal/scene (once, and again after a reset:
// dds/scene_message.h), rt/hadal/monitor (while read: dds/monitor.h), rt/hadal/acoustic_links (while it or the
// monitor is read), rt/<vehicle>/odometry (and rt/<vehicle>/sea_state in waves),
// rt/<vehicle>/<kind>/state of the actuator kinds and rt/<vehicle>/<sensor> (per sensor, its
// topics, of ROS types; camera previews while read: dds/image_preview.h); subscribes
// rt/<vehicle>/actuators/commands, the joint controllers' and modems' topics and rt/hadal/step_request. Incoming samples are queued by the DDS
// threads and taken by the step loop at step boundaries, so the loop never waits on DDS. Writers to
// setpoint topics of vehicles that do not exist are reported (a typo in a vehicle name is otherwise silent
// in DDS).
#pragma once

#include "hadal/core/model.h"
#include "hadal/core/state.h"
#include "hadal/sensors/sensor_kind.h"
#include "inbound.h"

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace hadal::physics {
class Ocean;
}

namespace hadal::dds {

struct StatusReport {
  double sim_time = 0.0;
  double wall_time = 0.0;
  double real_time_factor = 0.0;
  std::uint64_t step_count = 0;
  double step_size = 0.0;
  std::uint8_t mode = 0;  // hadal_msgs SimStatus MODE_*
  std::vector<std::uint32_t> vehicle_faults;
  std::uint64_t rejected_commands = 0;
  std::string last_error;
  std::uint64_t dropped_captures = 0;  // late in real time (Simulation::dropped_captures)
};

struct TopicCount {
  std::string topic;
  std::uint64_t samples = 0;
};

class ServerEndpoints {
 public:
  // How many samples the state writers (clock, status, odometry, actuator states) and the preview writers keep
  // for reliable readers that fall behind: 10 and 1; while the server records itself (`recorded`: hadald
  // --record) 100 (like the sensors' writers) and 10: its recorder reads every topic over DDS, and on a loaded
  // 2-core machine it fell more than 10 odometry samples (0.2 s of sim time), and a preview image, behind and
  // the bag lost them (interop.cyclone_decodes_recorded_bag).
  static constexpr int kStateHistoryDepth = 10, kRecordedStateHistoryDepth = 100;
  static constexpr int kPreviewHistoryDepth = 1, kRecordedPreviewHistoryDepth = 10;

  // `description` (which process this is: pid, host, scenario) goes with the participant for other hadald to name.
  ServerEndpoints(const Model& model, int domain_id, const std::string& description = {}, bool recorded = false);
  ~ServerEndpoints();
  ServerEndpoints(const ServerEndpoints&) = delete;
  ServerEndpoints& operator=(const ServerEndpoints&) = delete;

  // Commands received since the last call, in arrival order. At most kMaxQueuedCommands wait: beyond, the
  // oldest is dropped (a newer one of its vehicle replaces it anyway) and counted in superseded_commands().
  static constexpr std::size_t kMaxQueuedCommands = 1024;
  std::vector<InboundCommand> take_commands();
  std::uint64_t superseded_commands() const;
  // Step requests received and not yet taken (a server not in lockstep refuses them all).
  std::vector<InboundStepRequest> take_step_requests();
  // The next step request, waiting up to `timeout` for one: first polling for up to `spin` (no sleep, so a
  // request that comes within it costs no wake-up of this thread), then asleep until one comes.
  std::optional<InboundStepRequest> wait_step_request(std::chrono::milliseconds timeout,
                                                      std::chrono::microseconds spin = std::chrono::microseconds(0));
  // Wakes a wait_step_request() (used on shutdown).
  void interrupt();
  // Human-readable reports from the DDS threads (e.g. a writer for an unknown vehicle).
  std::vector<std::string> take_reports();
  // Warnings from the DDS threads: another hadald on the same domain, named by its description.
  std::vector<std::string> take_warnings();

  void publish_clock(double time_s);
  void publish_odometry(int vehicle_index, const SimState& state);
  // rt/<vehicle>/sea_state (hadal_msgs/SeaState) when the scenario has waves (nothing otherwise), from the
  // simulation's ocean.
  void publish_sea_state(int vehicle_index, const SimState& state, const physics::Ocean& ocean);
  // rt/<vehicle>/joint_states of an articulated vehicle (nothing for a rigid one).
  void publish_joint_states(int vehicle_index, const SimState& state);
  // rt/<vehicle>/<kind>/state of each actuator kind the vehicle publishes (thrusters: every vehicle; tracks,
  // fins, buoyancy engines, drop weights: those that have one; dds/actuator_topics.h).
  void publish_actuator_states(int vehicle_index, const SimState& state);
  // rt/hadal/cables/<name>/from, /to (geometry_msgs/WrenchStamped: the force cable c put on what holds each end
  // over the last step, in W) and /shape (nav_msgs/Path: its nodes in W).
  void publish_cable(int cable_index, const SimState& state);
  // The sensor's last sample (state.vehicles[v].sensors[s]).
  void publish_sensor(int vehicle_index, int sensor_index, const SimState& state);
  void publish_status(const StatusReport& report);
  // rt/hadal/monitor (dds/monitor.h): the latest sample of every light topic, when kMonitorInterval of wall
  // time has passed since the last, a reader is matched and a topic was written since. Cheap when not due:
  // call it as often as the loop comes by.
  void publish_monitor(double sim_time_s);
  // rt/hadal/acoustic_links (hadal_msgs/AcousticLinks): due when the scenario has acoustic sensors (modems, USBLs,
  // LBLs), kMonitorInterval of wall time has passed since the last and it or the monitor is read; then
  // publish_acoustic_links() with what is in flight (Simulation::acoustic_links). An empty list is sent once.
  bool acoustic_links_due();
  void publish_acoustic_links(double sim_time_s, const std::vector<sensors::AcousticLink>& links);
  // Every vehicle's ground truth rides along (fill_reply_states); unknown_vehicle names the vehicle a
  // request was refused for (else empty).
  void publish_step_reply(std::uint64_t request_id, bool accepted, const std::string& error,
                          const SimState& state, const std::string& unknown_vehicle = "");

  // Waits up to timeout_s for matched reliable readers to acknowledge everything written, so the
  // last samples of a run are not lost when the participant goes away.
  void flush(double timeout_s);
  // Drops the samples every writer kept (TopicRegistry::clear_kept_samples): after a lockstep reset, a
  // client subscribing later must not receive the run before's samples, whose stamps the new run repeats.
  void clear_kept_samples();

  // Samples written per published topic since start (for the run summary).
  std::vector<TopicCount> published_counts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hadal::dds
