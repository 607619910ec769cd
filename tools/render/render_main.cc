// hadal-render: renders every camera of a scenario at a sim time to PNG files, without DDS, so that a
// scenario can be looked at in seconds (docs/ARCHITECTURE.md, "Cameras").
//   hadal-render SCENARIO.yaml [--time T] [--camera NAME] [--out DIR] [--threads N]
// The scenario runs (its schedules, physics and sensors, as hadald --mode fast would) from 0 to the
// physics step nearest T; then each camera renders the state there exactly as it renders a frame in the
// simulation (sensors/camera_sensor.h: the same lights, optics, lens and image sensor, noise keyed by
// the step), on the simulation's own ray-cast workers over its one world scene: N of them (default the
// scenario's world.raycast_threads; 0: one per hardware thread). Files in DIR (default .):
//   <vehicle>_<camera>.png        the image (rgb8 or mono8)
//   <vehicle>_<camera>_depth.png  depth along the optical axis, 16-bit millimetres (0: nothing hit;
//                                 depths beyond 65.535 m are written as 65535)
// and one JSON object per camera on stdout: {"vehicle", "camera", "time" [s], "image", "depth",
// "width", "height", "encoding", "mean_counts" (per channel), "hit_fraction"}.
// Sonars are not rendered here: hadal-validate-sonar draws them; hadal-render names it on stderr when the
// scenario has any.
// Exit status: 0 success; 1 the scenario does not load (file:line:col errors on stderr), has no camera
// (or none named NAME), or a file cannot be written; 2 usage error.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hadal/core/allocator.h"
#include "hadal/config/scenario_loader.h"
#include "hadal/core/simulation.h"
#include "hadal/geometry/raycast_service.h"
#include "hadal/sensors/camera_sensor.h"
#include "cli_args.h"
#include "json_number.h"
#include "parse_number.h"

namespace {

using hadal::tools::json_number;
using hadal::tools::parse_number;

constexpr const char* kUsage =
    "usage: hadal-render SCENARIO.yaml [--time T] [--camera NAME] [--out DIR] [--threads N]\n"
    "  --time T     simulation time [s] to render at (default 0); the scenario runs up to it\n"
    "  --camera N   only the camera named N (or VEHICLE/N); default every camera\n"
    "  --out DIR    directory for the PNG files (default .; created if missing)\n"
    "  --threads N  ray-cast worker threads (default world.raycast_threads; 0: one per hardware thread)\n"
    "Writes <vehicle>_<camera>.png and <vehicle>_<camera>_depth.png (16-bit mm) per camera and\n"
    "prints one JSON object per camera. Sonars: hadal-validate-sonar --scenario SCENARIO.yaml --out DIR\n"
    "draws a forward-looking fan, a multibeam swath and a side-scan waterfall.\n";

struct CameraRef {
  std::size_t vehicle = 0;
  std::size_t sensor = 0;
};

}  // namespace

