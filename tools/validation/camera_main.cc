// hadal-validate-camera: the paper's camera figure, rendered by Hadal's own image formation
// (docs/ARCHITECTURE.md, "Cameras"): one scene — a checkerboard target standing on the seabed 2.2 m in
// front of a camera 1.5 m above the sediment, pitched 10 deg down — in six panels, one PNG:
//   1 pinhole             2 barrel (k1 -0.15)     3 pincushion (k1 +0.2)     (clear water, lights, 2000 m)
//   4 shallow: daylight only, Jerlov II, 15 m     5 deep sea: lights only, 2000 m, b = 0.05 /m
//   6 deep sea: lights only, 2000 m, b = 0.4 /m (turbid: backscatter veils the scene)
// Each panel is a frame of the camera sensor kind (sensors/camera_sensor.h) on the ray-cast workers,
// noise seeded; the JSON summary gives every panel's mean counts (R, G, B) and the mean of a patch left
// of the target (columns 0-59, rows 40-139) that looks into open water only: the backscatter (zero-ish
// in clear water, growing with b).
//   hadal-validate-camera [--out DIR]     (default validation_out/camera)
// Writes DIR/camera_figure.png; prints one JSON object. Exit 0, or 1 when DIR cannot be written, 2 on
// a usage error.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "hadal/geometry/raycast_service.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/render/water_presets.h"
#include "hadal/sensors/camera_sensor.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using validation::json_rounded;

constexpr const char* kTool = "hadal-validate-camera";
constexpr const char* kUsage =
    "usage: hadal-validate-camera [--out DIR]\n"
    "  --out DIR  output directory (default validation_out/camera)\n"
    "Renders the camera figure (six panels: lens models, shallow and deep water) to DIR/camera_figure.png\n"
    "and prints a JSON summary.\n";

struct Panel {
  std::string label;
  double k1 = 0.0;
  double depth_m = 2000.0;  // of the seabed
  double scattering_per_m = 0.01;
  bool lights = true;
  bool daylight = false;
};

Eigen::Isometry3d pose(const Eigen::Vector3d& p, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = p;
  return X;
}

Eigen::Matrix3d pitch(double rad) { return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitY()).toRotationMatrix(); }

