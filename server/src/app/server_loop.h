// The hadald run loop: fixed-step simulation driven in realtime, fast or lockstep mode, with the DDS
// endpoints serviced at step boundaries.
//
// Realtime mode sleeps to an absolute schedule (step k starts at wall t0 + k dt / rtf), so the
// real-time factor does not drift over long runs; when a step overruns, later steps run back to back
// until the schedule is caught up. Fast mode never sleeps. Lockstep mode steps only when a
// rt/hadal/step_request arrives, runs exactly the requested number of steps and then replies; a reset
// request first starts the run over at sim time 0 (Simulation::reset), so an episode needs no restart.
// Publication rates (clock, odometry, thruster state) are in sim time; the status heartbeat is in
// wall time (so an idle lockstep server is still discoverable).
#pragma once

#include "cli.h"
#include "hadal/core/model.h"

#include <atomic>
#include <cstdint>
#include <deque>
#include <utility>
#include <string>
#include <vector>

namespace hadal::app {

struct VehicleSummary {
  std::string name;
  // Since the start, or since the last lockstep reset (from the pose it set).
  double distance_travelled = 0.0;  // path length of B's origin [m]
  double net_displacement = 0.0;    // |p_end - p_start| [m]
  // Range straight down (-z) to the seabed at the end, ray-cast; negative: B's origin is that far below the
  // seabed's surface (a crawler's tracks sunk into soil; the ray straight up finds it); inf: no seabed.
  double altitude = 0.0;
  bool is_static = false;  // VehicleSpec::is_static: it never moves, so no distances are said
};

struct RunSummary {
  double sim_time = 0.0;
  double wall_time = 0.0;
  std::uint64_t steps = 0;
  std::uint64_t resets = 0;  // lockstep reset requests served
  std::uint64_t rejected_commands = 0;
  std::uint64_t dropped_captures = 0;  // captures late in real time, never waited for
  std::uint64_t skipped_captures = 0;  // of those, the ones no worker had started (never rendered)
  double peak_memory_mb = 0.0;         // the process's peak resident set size [MiB]
  std::vector<VehicleSummary> vehicles;
  std::vector<std::pair<std::string, std::uint64_t>> samples_published;  // per topic

  std::string format() const;
};

// The real-time factor a run reports, on rt/hadal/status (so in hadal-viewer) and on its status line alike:
// sim seconds per wall second over the last kWindow_s of wall time. Over one 0.1 s status period alone, a
// real-time run catching up after a late step reads ~2 although its schedule keeps 1.00.
class RtfWindow {
 public:
  static constexpr double kWindow_s = 1.0;
  // A sample: wall and sim time [s] (wall times increasing).
  void add(double wall_s, double sim_s);
  // Sim seconds per wall second from the oldest kept sample to the newest; 0 before two samples.
  double rtf() const;
  // Forgets the samples (a lockstep reset starts sim time over).
  void clear() { samples_.clear(); }

 private:
  std::deque<std::pair<double, double>> samples_;  // (wall, sim), oldest first
};

// What a run in `mode` will not do as the scenario expects, one line each ("<vehicle>/<sensor>: ..."): in real
// time, a captured sensor whose latency_s rounds to 0 physics steps publishes nothing (every capture is due
// in its own step, before a worker can have made it; configs/REFERENCE.md, "Captured sensors").
std::vector<std::string> mode_warnings(const Model& model, RunMode mode);

// Runs until `stop` is set or the duration is reached. Throws std::runtime_error if DDS cannot start.
RunSummary run_server(const Model& model, const CliOptions& options, const std::atomic<bool>& stop);

}  // namespace hadal::app
