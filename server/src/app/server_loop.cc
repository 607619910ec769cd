#include "server_loop.h"

#include "hadal/core/rate_divider.h"
#include "hadal/core/simulation.h"
#include "hadal/geometry/ray_batch.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/record/bag_recorder.h"
#include "../dds/server_endpoints.h"
#include "hadal/dds/guarded_type.h"

#include <hadal_msgs.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>
#include <thread>

namespace hadal::app {

namespace {

using Clock = std::chrono::steady_clock;

std::uint8_t mode_code(RunMode mode) {
  namespace C = hadal_msgs::msg::SimStatus_Constants;
  switch (mode) {
    case RunMode::kRealtime: return C::MODE_REALTIME;
    case RunMode::kFast: return C::MODE_FAST;
    case RunMode::kLockstep: return C::MODE_LOCKSTEP;
  }
  return C::MODE_REALTIME;
}

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Which hadald this is, for another on the same domain to name (dds::ServerEndpoints).
std::string describe_process(const CliOptions& options) {
  char host[256] = {};
  if (gethostname(host, sizeof(host) - 1) != 0) host[0] = '\0';
  return "pid " + std::to_string(getpid()) + " on " + (host[0] != '\0' ? std::string(host) : "this host") +
         ", scenario " + options.scenario_file + ", mode " + to_string(options.mode);
}

class Runner {
 public:
  Runner(const Model& model, const CliOptions& options, const std::atomic<bool>& stop)
      : model_(model),
        options_(options),
        stop_(stop),
        sim_(model),
        dds_(model, options.domain_id, describe_process(options), /*recorded=*/!options.record_dir.empty()) {
    // In real time a capture whose rays are late is dropped: the step loop never waits on the workers.
    sim_.set_wait_for_captures(options.mode != RunMode::kRealtime);
    clock_divider_ = RateDivider(model.world.clock_rate_hz);
    const std::size_t n = model.vehicles.size();
    for (const auto& cable : model_.cables) cable_dividers_.emplace_back(cable.rate_hz);
    odometry_dividers_.reserve(n);
    for (const auto& v : model.vehicles) {
      odometry_dividers_.emplace_back(v.odometry_rate_hz);
      actuator_state_dividers_.emplace_back(v.actuator_state_rate_hz);
    }
    for (const auto& v : model.vehicles) published_samples_.emplace_back(v.sensors.size(), 0);
    last_command_stamp_.assign(n, std::numeric_limits<std::int64_t>::min());
    last_command_source_.assign(n, dds::SourceId{});
    distance_.assign(n, 0.0);
    reported_resets_.assign(n, 0);
    for (const auto& v : sim_.state().vehicles) start_positions_.push_back(v.body.X_WB.translation());
    previous_positions_ = start_positions_;
  }

  RunSummary run() {
    start_wall_ = Clock::now();
    last_status_wall_ = start_wall_;
    publish_status();
    if (!options_.record_dir.empty()) start_recording();
    const double discovery_wait = options_.effective_discovery_wait();
    const Clock::time_point wait_end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                          std::chrono::duration<double>(discovery_wait));
    while (!stop_.load() && Clock::now() < wait_end) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      service_wall_clock();
    }
    start_wall_ = Clock::now();
    last_status_wall_ = start_wall_;
    last_line_wall_ = start_wall_;
    publish_due();
    switch (options_.mode) {
      case RunMode::kRealtime:
      case RunMode::kFast: run_free(); break;
      case RunMode::kLockstep: run_lockstep(); break;
    }
    publish_status();
    RunSummary result = summary();  // before the flush, so the wall time is the run's alone
    dds_.flush(1.0);
    if (recorder_) {
      const std::string error = recorder_->stop();
      std::fprintf(stderr, "hadald: recorded %llu message(s) into %s\n",
                   static_cast<unsigned long long>(recorder_->message_count()), options_.record_dir.c_str());
      if (const std::string lost = recorder_->lost_samples_text(); !lost.empty()) {
        std::fprintf(stderr, "hadald: warning: --record: samples lost (the recorder fell behind): %s\n", lost.c_str());
      }
      if (!error.empty()) std::fprintf(stderr, "hadald: error: --record: %s\n", error.c_str());
    }
    return result;
  }