// The scene of a panel: the rig (camera, two lights) and the target over a plane seabed.
Model panel_model(const Panel& panel) {
  Model model;
  const double z_seabed = -panel.depth_m;
  model.world.seed = 11;
  model.world.water.surface_z = 0.0;
  model.world.seabed.z = z_seabed;
  OpticsSpec& optics = model.world.optics;
  optics.water.absorption_per_m = render::pure_water_absorption_per_m() + 0.02;
  optics.water.scattering_per_m = render::Rgb::Constant(panel.scattering_per_m);
  optics.water.forward_scatter_max_angle_rad = 10.0 * kDegToRad;  // the scenario default (configs/REFERENCE.md)
  optics.daylight.surface_z_m = 0.0;
  optics.daylight.surface_irradiance_W_per_m2 = panel.daylight ? render::Rgb(150.0, 170.0, 160.0) : render::Rgb::Zero();
  optics.daylight.Kd_per_m = render::jerlov_Kd_per_m(render::JerlovType::kII);

  VehicleSpec rig;
  rig.name = "rig";
  LinkSpec frame;
  frame.name = "frame";
  frame.mass = 1.0;
  rig.links = {frame};
  rig.X_WB_initial = pose(Eigen::Vector3d(0.0, 0.0, z_seabed + 1.5));
  SensorSpec camera;
  camera.name = "camera";
  camera.X_LS = pose(Eigen::Vector3d::Zero(), pitch(10.0 * kDegToRad));
  sensors::CameraSensor::Spec spec;
  render::LensSpec lens = render::lens_from_horizontal_fov(480, 360, 70.0 * kDegToRad);
  if (panel.k1 != 0.0) {
    lens.model = render::LensModel::kRadialTangential;
    lens.distortion = {panel.k1, 0.0, 0.0, 0.0, 0.0};
  }
  sensors::CameraSensor::set_lens(spec, lens);
  spec.far_clip = 40.0;
  spec.sensor.exposure_s = 0.02;
  spec.sensor.gain_dn_per_e = 0.02;
  camera.kind = spec;
  rig.sensors = {camera};
  if (panel.lights) {
    for (double side : {0.5, -0.5}) {
      LightSpec light;
      light.name = side > 0 ? "port" : "starboard";
      light.X_LF = pose(Eigen::Vector3d(0.0, side, 0.2), pitch(20.0 * kDegToRad));
      light.inner_half_angle = 35.0 * kDegToRad;
      light.outer_half_angle = 45.0 * kDegToRad;
      light.intensity_W_per_sr = Eigen::Array3d::Constant(400.0);
      rig.lights.push_back(light);
    }
  }

  // Target: a 2.4 m x 1.8 m board standing on the sediment 2.2 m ahead, facing the camera (its z along
  // -x), its squares reaching towards the image's edges where distortion shows.
  VehicleSpec target;
  target.name = "target";
  LinkSpec board;
  board.name = "board";
  board.mass = 1.0;
  CollisionShape plate;
  plate.type = CollisionShapeType::kBox;
  plate.box_size = Eigen::Vector3d(2.4, 1.8, 0.02);
  board.collisions = {plate};
  board.appearance.albedo = Eigen::Array3d(0.8, 0.8, 0.8);
  CheckerboardSpec pattern;
  pattern.columns = 14;
  pattern.rows = 10;
  pattern.square_size = 0.15;
  pattern.X_LP = pose(Eigen::Vector3d(-1.05, -0.75, 0.0));
  board.appearance.checkerboard = pattern;
  target.links = {board};
  target.X_WB_initial = pose(Eigen::Vector3d(2.2, 0.0, z_seabed + 1.25), pitch(-90.0 * kDegToRad));
  model.vehicles = {rig, target};
  return model;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_dir = "validation_out/camera";
  validation::CommandLine command_line = validation::make_command_line(kTool, kUsage);
  command_line.text("--out", &out_dir);
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (const std::string error = validation::ensure_directory(out_dir); !error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }
  const std::vector<Panel> panels = {
      {"pinhole", 0.0, 2000.0, 0.01, true, false},
      {"barrel k1 -0.15", -0.15, 2000.0, 0.01, true, false},
      {"pincushion k1 +0.2", 0.2, 2000.0, 0.01, true, false},
      {"shallow 15 m, daylight, Jerlov II", 0.0, 15.0, 0.05, false, true},
      {"deep 2000 m, lights, b 0.05/m", 0.0, 2000.0, 0.05, true, false},
      {"deep 2000 m, lights, b 0.4/m", 0.0, 2000.0, 0.4, true, false}};
  std::vector<cv::Mat> tiles;
  std::string summary = "{\"figure\": \"" + validation::join_path(out_dir, "camera_figure.png") + "\", \"panels\": [";
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const Model model = panel_model(panels[p]);
    const auto& spec = spec_of<sensors::CameraSensor>(model.vehicles[0].sensors[0]);
    sensors::CameraSensor::State state;
    state.noise_key = sensors::channel_key(model.world.seed, "rig", "camera", "image");
    const std::vector<Eigen::Isometry3d> X_WB = {model.vehicles[0].X_WB_initial, model.vehicles[1].X_WB_initial};
    const Eigen::Isometry3d X_BS = model.vehicles[0].sensors[0].X_LS;
    const sensors::CaptureContext context{0.0, 0, X_WB, 0, X_BS, &model};
    sensors::CameraSensor::Capture frame;
    geometry::RaycastService service(geometry::build_world_scene(model));
    service.submit(X_WB, sensors::CameraSensor::capture(context, spec, state, frame)).get();
    const cv::Mat rgb(spec.lens->height_px(), spec.lens->width_px(), CV_8UC3, frame.image.data());
    cv::Mat bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    const cv::Scalar mean = cv::mean(rgb), water = cv::mean(rgb(cv::Rect(0, 40, 60, 100)));
    cv::putText(bgr, std::to_string(p + 1) + "  " + panels[p].label, cv::Point(10, 24), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    tiles.push_back(bgr);
    summary += std::string(p ? ", " : "") + "{\"panel\": \"" + panels[p].label + "\", \"mean_counts\": [" +
               json_rounded(mean[0]) + ", " + json_rounded(mean[1]) + ", " + json_rounded(mean[2]) +
               "], \"open_water_mean_counts\": [" + json_rounded(water[0]) + ", " + json_rounded(water[1]) + ", " +
               json_rounded(water[2]) + "]}";
  }
  cv::Mat row0, row1, figure;
  cv::hconcat(std::vector<cv::Mat>(tiles.begin(), tiles.begin() + 3), row0);
  cv::hconcat(std::vector<cv::Mat>(tiles.begin() + 3, tiles.end()), row1);
  cv::vconcat(row0, row1, figure);
  const std::string file = validation::join_path(out_dir, "camera_figure.png");
  if (!cv::imwrite(file, figure)) {
    std::fprintf(stderr, "%s: cannot write %s\n", kTool, file.c_str());
    return 1;
  }
  std::printf("%s]}\n", summary.c_str());
  return 0;
}
