#include "hadal/sensors/camera_sensor.h"

#include <sensor_msgs.h>
#include <sensor_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "hadal/config/yaml_reader.h"
#include "hadal/core/model.h"
#include "hadal/core/units.h"
#include "hadal/dds/time_msg.h"
#include "hadal/geometry/embree_scene.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/render/camera_presets.h"
#include "hadal/render/camera_rays.h"
#include "hadal/render/frame.h"
#include "hadal/render/texture.h"
#include "hadal/sensors/noise.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::format_number;
using config::MapReader;
using config::Need;
using config::Range;

namespace {

render::SpotLight spot_light(const LightSpec& light, const Eigen::Isometry3d& X_AF) {
  render::SpotLight spot;
  spot.p_WL = X_AF.translation();
  spot.axis_W = X_AF.linear().col(0).normalized();
  spot.inner_half_angle_rad = light.inner_half_angle;
  spot.outer_half_angle_rad = light.outer_half_angle;
  spot.intensity_W_per_sr = light.intensity_W_per_sr;
  return spot;
}

// Every vehicle's lights posed at the snapshot, and the world's optics.
render::FrameLighting lighting_at(const Model& model, const std::vector<Eigen::Isometry3d>& X_WB) {
  render::FrameLighting lighting;
  lighting.water = model.world.optics.water;
  lighting.daylight = model.world.optics.daylight;
  lighting.marine_snow = model.world.optics.marine_snow;
  for (std::size_t i = 0; i < model.vehicles.size() && i < X_WB.size(); ++i) {
    const VehicleSpec& vehicle = model.vehicles[i];
    for (const LightSpec& light : vehicle.lights) {
      lighting.lights.push_back(
          spot_light(light, X_WB[i] * vehicle.links[static_cast<std::size_t>(light.link_index)].X_BL * light.X_LF));
    }
  }
  return lighting;
}

// The lights in the camera's optical frame C when they all ride on the camera's own vehicle (rigid:
// the same in every frame, from the specs alone, so their backscatter table is kept); nullopt when
// another vehicle has lights (they move relative to the camera).
std::optional<std::vector<render::SpotLight>> own_lights_C(const Model& model, int vehicle_index,
                                                           const Eigen::Isometry3d& X_BS) {
  std::vector<render::SpotLight> lights_C;
  const Eigen::Isometry3d X_CB = (X_BS * render::X_SC()).inverse();
  for (std::size_t i = 0; i < model.vehicles.size(); ++i) {
    const VehicleSpec& vehicle = model.vehicles[i];
    if (vehicle.lights.empty()) continue;
    if (static_cast<int>(i) != vehicle_index) return std::nullopt;
    for (const LightSpec& light : vehicle.lights) {
      lights_C.push_back(spot_light(light, X_CB * vehicle.links[static_cast<std::size_t>(light.link_index)].X_BL * light.X_LF));
    }
  }
  return lights_C;
}

void fill_header(const MessageHeader& header, std_msgs::msg::Header& out) {
  out.stamp(dds::to_time_msg(header.stamp));
  out.frame_id(CameraSensor::optical_frame_id(header.frame_id));
}

}  // namespace

Eigen::Array3d surface_albedo(const Model& model, const std::vector<Eigen::Isometry3d>& X_WB,
                              const render::SurfacePoint& hit) {
  const OpticsSpec& optics = model.world.optics;
  const Eigen::Vector3d& p_W = hit.p_W;
  if (hit.material == geometry::kSeabedMaterial || hit.body < 0) {
    return render::sediment_albedo(optics.seabed_pattern, optics.seabed_albedo, p_W.x(), p_W.y());
  }
  const auto b = static_cast<std::size_t>(hit.body);
  const std::uint32_t code = hit.material - geometry::kVehicleMaterial;  // geometry::link_material(link, m)
  const std::size_t link = geometry::link_of_material(code);
  if (hit.material < geometry::kVehicleMaterial || b >= model.vehicles.size() || b >= X_WB.size() ||
      link >= model.vehicles[b].links.size()) {
    return optics.vehicle_albedo;
  }
  const LinkSpec& spec = model.vehicles[b].links[link];
  render::Rgb base = optics.vehicle_albedo;
  if (spec.appearance.albedo) {
    base = *spec.appearance.albedo;
  } else if (const LinkMesh* seen = spec.seen_mesh()) {
    // The link mesh's own material (its visual mesh's, if it has one): its glTF base colour factor
    // (linear RGB), times its base-colour texture at the hit's texture coordinates when it has one
    // (render/texture.h), clipped to [0, 1].
    const geometry::TriangleMesh& mesh = *seen->mesh;
    const std::uint32_t m = geometry::mesh_material_of(code);
    if (m < mesh.materials.size()) {
      const geometry::Material& material = mesh.materials[m];
      const auto& c = material.base_color;
      base = render::Rgb(c[0], c[1], c[2]);
      const int t = material.base_color_texture;
      if (t >= 0 && static_cast<std::size_t>(t) < mesh.textures.size() && std::isfinite(hit.tex_u) &&
          std::isfinite(hit.tex_v)) {
        base *= render::sample_texture(mesh.textures[static_cast<std::size_t>(t)], hit.tex_u, hit.tex_v);
      }
      base = base.cwiseMax(0.0).cwiseMin(1.0);
    }
  }
  if (!spec.appearance.checkerboard) return base;
  const CheckerboardSpec& board = *spec.appearance.checkerboard;
  const Eigen::Vector3d p_P = (X_WB[b] * spec.X_BL * board.X_LP).inverse() * p_W;
  const double column = std::floor(p_P.x() / board.square_size), row = std::floor(p_P.y() / board.square_size);
  if (column < 0.0 || row < 0.0 || column >= board.columns || row >= board.rows) return base;
  return (static_cast<long>(column) + static_cast<long>(row)) % 2 == 0 ? render::Rgb(board.dark_albedo) : base;
}