 private:
  // hadald --record: the same recorder as hadal-record, on its own participant in this process, subscribed
  // (and matched) before the first step, so a run is recorded from t = 0. Bag time is sim time.
  void start_recording() {
    record::BagRecorderOptions options;
    options.domain_id = options_.domain_id;
    options.directory = options_.record_dir;
    options.use_sim_time = true;
    options.participant_name = "hadald_record";
    options.security = model_.security;  // a secure hadald's writers match secure readers only
    recorder_ = std::make_unique<record::BagRecorder>(options);
    if (const std::string error = recorder_->start(); !error.empty()) {
      recorder_.reset();
      throw std::runtime_error("--record " + options_.record_dir + ": " + error);
    }
    std::fprintf(stderr, "hadald: recording %zu topic(s) into %s\n", recorder_->topic_count(),
                 options_.record_dir.c_str());
  }

  bool duration_reached() const {
    // Half a step of slack: sim time is k * dt, so the last step lands within rounding of the duration.
    return options_.duration && sim_.time() >= *options_.duration - 0.5 * model_.world.step_size();
  }

  void run_free() {
    const double dt = model_.world.step_size();
    const bool realtime = options_.mode == RunMode::kRealtime;
    const std::uint64_t first_step = sim_.state().step_count;
    while (!stop_.load() && !duration_reached()) {
      if (realtime) {
        const double target_s =
            static_cast<double>(sim_.state().step_count - first_step) * dt / options_.real_time_factor;
        std::this_thread::sleep_until(start_wall_ + std::chrono::duration_cast<Clock::duration>(
                                                        std::chrono::duration<double>(target_s)));
      }
      step_once();
      service_wall_clock();
    }
  }

  void run_lockstep() {
    // Polls for the next request only right after a reply (a client in a loop sends it within tens of
    // microseconds), never while idle.
    bool replied = false;
    while (!stop_.load() && !duration_reached()) {
      auto request = dds_.wait_step_request(
          std::chrono::milliseconds(50), replied ? std::chrono::microseconds(options_.lockstep_spin_us)
                                                 : std::chrono::microseconds(0));
      service_wall_clock();
      replied = request.has_value();
      if (!request) continue;
      if (!request->error.empty()) {
        reject("step request " + std::to_string(request->request_id) + ": " + request->error);
        dds_.publish_step_reply(request->request_id, false, request->error, sim_.state(), request->unknown_vehicle);
        continue;
      }
      // All attached commands are checked before any is applied: a refused request changes nothing.
      std::string refused;
      for (const auto& command : request->commands) {
        const std::string reason =
            command.winch
                ? sim_.check_winch_command(command.winch->cable_index, command.winch->speed, command.winch->target_length)
            : command.packet
                ? sim_.check_packet(command.vehicle_index, command.packet->modem, command.packet->destination,
                                    command.packet->payload.size())
            : command.trajectory
                ? sim_.check_joint_trajectory(command.vehicle_index, command.joint_controller, *command.trajectory)
            : command.joint_controller.empty()
                ? sim_.check_controls(command.vehicle_index, command.setpoints)
                : sim_.check_joint_commands(command.vehicle_index, command.joint_controller, command.setpoints);
        if (!reason.empty() && refused.empty()) refused = dds::command_target(model_, command) + ": " + reason;
      }
      if (!refused.empty()) {
        reject("step request " + std::to_string(request->request_id) + ": " + refused);
        dds_.publish_step_reply(request->request_id, false, refused, sim_.state());
        continue;
      }
      if (request->reset) {
        // Checked before anything is applied, like the commands: a refused reset changes nothing.
        const std::string reason = sim_.reset(request->reset_seed.value_or(model_.world.seed), request->reset_X_WB);
        if (!reason.empty()) {
          reject("step request " + std::to_string(request->request_id) + ": " + reason);
          dds_.publish_step_reply(request->request_id, false, reason, sim_.state());
          continue;
        }
        restart_streams();
      }
      for (const auto& command : request->commands) apply_command(command);
      std::uint32_t done = 0;
      for (; done < request->steps && !stop_.load() && !duration_reached(); ++done) {
        step_once();
        service_wall_clock();  // the status heartbeat goes on through a long request
      }
      if (done < request->steps) {  // cut short: the reply says so, with how far it got
        const std::string reason = "stopped after " + std::to_string(done) + " of " + std::to_string(request->steps) +
                                   " steps: the server is shutting down or reached its --duration";
        dds_.publish_step_reply(request->request_id, false, reason, sim_.state());
        continue;
      }
      dds_.publish_step_reply(request->request_id, true, "", sim_.state());
    }
  }