int main(int argc, char** argv) {
  using namespace hadal;
  hadal::keep_frame_buffers_mapped();  // core/allocator.h
  std::string scenario, only, out_dir = ".";
  double time = 0.0, threads = 0.0;
  bool threads_given = false;
  tools::CommandLine command_line("hadal-render", kUsage);
  command_line.unknown_words("unknown option %s")
      .number("--time", &time, tools::NumberRange::at_least(0.0))
      .text("--camera", &only)
      .text("--out", &out_dir)
      .option("--threads",
              [&](const std::string& value) -> std::string {
                if (!parse_number(value, &threads) || threads < 0.0 || threads > 256.0 ||
                    threads != std::floor(threads)) {
                  return "--threads must be a whole number in [0, 256] (got '" + value + "')";
                }
                threads_given = true;
                return "";
              })
      .one_positional(&scenario, "one scenario only (got '%s' and '%s')");
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (scenario.empty()) return command_line.usage_error("no scenario given");

  config::LoadResult loaded = config::load_scenario_file(scenario);
  if (!loaded.model) {
    for (const auto& error : loaded.errors) std::fprintf(stderr, "%s\n", error.format().c_str());
    return 1;
  }
  Model model = std::move(*loaded.model);
  if (threads_given) model.world.raycast_threads = static_cast<int>(threads);
  std::vector<CameraRef> cameras;
  std::string sonars;  // "auv/fls (fls), ..."
  std::vector<std::string> names;
  for (std::size_t i = 0; i < model.vehicles.size(); ++i) {
    for (std::size_t k = 0; k < model.vehicles[i].sensors.size(); ++k) {
      const SensorSpec& sensor = model.vehicles[i].sensors[k];
      const std::string full = model.vehicles[i].name + "/" + sensor.name;
      if (sensor.type() == "fls" || sensor.type() == "multibeam" || sensor.type() == "sidescan") {
        sonars += (sonars.empty() ? "" : ", ") + full + " (" + std::string(sensor.type()) + ")";
      }
      if (sensor.type() != sensors::CameraSensor::kType) continue;
      names.push_back(full);
      if (only.empty() || only == sensor.name || only == full) cameras.push_back({i, k});
    }
  }
  // Sonar images are drawn by another tool: said whenever the scenario has sonars, so that "look at what my
  // sensors see" finds its command for every imaging sensor.
  const std::string sonar_hint = sonars.empty() ? std::string()
                                                : "sonars " + sonars + " are drawn by hadal-validate-sonar --scenario " +
                                                      scenario + " --out DIR (forward-looking fan, multibeam swath, "
                                                      "side-scan waterfall)";
  if (!sonar_hint.empty()) std::fprintf(stderr, "hadal-render: %s\n", sonar_hint.c_str());
  if (cameras.empty()) {
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
    std::fprintf(stderr, "hadal-render: %s: %s\n", scenario.c_str(),
                 names.empty() ? "the scenario has no camera (a sensor of type: camera)"
                               : ("no camera named '" + only + "' (cameras: " + list + ")").c_str());
    return 1;
  }
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) {
    std::fprintf(stderr, "hadal-render: cannot create %s: %s\n", out_dir.c_str(), error.message().c_str());
    return 1;
  }

  Simulation sim(model);
  const auto steps = static_cast<std::uint64_t>(std::llround(time * model.world.physics_rate_hz));
  while (sim.state().step_count < steps) sim.step();

  for (const CameraRef& ref : cameras) {
    const VehicleSpec& vehicle = model.vehicles[ref.vehicle];
    const SensorSpec& sensor = vehicle.sensors[ref.sensor];
    const auto& spec = spec_of<sensors::CameraSensor>(sensor);
    const auto& state = std::get<sensors::CameraSensor::State>(sim.state().vehicles[ref.vehicle].sensors[ref.sensor].kind);
    // The ray bodies' poses, and the camera's mounting where its link is now (a wrist camera's moves).
    const Simulation::CaptureMount mount =
        sim.capture_mount(static_cast<int>(ref.vehicle), static_cast<int>(ref.sensor));
    const auto v = static_cast<int>(ref.vehicle);
    const sensors::CaptureContext context{sim.time(), sim.state().step_count, mount.X_Wb, v,
                                          mount.X_BS, &sim.model(),           &sim.ocean(), mount.ray_body};
    sensors::CameraSensor::Capture frame;
    sim.raycast_service().submit(mount.X_Wb, sensors::CameraSensor::capture(context, spec, state, frame)).get();

    const int width = spec.lens->width_px(), height = spec.lens->height_px();
    const int channels = spec.mono ? 1 : 3;
    cv::Mat image(height, width, spec.mono ? CV_8UC1 : CV_8UC3, frame.image.data());
    cv::Mat bgr;
    if (spec.mono) {
      bgr = image;
    } else {
      cv::cvtColor(image, bgr, cv::COLOR_RGB2BGR);
    }
    cv::Mat depth_mm(height, width, CV_16UC1);
    std::size_t hits = 0;
    for (int v = 0; v < height; ++v) {
      for (int u = 0; u < width; ++u) {
        const float z = frame.depth_m[static_cast<std::size_t>(v) * width + u];
        hits += std::isfinite(z);
        depth_mm.at<std::uint16_t>(v, u) =
            std::isfinite(z) ? static_cast<std::uint16_t>(std::clamp(std::lround(z * 1000.0), 1L, 65535L)) : 0;
      }
    }
    const std::string base = out_dir + "/" + vehicle.name + "_" + sensor.name;
    const std::string image_file = base + ".png", depth_file = base + "_depth.png";
    bool written = false;
    try {
      written = cv::imwrite(image_file, bgr) && cv::imwrite(depth_file, depth_mm);
    } catch (const cv::Exception& e) {
      std::fprintf(stderr, "hadal-render: %s\n", e.what());
    }
    if (!written) {
      std::fprintf(stderr, "hadal-render: cannot write %s\n", image_file.c_str());
      return 1;
    }
    std::vector<double> mean(static_cast<std::size_t>(channels), 0.0);
    for (std::size_t i = 0; i < frame.image.size(); ++i) mean[i % static_cast<std::size_t>(channels)] += frame.image[i];
    std::string means;
    for (double& m : mean) {
      m /= static_cast<double>(static_cast<std::size_t>(width) * height);
      means += (means.empty() ? "" : ", ") + json_number(m);
    }
    std::printf("{\"vehicle\": \"%s\", \"camera\": \"%s\", \"time\": %s, \"image\": \"%s\", \"depth\": \"%s\", "
                "\"width\": %d, \"height\": %d, \"encoding\": \"%s\", \"mean_counts\": [%s], \"hit_fraction\": %s}\n",
                vehicle.name.c_str(), sensor.name.c_str(), json_number(sim.time()).c_str(), image_file.c_str(),
                depth_file.c_str(), width, height, spec.mono ? "mono8" : "rgb8", means.c_str(),
                json_number(static_cast<double>(hits) / (static_cast<double>(width) * height)).c_str());
  }
  return 0;
}
