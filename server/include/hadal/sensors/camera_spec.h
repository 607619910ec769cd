// The camera's spec (sensors/camera_sensor.h; keys: CameraSensor::keys()): its calibration as given, the lens made of it, the image sensor.
#pragma once

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/render/lens_model.h"

namespace hadal::sensors {

struct CameraSensor;

}  // namespace hadal::sensors

namespace hadal::render {
class Lens;
struct LensSpec;
class BackscatterTableCache;
}  // namespace hadal::render

namespace hadal::sensors {

struct ImageSensorSpec {
  Eigen::Array3d sensitivity = Eigen::Array3d::Constant(2.0e5);  // [e- / s / (W/(m^2 sr))] per channel
  double exposure_s = 0.01;
  double gain_dn_per_e = 0.05;  // counts per electron (analog gain)
  double full_well_e = 10000.0;
  double read_noise_e = 3.0;  // rms [electrons]
  bool shot_noise = true;
  bool vignetting = true;  // the cos^4 law
};

// The calibration as the file gives it: a preset's lens, or a field of view or fx, fy, cx, cy, a lens
// model and its distortion; then a downscale. The lens is made of it when the keys are read.
struct CameraCalibration {
  const render::LensSpec* preset = nullptr;  // one of render::camera_presets(); null: none
  int width_px = 640;
  int height_px = 480;
  double hfov = 90.0 * kDegToRad;  // [rad]; used without fx, fy
  std::optional<double> fx, fy, cx, cy;  // [px]
  render::LensModel model = render::LensModel::kPinhole;
  std::array<double, 5> distortion{};  // plumb_bob: k1, k2, p1, p2, k3; equidistant: k1, k2, k3, k4
  double downscale = 1.0;
};
struct CameraSpec {
  using Kind = CameraSensor;
  CameraCalibration calibration;
  std::shared_ptr<const render::Lens> lens;  // the calibration and its ray table (shared, immutable)
  std::shared_ptr<const std::vector<float>> cos_theta;  // z_C of each pixel's ray (vignetting)
  // The backscatter table of the lights on the camera's own vehicle, kept from frame to frame
  // (render/frame.h); shared by copies of the spec, rebuilt if its inputs change. Made with the lens by
  // set_lens(); without one, every frame makes its table.
  std::shared_ptr<render::BackscatterTableCache> backscatter_cache;
  double near_clip = 0.1;
  double far_clip = 50.0;
  bool mono = false;  // mono8 instead of rgb8
  ImageSensorSpec sensor;
};

}  // namespace hadal::sensors