  // After a reset (sim time back at 0): every stream starts again as at the start, commands that
  // arrived on the setpoint topics before the reset are dropped, the writers forget the samples they
  // kept for late joiners (the run before's, whose stamps would satisfy a wait for the new run's), and
  // the initial state is published (the samples a fresh server would publish at t = 0) before the reply.
  void restart_streams() {
    dds_.take_commands();
    rtf_.clear();  // sim time starts over
    dds_.clear_kept_samples();
    clock_divider_.reset();
    for (auto& divider : odometry_dividers_) divider.reset();
    for (auto& divider : cable_dividers_) divider.reset();
    for (auto& divider : actuator_state_dividers_) divider.reset();
    for (auto& samples : published_samples_) std::fill(samples.begin(), samples.end(), 0);
    std::fill(last_command_stamp_.begin(), last_command_stamp_.end(), std::numeric_limits<std::int64_t>::min());
    std::fill(last_command_source_.begin(), last_command_source_.end(), dds::SourceId{});
    last_joint_command_.clear();
    const auto& vehicles = sim_.state().vehicles;
    for (std::size_t i = 0; i < vehicles.size(); ++i) {
      // The summary's distances, like its sim time and steps, count from the reset (the pose it set).
      start_positions_[i] = previous_positions_[i] = vehicles[i].body.X_WB.translation();
      distance_[i] = 0.0;
      reported_resets_[i] = vehicles[i].fault_resets;
    }
    ++resets_;
    publish_due();
  }

  // Returns the rejection reason, or "" when the command was applied or superseded.
  std::string apply_command(const dds::InboundCommand& command) {
    if (!command.error.empty()) return command.error;
    if (command.winch) {  // the last command wins: each replaces the winch's command
      return sim_.command_winch(command.winch->cable_index, command.winch->speed, command.winch->target_length);
    }
    const auto v = static_cast<std::size_t>(command.vehicle_index);
    if (command.packet) {  // every packet is sent: none supersedes another
      dds::InboundCommand::Packet packet = *command.packet;
      return sim_.send_packet(command.vehicle_index, packet.modem, packet.destination, std::move(packet.payload));
    }
    if (!command.joint_controller.empty()) {
      // The same staleness rule, per joint controller.
      auto& [source, stamp] = last_joint_command_[{command.vehicle_index, command.joint_controller}];
      if (command.source == source && command.source_stamp_ns < stamp) return "";
      const std::string reason =
          command.trajectory
              ? sim_.set_joint_trajectory(command.vehicle_index, command.joint_controller, *command.trajectory)
              : sim_.set_joint_commands(command.vehicle_index, command.joint_controller, command.setpoints);
      if (reason.empty()) {
        source = command.source;
        stamp = command.source_stamp_ns;
      }
      return reason;
    }
    // DDS does not order samples across topics: a command older than one its own sender had applied (the
    // setpoints a client also attached to a step request, arriving after it) is stale. Stamps of
    // different senders come from different clocks and are never compared: between senders, the later
    // arrival wins.
    if (command.source == last_command_source_[v] && command.source_stamp_ns < last_command_stamp_[v]) return "";
    const std::string reason = sim_.set_controls(command.vehicle_index, command.setpoints);
    if (reason.empty()) {
      last_command_stamp_[v] = command.source_stamp_ns;
      last_command_source_[v] = command.source;
    }
    return reason;
  }