void surface_albedos(const Model& model, const std::vector<Eigen::Isometry3d>& X_WB, const render::SurfacePoints& points,
                     float* r, float* g, float* b) {
  const OpticsSpec& optics = model.world.optics;
  render::sediment_albedo(optics.seabed_pattern, optics.seabed_albedo, points.origin_W.head<2>(), points.x, points.y,
                          points.count, r, g, b);
  for (std::size_t i = 0; i < points.count; ++i) {
    if (points.material[i] == geometry::kSeabedMaterial || points.body[i] < 0) continue;  // the seabed, or a miss
    const Eigen::Array3d albedo = surface_albedo(model, X_WB, points.point(i));
    r[i] = static_cast<float>(albedo[0]);
    g[i] = static_cast<float>(albedo[1]);
    b[i] = static_cast<float>(albedo[2]);
  }
}

const std::vector<std::string>& CameraSensor::keys() {
  static const std::vector<std::string> keys = {
      "width",       "height",        "hfov_deg",    "fx",           "fy",         "cx",
      "cy",          "lens_model",    "distortion",  "near_clip",    "far_clip",   "encoding",
      "exposure_s",  "gain_dn_per_e", "full_well_e", "read_noise_e", "shot_noise", "vignetting",
      "sensitivity", "preset",        "downscale"};
  return keys;
}

namespace {

// The calibration keys (a field of view, or fx, fy, cx, cy, a lens model and its distortion).
void read_calibration(const MapReader& map, render::LensSpec& lens) {
  map.read_whole_number("width", Need::kOptional, Range::closed(1.0, 8192.0), &lens.width_px);
  map.read_whole_number("height", Need::kOptional, Range::closed(1.0, 8192.0), &lens.height_px);
  const bool calibrated = map.has("fx") || map.has("fy");
  double hfov_deg = 90.0;
  if (map.has("hfov_deg") && calibrated) {
    map.error_at_key("hfov_deg", "give either hfov_deg or the calibration fx, fy, not both");
  }
  map.read_number("hfov_deg", Need::kOptional, Range::closed(1.0, 179.0), &hfov_deg);
  const render::LensSpec fov = render::lens_from_horizontal_fov(lens.width_px, lens.height_px, hfov_deg * kDegToRad);
  lens.fx = fov.fx;
  lens.fy = fov.fy;
  lens.cx = fov.cx;
  lens.cy = fov.cy;
  if (calibrated) {
    map.read_number("fx", Need::kRequired, Range::positive(), &lens.fx);
    map.read_number("fy", Need::kRequired, Range::positive(), &lens.fy);
  }
  map.read_number("cx", Need::kOptional, Range::finite(), &lens.cx);
  map.read_number("cy", Need::kOptional, Range::finite(), &lens.cy);
  map.read_choice("lens_model", Need::kOptional,
                  {{"pinhole", render::LensModel::kPinhole},
                   {"plumb_bob", render::LensModel::kRadialTangential},
                   {"radial_tangential", render::LensModel::kRadialTangential},
                   {"equidistant", render::LensModel::kEquidistant}},
                  &lens.model);
  if (const auto distortion = map.optional("distortion")) {
    if (lens.model == render::LensModel::kPinhole) {
      map.error_at_key("distortion", "a pinhole lens has no distortion (set lens_model: plumb_bob or equidistant)");
    } else {
      const std::size_t count = lens.model == render::LensModel::kEquidistant ? 4 : 5;
      if (const auto d = distortion->numbers(count)) std::copy(d->begin(), d->end(), lens.distortion.begin());
    }
  }
}

// A preset's calibration (render/camera_presets.h); nullopt after reporting an unknown name or a
// calibration key given with it.
std::optional<render::LensSpec> read_preset(const MapReader& map) {
  std::string name;
  map.read_string("preset", Need::kRequired, &name);
  std::optional<render::LensSpec> preset = render::camera_preset(name);
  if (!preset) {
    std::string names;
    for (const auto& p : render::camera_presets()) names += (names.empty() ? "" : ", ") + std::string(p.name);
    map.error_at_key("preset", "unknown camera preset '" + name + "' (presets: " + names + ")");
  }
  for (const char* key : {"width", "height", "hfov_deg", "fx", "fy", "cx", "cy", "lens_model", "distortion"}) {
    if (map.has(key)) {
      map.error_at_key(key, std::string("the preset sets the calibration; give either '") + key +
                                "' or 'preset' (use 'downscale' for a smaller image)");
      preset.reset();
    }
  }
  return preset;
}

}  // namespace

