#include "hadal/render/camera_presets.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hadal::render {

const config::Presets<LensSpec>& camera_presets() {
  static const config::Presets<LensSpec> presets = {
      {.id = "svin2_stereo_rig_v2_left",
       .product = "SVIn2 stereo rig v2, left camera: the Autonomous Field Robotics Lab's diver-held sensor suite "
                  "(underwater caves)",
       .source = "github.com/AutonomousFieldRoboticsLab/SVIn config/config_stereorig_v2.yaml @1bb181b5, cameras[0] "
                 "(radialtangential: k1, k2, p1, p2); Rahman, Li and Rekleitis, SVIn2, IROS 2019",
       .figures = {.width_px = 1600,
                   .height_px = 1200,
                   .fx = 1156.5188534683703,
                   .fy = 1156.5772666173266,
                   .cx = 763.2083316463371,
                   .cy = 617.2779853849335,
                   .model = LensModel::kRadialTangential,
                   .distortion = {-0.17473019446863114, 0.10643290428040156, 0.005210777878907861,
                                  -0.00028664918860079295, 0.0}}},
      {.id = "subpipe_gopro_hero10",
       .product = "SubPipe Cam0: a GoPro Hero 10 on an OceanScan-MST LAUV inspecting a submarine outfall pipeline",
       .source = "github.com/remaro-network/SubPipe-dataset README.md, 1.3 Camera parameters (@c5dc7d9b; resolution "
                 "given as height x width 1520x2704); Alvarez-Tunon et al., SubPipe, arXiv:2401.17907 (2024)",
       .figures = {.width_px = 2704,
                   .height_px = 1520,
                   .fx = 1612.36,
                   .fy = 1622.56,
                   .cx = 1365.43,
                   .cy = 741.27,
                   .model = LensModel::kRadialTangential,
                   .distortion = {-0.247, 0.0869, -0.006, 0.001, 0.0}}},
  };
  return presets;
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