  // hadald --record: a writer keeps its last samples for a reliable reader that falls behind (100 of a state or
  // sensor topic, 10 of a camera preview), and a fast run outpaced its recorder (writing the bag) by more than that
  // within seconds (default.yaml, 20 s: a tenth of the IMU's samples lost): every kRecorderCheckSteps steps, the
  // loop waits until the recorder is within kRecorderLag samples of every topic it records (a topic gains at most
  // one sample a step: it never falls more than 15 behind), so the bag loses nothing; the run goes as fast as the
  // recorder. A recorder stuck for 10 s is left behind, once, with a warning (its losses are reported at the end).
  static constexpr std::uint64_t kRecorderCheckSteps = 10;
  static constexpr std::int64_t kRecorderLag = 5;
  void keep_recorder_up() {
    if (!recorder_ || recorder_stuck_ || sim_.state().step_count % kRecorderCheckSteps != 0) return;
    const auto deadline = Clock::now() + std::chrono::seconds(10);
    for (;;) {
      const std::map<std::string, std::int64_t> read = recorder_->last_sequences();
      bool behind = false;
      for (const dds::TopicCount& count : dds_.published_counts()) {
        const auto last = read.find(count.topic);
        if (last != read.end() && static_cast<std::int64_t>(count.samples) - last->second > kRecorderLag) behind = true;
      }
      if (!behind) return;
      if (Clock::now() > deadline) {
        recorder_stuck_ = true;
        std::fprintf(stderr, "hadald: warning: --record: the recorder has not kept up for 10 s; the run goes on "
                             "without waiting for it\n");
        return;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
  }

  void step_once() {
    for (const auto& command : dds_.take_commands()) {
      const std::string reason = apply_command(command);
      if (!reason.empty()) reject(dds::command_target(model_, command) + ": " + reason);
    }
    sim_.step();
    const SimState& state = sim_.state();
    for (std::size_t i = 0; i < state.vehicles.size(); ++i) {
      const Eigen::Vector3d p = state.vehicles[i].body.X_WB.translation();
      distance_[i] += (p - previous_positions_[i]).norm();
      previous_positions_[i] = p;
      if (state.vehicles[i].fault_resets != reported_resets_[i]) {
        reported_resets_[i] = state.vehicles[i].fault_resets;
        std::fprintf(stderr, "hadald: %s: non-finite state at t = %.3f s, vehicle reset to its initial pose\n",
                     model_.vehicles[i].name.c_str(), state.time);
      }
    }
    publish_due();
    keep_recorder_up();
  }

  void publish_due() {
    const SimState& state = sim_.state();
    if (clock_divider_.due(state.time)) dds_.publish_clock(state.time);
    if (dds_.acoustic_links_due()) dds_.publish_acoustic_links(state.time, sim_.acoustic_links());
    for (std::size_t c = 0; c < cable_dividers_.size(); ++c) {
      if (cable_dividers_[c].due(state.time)) dds_.publish_cable(static_cast<int>(c), state);  // and its winch's
    }
    for (std::size_t i = 0; i < model_.vehicles.size(); ++i) {
      if (odometry_dividers_[i].due(state.time)) {
        dds_.publish_odometry(static_cast<int>(i), state);
        dds_.publish_joint_states(static_cast<int>(i), state);
        dds_.publish_sea_state(static_cast<int>(i), state, sim_.ocean());
      }
      if (actuator_state_dividers_[i].due(state.time)) {
        dds_.publish_actuator_states(static_cast<int>(i), state);
      }
      // Sensors sample inside the simulation at their own rates; publish each new sample once.
      const std::vector<SensorState>& sensors = state.vehicles[i].sensors;
      for (std::size_t k = 0; k < sensors.size(); ++k) {
        if (sensors[k].samples != published_samples_[i][k]) {
          published_samples_[i][k] = sensors[k].samples;
          dds_.publish_sensor(static_cast<int>(i), static_cast<int>(k), state);
        }
      }
    }
  }

  void reject(const std::string& reason) {
    ++rejected_;
    last_error_ = reason;
    // At most one line per wall second, so a misbehaving client cannot flood the log.
    const double now = seconds_since(start_wall_);
    if (now - last_reject_print_ >= 1.0 || rejected_ == 1) {
      std::fprintf(stderr, "hadald: rejected command: %s\n", reason.c_str());
      last_reject_print_ = now;
    }
  }

  void service_wall_clock() {
    const Clock::time_point now = Clock::now();
    const double status_period = 1.0 / model_.world.status_rate_hz;
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(status_period));
    if (now >= last_status_wall_ + period) {
      publish_status();
      // Absolute schedule (k periods after start), so the heartbeat keeps its rate; after a stall it
      // resumes from now instead of bursting.
      last_status_wall_ += period;
      if (now >= last_status_wall_ + period) last_status_wall_ = now;
      for (const auto& warning : dds_.take_warnings()) std::fprintf(stderr, "hadald: warning: %s\n", warning.c_str());
      // Writers whose samples are never seen (an unknown vehicle, a wrong type, best effort): refusals too.
      for (const auto& report : dds_.take_reports()) {
        std::fprintf(stderr, "hadald: %s\n", report.c_str());
        ++rejected_;
        last_error_ = report;
      }
      if (options_.mode != RunMode::kLockstep) refuse_step_requests();
      // Samples no reader could decode (dds/guarded_type.h): dropped by DDS, counted and said here.
      const std::uint64_t undecodable = dds::undecodable_samples().load();
      if (undecodable != reported_undecodable_) {
        const std::string report = std::to_string(undecodable - reported_undecodable_) +
                                   " undecodable sample(s) dropped (malformed, or sequences longer than the sample)";
        std::fprintf(stderr, "hadald: %s\n", report.c_str());
        rejected_ += undecodable - reported_undecodable_;
        last_error_ = report;
        reported_undecodable_ = undecodable;
      }
      const std::uint64_t superseded = dds_.superseded_commands();
      if (superseded != reported_superseded_) {
        std::fprintf(stderr, "hadald: %llu queued command(s) replaced by newer ones before a step took them "
                     "(more than %zu waiting)\n", static_cast<unsigned long long>(superseded - reported_superseded_),
                     dds::ServerEndpoints::kMaxQueuedCommands);
        reported_superseded_ = superseded;
      }
    }
    dds_.publish_monitor(sim_.time());
    if (options_.status_line && options_.mode != RunMode::kLockstep &&
        std::chrono::duration<double>(now - last_line_wall_).count() >= 1.0) {
      const double wall = std::chrono::duration<double>(now - last_line_wall_).count();
      const double steps = static_cast<double>(sim_.state().step_count - last_line_steps_);
      if (last_line_wall_ != Clock::time_point{}) {
        // The status's figure (RtfWindow), so that the line and rt/hadal/status (the viewer) agree.
        std::fprintf(stderr, "hadald: sim %.3f s  RTF %.2f  %.0f steps/s\n", sim_.time(), rtf_.rtf(), steps / wall);
      }
      last_line_wall_ = now;
      last_line_steps_ = sim_.state().step_count;
    }
  }

  // Outside lockstep nothing waits for step requests: each is refused at once with the reason, instead of
  // leaving its sender waiting for a reply that never comes.
  void refuse_step_requests() {
    for (const auto& request : dds_.take_step_requests()) {
      const std::string reason = request.error.empty() ? std::string("hadald runs in ") + to_string(options_.mode) +
                                                             " mode; step and reset requests need --mode lockstep"
                                                       : request.error;
      reject("step request " + std::to_string(request.request_id) + ": " + reason);
      dds_.publish_step_reply(request.request_id, false, reason, sim_.state(), request.unknown_vehicle);
    }
  }

  void publish_status() {
    dds::StatusReport report;
    report.sim_time = sim_.time();
    report.wall_time = seconds_since(start_wall_);
    // On the steady clock itself, not since start_wall_: that restarts after the discovery wait.
    rtf_.add(std::chrono::duration<double>(Clock::now().time_since_epoch()).count(), sim_.time());
    report.real_time_factor = rtf_.rtf();
    report.step_count = sim_.state().step_count;
    report.step_size = model_.world.step_size();
    report.mode = mode_code(options_.mode);
    for (const auto& v : sim_.state().vehicles) report.vehicle_faults.push_back(v.faults);
    report.rejected_commands = rejected_;
    report.last_error = last_error_;
    report.dropped_captures = sim_.dropped_captures();
    dds_.publish_status(report);
  }

  // One ray straight down from each vehicle's origin, through its own hull, against the last snapshot
  // (the simulation's ray-cast workers over the one world scene, exercised end to end); where it finds
  // nothing, one straight up: an origin sunk into the seabed (soil contact) is below its surface.
  std::vector<double> altitudes() {
    const auto cast = [&](float direction_z) {
      geometry::RayBatch batch;
      batch.set_snapshot(sim_.state(), sim_.ray_body_poses(sim_.state()));
      const auto& vehicles = sim_.state().vehicles;
      for (std::size_t i = 0; i < vehicles.size(); ++i) {
        batch.add_ray(vehicles[i].body.X_WB.translation().cast<float>(), Eigen::Vector3f(0.0f, 0.0f, direction_z),
                      0.0f, std::numeric_limits<float>::infinity(), static_cast<std::int32_t>(i));
      }
      return sim_.raycast_service().submit(std::move(batch)).get();
    };
    const geometry::RayHits down = cast(-1.0f);
    std::vector<double> altitude(down.distance.begin(), down.distance.end());
    if (std::any_of(altitude.begin(), altitude.end(), [](double a) { return !std::isfinite(a); })) {
      const geometry::RayHits up = cast(1.0f);
      for (std::size_t i = 0; i < altitude.size(); ++i) {
        if (!std::isfinite(altitude[i]) && std::isfinite(up.distance[i]) && up.body[i] == geometry::kStaticBody) {
          altitude[i] = -static_cast<double>(up.distance[i]);
        }
      }
    }
    return altitude;
  }

  RunSummary summary() {
    RunSummary s;
    const std::vector<double> altitude = altitudes();
    s.sim_time = sim_.time();
    s.wall_time = seconds_since(start_wall_);
    s.steps = sim_.state().step_count;
    s.resets = resets_;
    s.rejected_commands = rejected_;
    s.dropped_captures = sim_.dropped_captures();
    s.skipped_captures = sim_.skipped_captures();
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) == 0) s.peak_memory_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
    for (std::size_t i = 0; i < model_.vehicles.size(); ++i) {
      const Eigen::Vector3d p = sim_.state().vehicles[i].body.X_WB.translation();
      s.vehicles.push_back({model_.vehicles[i].name, distance_[i], (p - start_positions_[i]).norm(), altitude[i],
                            model_.vehicles[i].is_static});
    }
    for (const auto& count : dds_.published_counts()) s.samples_published.emplace_back(count.topic, count.samples);
    return s;
  }

  using InboundCommandRef = const dds::InboundCommand&;

  std::unique_ptr<record::BagRecorder> recorder_;  // --record
  bool recorder_stuck_ = false;  // keep_recorder_up gave up waiting
  const Model& model_;
  const CliOptions& options_;
  const std::atomic<bool>& stop_;
  Simulation sim_;
  dds::ServerEndpoints dds_;
  RateDivider clock_divider_;
  std::vector<RateDivider> odometry_dividers_, actuator_state_dividers_;
  std::vector<RateDivider> cable_dividers_;  // per cable (its rate_hz)
  // The sender and source stamp of the last joint command applied, per (vehicle, joint controller).
  std::map<std::pair<int, std::string>, std::pair<dds::SourceId, std::int64_t>> last_joint_command_;
  std::vector<std::vector<std::uint64_t>> published_samples_;  // per vehicle and sensor
  std::vector<std::int64_t> last_command_stamp_;
  std::vector<dds::SourceId> last_command_source_;  // who sent the command applied last, per vehicle
  std::uint64_t reported_superseded_ = 0, reported_undecodable_ = 0;
  std::vector<double> distance_;
  std::vector<std::uint64_t> reported_resets_;
  std::vector<Eigen::Vector3d> start_positions_, previous_positions_;
  Clock::time_point start_wall_, last_status_wall_, last_line_wall_{};
  double last_reject_print_ = 0.0;
  RtfWindow rtf_;  // the reported real-time factor
  std::uint64_t last_line_steps_ = 0, rejected_ = 0, resets_ = 0;
  std::string last_error_;
};

}  // namespace

