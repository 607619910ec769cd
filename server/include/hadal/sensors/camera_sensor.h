// Camera (YAML `type: camera`): a calibrated lens and an image sensor, rendered natively on the ray-cast
// workers with deep-sea image formation (docs/ARCHITECTURE.md, "Cameras"; render/frame.h). Topics:
//   rt/<vehicle>/<camera>/image_raw    sensor_msgs/Image, rgb8 (or mono8: the counts' Rec. 601 luma,
//                                      0.299 R + 0.587 G + 0.114 B, rounded)
//   rt/<vehicle>/<camera>/depth        sensor_msgs/Image, 32FC1: metres along the optical axis, NaN where
//                                      nothing is hit within the clip
//   rt/<vehicle>/<camera>/camera_info  sensor_msgs/CameraInfo: plumb_bob or equidistant, D, K, R, P exactly
//                                      as configured (render/lens.h)
// all with header.frame_id "<frame_id>_optical" (the optical frame C: z forward, x right, y down; REP
// 103/105) and stamped with the sim time of the snapshot the frame was rendered from. Mounted like every
// sensor, looking along x_S (C = S rotated by render::X_SC()).
//
// A frame is a captured sample (sensors/sensor_kind.h): at each sample time the snapshot's scene work
// renders radiance and depth (render::render_radiance: every vehicle's lights posed at the snapshot, the
// world's optics, shadows, backscatter, daylight), then exposes it (sensors/image_sensor.h, noise stream
// keyed by world.seed, vehicle, camera and the capture's step count, so the same seed gives the same
// images), on every ray-cast worker; the frame is published latency_s later. Its own vehicle is
// transparent to its rays and to its shadow rays. Surfaces: world.optics.seabed_albedo for the seabed,
// vehicle_albedo for hulls.
//
// YAML keys: CameraSensor::keys() (server/src/sensors/camera_sensor.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <cstdint>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/render/lens.h"
#include "hadal/sensors/image_sensor.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/camera_spec.h"

namespace sensor_msgs::msg {
class Image;
class ImagePubSubType;
class CameraInfo;
class CameraInfoPubSubType;
}  // namespace sensor_msgs::msg

namespace hadal::geometry {
class RayBodies;
}
namespace hadal::render {
class BackscatterTableCache;
struct SurfacePoint;
struct SurfacePoints;
}  // namespace hadal::render

namespace hadal::sensors {

// The albedo (0..1 per channel) of a surface point a camera ray hit (render::AlbedoAt), from the hit's
// material id and body: the seabed's (with its sediment pattern at p_W), or the hit link's: its YAML
// appearance albedo if given, else the base colour of the link mesh's glTF material the triangle
// belongs to (geometry::link_material): its factor times its base-colour texture at the hit's texture
// coordinates (render/texture.h), else the world's vehicle albedo; a checkerboard appearance is
// evaluated in the link's pattern frame at the snapshot's ray body poses X_WB (geometry/world_scene.h).
Eigen::Array3d surface_albedo(const Model& model, const geometry::RayBodies& bodies,
                              const std::vector<Eigen::Isometry3d>& X_WB, const render::SurfacePoint& hit);
// The same for a band of points (render::AlbedoOfPoints): the seabed's in one vectorized pass
// (render::sediment_albedo's batch form), the links' point by point.
void surface_albedos(const Model& model, const geometry::RayBodies& bodies, const std::vector<Eigen::Isometry3d>& X_WB,
                     const render::SurfacePoints& points, float* r, float* g, float* b);

struct CameraSensor {
  static constexpr std::string_view kType = "camera";
  static constexpr bool kCastsRays = false;  // rendered on the workers
  static constexpr bool kCaptures = true;
  static constexpr bool kRendersImages = true;  // hadald --no-cameras leaves it out

  using Calibration = CameraCalibration;
  using Spec = CameraSpec;
  struct State {
    std::uint64_t noise_key = 0;
    std::vector<std::uint8_t> image;  // rgb8 (3 bytes per pixel) or mono8, row-major
    std::vector<float> depth_m;       // row-major
  };
  struct Capture {
    std::vector<std::uint8_t> image;
    std::vector<float> depth_m;
  };

  // Images are large (0.9 and 1.2 MB at 640 x 480): their writers keep 10, not 100 (TopicHistoryDepth).
  struct ImageRawTopic {
    static constexpr std::string_view kSuffix = "image_raw";
    static constexpr int kHistoryDepth = 10;
    static constexpr bool kPreview = true;  // rt/<vehicle>/<camera>/preview (sensors/sensor_kind.h)
    static constexpr bool kInMonitor = false;
    using Message = sensor_msgs::msg::Image;
    using PubSubType = sensor_msgs::msg::ImagePubSubType;
    static void fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
  };
  struct DepthTopic {
    static constexpr std::string_view kSuffix = "depth";
    static constexpr int kHistoryDepth = 10;
    static constexpr bool kInMonitor = false;
    using Message = sensor_msgs::msg::Image;
    using PubSubType = sensor_msgs::msg::ImagePubSubType;
    static void fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
  };
  struct CameraInfoTopic {
    static constexpr std::string_view kSuffix = "camera_info";
    using Message = sensor_msgs::msg::CameraInfo;
    using PubSubType = sensor_msgs::msg::CameraInfoPubSubType;
    static void fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg);
  };
  using Topics = TopicList<ImageRawTopic, DepthTopic, CameraInfoTopic>;

  static const config::KeyTable<Spec, SensorReader>& keys();
  static SensorReach reach(const Spec& spec);
  static State initial_state(const Spec& spec, const SensorSetup& setup);
  static CaptureWork capture(const CaptureContext& context, const Spec& spec, const State& state, Capture& out);
  static void deliver(const SampleContext& context, const Spec& spec, State& state, Capture&& capture);

  // Makes the spec's lens (its ray table) and the rays' cos theta; throws std::invalid_argument as
  // render::make_lens does.
  static void set_lens(Spec& spec, const render::LensSpec& lens);

  // "<frame_id>_optical", the frame id of the camera's messages.
  static std::string optical_frame_id(const std::string& frame_id) { return frame_id + "_optical"; }
};

}  // namespace hadal::sensors