CameraSensor::Spec CameraSensor::read(const SensorReader& reader) {
  const MapReader& map = reader.map;
  Spec spec;
  render::LensSpec lens;
  bool lens_read = true;  // false after an error in the calibration's own keys: no lens is made
  if (map.has("preset")) {
    const std::optional<render::LensSpec> preset = read_preset(map);
    lens_read = preset.has_value();
    if (preset) lens = *preset;
  } else {
    read_calibration(map, lens);
  }
  double downscale = 1.0;
  if (map.read_number("downscale", Need::kOptional, Range::closed(1.0, 64.0), &downscale) && lens_read) {
    try {
      lens = render::downscaled(lens, downscale);
    } catch (const std::invalid_argument& e) {
      map.error_at_key("downscale", e.what());
      lens_read = false;
    }
  }
  map.read_number("near_clip", Need::kOptional, Range::non_negative(), &spec.near_m);
  map.read_number("far_clip", Need::kOptional, Range::positive(), &spec.far_m);
  if (!(spec.far_m > spec.near_m)) {
    map.error_at_key(map.has("far_clip") ? "far_clip" : "near_clip",
                     "far_clip (" + format_number(spec.far_m) + " m) must exceed near_clip (" +
                         format_number(spec.near_m) + " m)");
  }
  map.read_choice("encoding", Need::kOptional, {{"rgb8", false}, {"mono8", true}}, &spec.mono);
  ImageSensorSpec& sensor = spec.sensor;
  map.read_number("exposure_s", Need::kOptional, Range::left_open(0.0, 10.0), &sensor.exposure_s);
  map.read_number("gain_dn_per_e", Need::kOptional, Range::left_open(0.0, 1e3), &sensor.gain_dn_per_e);
  map.read_number("full_well_e", Need::kOptional, Range::left_open(0.0, 1e8), &sensor.full_well_e);
  map.read_number("read_noise_e", Need::kOptional, Range::closed(0.0, 1e4), &sensor.read_noise_e);
  map.read_bool("shot_noise", Need::kOptional, &sensor.shot_noise);
  map.read_bool("vignetting", Need::kOptional, &sensor.vignetting);
  Eigen::Vector3d sensitivity = sensor.sensitivity.matrix();
  if (map.read_vector3("sensitivity", Need::kOptional, Range::left_open(0.0, 1e12), &sensitivity)) {
    sensor.sensitivity = sensitivity.array();
  }
  // The lens: its own checks (a distortion without an inverse inside the image, say) at the lens keys.
  if (!lens_read) return spec;
  try {
    set_lens(spec, lens);
  } catch (const std::invalid_argument& e) {
    const char* key = map.has("preset")       ? "preset"
                      : map.has("distortion") ? "distortion"
                      : map.has("fx")         ? "fx"
                      : map.has("hfov_deg")   ? "hfov_deg"
                                              : nullptr;
    if (key != nullptr) {
      map.error_at_key(key, std::string("unusable lens: ") + e.what());
    } else {
      map.value().error(std::string("unusable lens: ") + e.what());
    }
  }
  return spec;
}

void CameraSensor::set_lens(Spec& spec, const render::LensSpec& lens) {
  auto made = std::make_shared<const render::Lens>(render::make_lens(lens));
  auto cos_theta = std::make_shared<std::vector<float>>();
  cos_theta->reserve(made->rays_C().size());
  for (const Eigen::Vector3f& d : made->rays_C()) cos_theta->push_back(d.z());
  spec.lens = std::move(made);
  spec.cos_theta = std::move(cos_theta);
  spec.backscatter_cache = std::make_shared<render::BackscatterTableCache>();
}