std::string RunSummary::format() const {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << "hadald summary\n";
  out << "  sim time " << sim_time << " s in " << wall_time << " s wall, RTF "
      << (wall_time > 0.0 ? sim_time / wall_time : 0.0) << ", " << steps << " steps\n";
  for (const auto& v : vehicles) {
    if (v.is_static) {
      out << "  " << v.name << ": static, ";  // it never moves: no distance to report
    } else {
      out << "  " << v.name << ": distance travelled " << v.distance_travelled << " m (net displacement "
          << v.net_displacement << " m), ";
    }
    if (std::isfinite(v.altitude) && v.altitude < 0.0) {
      out << "altitude " << v.altitude << " m (its origin below the seabed's surface)\n";
    } else if (std::isfinite(v.altitude)) {
      out << "altitude " << v.altitude << " m\n";
    } else {
      out << "no seabed below\n";
    }
  }
  out << "  samples published:\n";
  for (const auto& [topic, count] : samples_published) out << "    " << topic << " " << count << "\n";
  if (resets > 0) out << "  resets: " << resets << " (sim time, steps and distances since the last)\n";
  out << "  rejected commands: " << rejected_commands << "\n";
  out << "  late captures dropped: " << dropped_captures << " (" << skipped_captures
      << " before a worker started them)\n";
  out << "  peak memory: " << peak_memory_mb << " MiB\n";
  return out.str();
}

