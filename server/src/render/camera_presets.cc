#include "hadal/render/camera_presets.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hadal::render {
namespace {

LensSpec calibration(int width, int height, double fx, double fy, double cx, double cy, LensModel model,
                     std::array<double, 5> distortion) {
  LensSpec lens;
  lens.width_px = width;
  lens.height_px = height;
  lens.fx = fx;
  lens.fy = fy;
  lens.cx = cx;
  lens.cy = cy;
  lens.model = model;
  lens.distortion = distortion;
  return lens;
}

std::vector<CameraPreset> make_presets() {
  std::vector<CameraPreset> presets;
  // SVIn2 "stereo rig v2", left camera: the diver-held sensor suite of the Autonomous Field Robotics
  // Lab used in underwater caves. Source: github.com/AutonomousFieldRoboticsLab/SVIn,
  // config/config_stereorig_v2.yaml (commit 1bb181b5), cameras[0]: image_dimension [1600, 1200],
  // distortion_coefficients [-0.17473019446863114, 0.10643290428040156, 0.005210777878907861,
  // -0.00028664918860079295] (radialtangential: k1, k2, p1, p2), focal_length [1156.5188534683703,
  // 1156.5772666173266], principal_point [763.2083316463371, 617.2779853849335].
  // Rahman, Li and Rekleitis, "SVIn2: An Underwater SLAM System using Sonar, Visual, Inertial, and
  // Depth Sensor", IROS 2019.
  presets.push_back({"svin2_stereo_rig_v2_left", "SVIn2 stereo rig v2, left camera (underwater caves)",
                     calibration(1600, 1200, 1156.5188534683703, 1156.5772666173266, 763.2083316463371,
                                 617.2779853849335, LensModel::kRadialTangential,
                                 {-0.17473019446863114, 0.10643290428040156, 0.005210777878907861,
                                  -0.00028664918860079295, 0.0})});
  // SubPipe Cam0: GoPro Hero 10 on an OceanScan-MST LAUV inspecting a submarine outfall pipeline.
  // Source: github.com/remaro-network/SubPipe-dataset, README.md, "1.3 Camera parameters" (added in
  // commit c5dc7d9b): Resolution 1520x2704 (height x width), fx = 1612.36, fy = 1622.56,
  // cx = 1365.43, cy = 741.27, k1 = -0.247, k2 = 0.0869, p1 = -0.006, p2 = 0.001.
  // Álvarez-Tuñón et al., "SubPipe: A Submarine Pipeline Inspection Dataset for Segmentation and
  // Visual-inertial Localization", arXiv:2401.17907 (2024).
  presets.push_back({"subpipe_gopro_hero10", "SubPipe Cam0, GoPro Hero 10 on an LAUV",
                     calibration(2704, 1520, 1612.36, 1622.56, 1365.43, 741.27, LensModel::kRadialTangential,
                                 {-0.247, 0.0869, -0.006, 0.001, 0.0})});
  return presets;
}

}  // namespace

const std::vector<CameraPreset>& camera_presets() {
  static const std::vector<CameraPreset> presets = make_presets();
  return presets;
}

std::optional<LensSpec> camera_preset(std::string_view name) {
  for (const CameraPreset& preset : camera_presets()) {
    if (preset.name == name) return preset.lens;
  }
  return std::nullopt;
}

LensSpec downscaled(const LensSpec& lens, double s) {
  if (!(s >= 1.0) || !std::isfinite(s)) throw std::invalid_argument("downscale must be a number >= 1");
  const double width = lens.width_px / s, height = lens.height_px / s;
  if (std::abs(width - std::round(width)) > 1e-9 || std::abs(height - std::round(height)) > 1e-9) {
    std::ostringstream factor;
    factor << s;
    throw std::invalid_argument("downscale " + factor.str() + " does not divide the " +
                                std::to_string(lens.width_px) + " x " + std::to_string(lens.height_px) +
                                " image into whole pixels");
  }
  LensSpec out = lens;
  out.width_px = static_cast<int>(std::lround(width));
  out.height_px = static_cast<int>(std::lround(height));
  out.fx = lens.fx / s;
  out.fy = lens.fy / s;
  out.cx = (lens.cx + 0.5) / s - 0.5;
  out.cy = (lens.cy + 0.5) / s - 0.5;
  return out;
}

}  // namespace hadal::render