CameraSensor::State CameraSensor::initial_state(const Spec& /*spec*/, const SensorSetup& setup) {
  State state;
  state.noise_key = channel_key(setup.seed, setup.vehicle, setup.sensor, "image");
  return state;
}

CaptureWork CameraSensor::capture(const CaptureContext& context, const Spec& spec, const State& state, Capture& out) {
  if (context.model == nullptr) throw std::logic_error("camera capture: no model in the capture context");
  if (!spec.lens) throw std::logic_error("camera capture: the camera has no lens (a failed read)");
  const Eigen::Isometry3d X_WC = context.X_WS() * render::X_SC();
  const std::int32_t own_body = static_cast<std::int32_t>(context.vehicle_index);
  const std::uint64_t key = state.noise_key, frame = context.step_count;
  render::FrameLighting lighting = lighting_at(*context.model, context.X_WB);
  lighting.negligible_radiance_W_per_m2_sr = negligible_radiance(spec.sensor);
  return [&out, spec, X_WC, own_body, key, frame, model = context.model, X_WB = context.X_WB, lighting = std::move(lighting),
          lights_C = own_lights_C(*context.model, context.vehicle_index, context.X_BS)](
             const geometry::EmbreeScene& scene, const ParallelFor& parallel) mutable {
    const render::AlbedoOfPoints albedo = [&](const render::SurfacePoints& points, float* r, float* g, float* b) {
      surface_albedos(*model, X_WB, points, r, g, b);
    };
    if (lights_C && spec.backscatter_cache) {
      lighting.backscatter = spec.backscatter_cache->get(lighting, *lights_C, spec.lens, static_cast<float>(spec.near_m),
                                                         static_cast<float>(spec.far_m), parallel);
    }
    render::RadianceFrame frame_radiance =
        render::render_radiance(scene, *spec.lens, X_WC, static_cast<float>(spec.near_m), static_cast<float>(spec.far_m),
                                own_body, lighting, albedo, parallel);
    std::vector<std::uint8_t> rgb = expose_rgb8(spec.sensor, frame_radiance.radiance, *spec.cos_theta, key, frame, parallel);
    if (spec.mono) {
      out.image.resize(rgb.size() / 3);
      for (std::size_t i = 0; i < out.image.size(); ++i) {
        const double luma = 0.299 * rgb[3 * i] + 0.587 * rgb[3 * i + 1] + 0.114 * rgb[3 * i + 2];
        out.image[i] = static_cast<std::uint8_t>(std::lround(luma));
      }
    } else {
      out.image = std::move(rgb);
    }
    out.depth_m = std::move(frame_radiance.depth_m);
  };
}

void CameraSensor::deliver(const SampleContext& /*context*/, const Spec& /*spec*/, State& state, Capture&& capture) {
  state.image = std::move(capture.image);
  state.depth_m = std::move(capture.depth_m);
}

void CameraSensor::ImageRawTopic::fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
  fill_header(header, msg.header());
  const std::uint32_t width = static_cast<std::uint32_t>(spec.lens->width_px());
  msg.height(static_cast<std::uint32_t>(spec.lens->height_px()));
  msg.width(width);
  msg.encoding(spec.mono ? "mono8" : "rgb8");
  msg.is_bigendian(0);
  msg.step(width * (spec.mono ? 1u : 3u));
  msg.data() = state.image;
}

void CameraSensor::DepthTopic::fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
  fill_header(header, msg.header());
  const std::uint32_t width = static_cast<std::uint32_t>(spec.lens->width_px());
  msg.height(static_cast<std::uint32_t>(spec.lens->height_px()));
  msg.width(width);
  msg.encoding("32FC1");
  msg.is_bigendian(0);  // x86-64 and ARM64 hosts: little-endian floats
  msg.step(width * static_cast<std::uint32_t>(sizeof(float)));
  msg.data().resize(state.depth_m.size() * sizeof(float));
  if (!state.depth_m.empty()) std::memcpy(msg.data().data(), state.depth_m.data(), msg.data().size());
}

void CameraSensor::CameraInfoTopic::fill(const Spec& spec, const State& /*state*/, const MessageHeader& header,
                                         Message& msg) {
  fill_header(header, msg.header());
  const render::Lens& lens = *spec.lens;
  msg.height(static_cast<std::uint32_t>(lens.height_px()));
  msg.width(static_cast<std::uint32_t>(lens.width_px()));
  msg.distortion_model(lens.distortion_model());
  msg.d(lens.D());
  msg.k(lens.K());
  msg.r(lens.R());
  msg.p(lens.P());
  msg.binning_x(0);
  msg.binning_y(0);
  msg.roi(sensor_msgs::msg::RegionOfInterest{});
}

}  // namespace hadal::sensors