void RtfWindow::add(double wall_s, double sim_s) {
  samples_.emplace_back(wall_s, sim_s);
  // Keep the newest sample at least kWindow_s older than the newest, and none older.
  while (samples_.size() > 2 && wall_s - samples_[1].first >= kWindow_s) samples_.pop_front();
}

double RtfWindow::rtf() const {
  if (samples_.size() < 2) return 0.0;
  const double wall = samples_.back().first - samples_.front().first;
  return wall > 0.0 ? (samples_.back().second - samples_.front().second) / wall : 0.0;
}

std::vector<std::string> mode_warnings(const Model& model, RunMode mode) {
  std::vector<std::string> warnings;
  if (mode != RunMode::kRealtime) return warnings;
  for (const VehicleSpec& vehicle : model.vehicles) {
    for (const SensorSpec& sensor : vehicle.sensors) {
      if (!sensor.captured() || sensor.latency_steps(model.world.physics_rate_hz) > 0) continue;
      std::ostringstream line;
      line << vehicle.name << "/" << sensor.name << ": latency_s " << sensor.latency_s
           << " s is less than one physics step: in real time its captures are due before a ray-cast worker can "
              "make them and none is published (leave latency_s out for one sample period, "
           << 1.0 / sensor.rate_hz << " s)";
      warnings.push_back(line.str());
    }
  }
  return warnings;
}

RunSummary run_server(const Model& model, const CliOptions& options, const std::atomic<bool>& stop) {
  Runner runner(model, options, stop);
  return runner.run();
}

}  // namespace hadal::app
