// hadald: the Hadal simulation server. See cli.h for the command line and docs/topics.md for the topics.
#include "cli.h"
#include "hadal/dds/participant.h"
#include "hadal/core/allocator.h"
#include "hadal/core/simulation.h"
#include "hadal/config/json_schema.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/config/security_block.h"
#include "hadal/record/rosbag2_writer.h"
#include "hadal/sensors/sensor_kinds.h"
#include "scheduling.h"
#include "server_loop.h"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <variant>
#include <vector>

namespace {

std::atomic<bool> g_stop{false};

extern "C" void handle_stop_signal(int) { g_stop.store(true); }

void install_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = handle_stop_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// One line per vehicle for the start-up log: name, type, links, actuators and sensors by kind.
std::string describe(const hadal::VehicleSpec& vehicle) {
  std::string text = "vehicle " + vehicle.name + " (" + hadal::to_string(vehicle.type) + "): " +
                     std::to_string(vehicle.links.size()) + " link(s), actuators [";
  const char* separator = "";
  for (const auto& actuator : vehicle.actuators) {
    text += separator + actuator.name + ": " + std::string(actuator.type());
    separator = ", ";
  }
  text += "], sensors [";
  separator = "";
  for (const auto& sensor : vehicle.sensors) {
    text += separator + sensor.name + ": " + std::string(sensor.type());
    separator = ", ";
  }
  return text + "]";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hadal;
  hadal::keep_frame_buffers_mapped();  // core/allocator.h
  const std::vector<std::string> args(argv + 1, argv + argc);
  const app::CliParse cli = app::parse_cli(args, std::getenv("ROS_DOMAIN_ID"));
  if (cli.options.help) {
    std::fputs(app::usage().c_str(), stdout);
    return 0;
  }
  if (!cli.error.empty()) {
    std::fprintf(stderr, "hadald: error: %s\n%s", cli.error.c_str(), app::usage().c_str());
    return 2;
  }
  if (!cli.options.schema.empty()) {
    std::fputs(config::scenario_json_schema(cli.options.schema)->c_str(), stdout);
    return 0;
  }
  if (const std::string why = record::Rosbag2Writer::existing_directory_error(cli.options.record_dir); !why.empty()) {
    std::fprintf(stderr, "hadald: error: --record: %s\n", why.c_str());
    return 2;
  }
  // Before any thread exists, so that all of hadald's threads inherit the CPUs and the policy.
  if (const std::string why = app::apply_scheduling(cli.options.cpus, cli.options.sched_batch, true); !why.empty()) {
    std::fprintf(stderr, "hadald: error: %s\n", why.c_str());
    return 2;
  }

  config::LoadOptions load_options;
  load_options.asset_roots = cli.options.asset_roots;
  load_options.overrides = cli.options.overrides;
  config::LoadResult loaded = config::load_scenario_file(cli.options.scenario_file, load_options);
  for (const auto& warning : loaded.warnings) std::fprintf(stderr, "%s\n", warning.format().c_str());
  if (!loaded.ok()) {
    for (const auto& error : loaded.errors) std::fprintf(stderr, "%s\n", error.format().c_str());
    std::fprintf(stderr, "hadald: %zu error(s) in the scenario; nothing started\n", loaded.errors.size());
    return 1;
  }
  if (cli.options.check) {
    std::printf("hadald: %s: ok (%zu vehicle(s), %zu override(s))\n", cli.options.scenario_file.c_str(),
                loaded.model->vehicles.size(), cli.options.overrides.size());
    return 0;
  }
  Model model = std::move(*loaded.model);
  if (!cli.options.security_file.empty()) {
    try {
      model.security = config::load_security_file(cli.options.security_file);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\nhadald: error in --security %s; nothing started\n", e.what(),
                   cli.options.security_file.c_str());
      return 1;
    }
  }
  if (cli.options.seed) model.world.seed = *cli.options.seed;
  if (cli.options.threads) model.world.threads = *cli.options.threads;
  if (cli.options.ray_kernels) model.world.ray_kernels = *cli.options.ray_kernels;
  if (!cli.options.cameras) hadal::remove_cameras(model);

  install_signal_handlers();
  std::fprintf(stderr,
               "hadald: %s, %zu vehicle(s), %.0f Hz physics, mode %s, DDS domain %d, %d thread(s) on CPU(s) %s%s%s\n",
               cli.options.scenario_file.c_str(), model.vehicles.size(), model.world.physics_rate_hz,
               app::to_string(cli.options.mode), cli.options.domain_id, model.world.effective_threads(),
               app::format_cpu_list(app::allowed_cpus()).c_str(), cli.options.sched_batch ? ", SCHED_BATCH" : "",
               model.world.ray_kernels == geometry::RayKernels::kPortable ? ", portable ray kernels" : "");
  if (model.security.enabled()) {
    std::fprintf(stderr, "hadald: DDS Security on: identity %s, permissions %s\n", model.security.certificate.c_str(),
                 model.security.permissions.c_str());
  }
  for (const auto& vehicle : model.vehicles) std::fprintf(stderr, "hadald: %s\n", describe(vehicle).c_str());
  for (const std::string& warning : app::mode_warnings(model, cli.options.mode)) {
    std::fprintf(stderr, "hadald: warning: %s\n", warning.c_str());
  }
  try {
    // Shared memory that killed DDS processes (a hadald or client ended by kill -9) left behind is RAM
    // held for nothing; a server start gives it back.
    if (hadal::dds::shared_memory_from_environment()) {
      const hadal::dds::StaleSharedMemory stale = hadal::dds::clean_stale_shared_memory();
      if (stale.segments > 0) {
        std::fprintf(stderr,
                     "hadald: removed %d stale shared-memory segment(s) of DDS processes that are gone (%.1f MB)\n",
                     stale.segments, static_cast<double>(stale.bytes) / 1e6);
      }
    }
    const app::RunSummary summary = app::run_server(model, cli.options, g_stop);
    std::fputs(summary.format().c_str(), stdout);
    std::fflush(stdout);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hadald: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
