#include "hadal/sensors/camera_sensor.h"

#include <sensor_msgs.h>
#include <sensor_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "hadal/config/key_table.h"
#include "hadal/core/model.h"
#include "hadal/core/units.h"
#include "hadal/dds/time_msg.h"
#include "hadal/geometry/embree_scene.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/physics/ocean.h"
#include "hadal/render/camera_presets.h"
#include "hadal/render/camera_rays.h"
#include "hadal/render/frame.h"
#include "hadal/render/sediment_pattern.h"
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

// Every vehicle's lights posed at the snapshot (each on its link's ray body: geometry/world_scene.h), and the
// world's optics.
render::FrameLighting lighting_at(const Model& model, const geometry::RayBodies& bodies,
                                  const std::vector<Eigen::Isometry3d>& X_WB) {
  render::FrameLighting lighting;
  lighting.water = model.world.optics.water;
  lighting.daylight = model.world.optics.daylight;
  lighting.marine_snow = model.world.optics.marine_snow;
  for (std::size_t i = 0; i < model.vehicles.size(); ++i) {
    const VehicleSpec& vehicle = model.vehicles[i];
    for (const LightSpec& light : vehicle.lights) {
      const auto b = static_cast<std::size_t>(bodies.of_link(static_cast<int>(i), light.link_index));
      if (b >= X_WB.size()) continue;
      lighting.lights.push_back(
          spot_light(light, X_WB[b] * vehicle.links[static_cast<std::size_t>(light.link_index)].X_BL * light.X_LF));
    }
  }
  return lighting;
}

// The lights in the camera's optical frame C when they all ride on the camera's own vehicle's base body, as
// the camera does (rigid: the same in every frame, from the specs alone, so their backscatter table is kept);
// nullopt when a light moves relative to the camera (on another vehicle, or either on a moving link).
std::optional<std::vector<render::SpotLight>> own_lights_C(const Model& model, const geometry::RayBodies& bodies,
                                                           int vehicle_index, int own_ray_body,
                                                           const Eigen::Isometry3d& X_BS) {
  std::vector<render::SpotLight> lights_C;
  const Eigen::Isometry3d X_CB = (X_BS * render::X_SC()).inverse();
  for (std::size_t i = 0; i < model.vehicles.size(); ++i) {
    const VehicleSpec& vehicle = model.vehicles[i];
    if (vehicle.lights.empty()) continue;
    if (static_cast<int>(i) != vehicle_index || own_ray_body != vehicle_index) return std::nullopt;
    for (const LightSpec& light : vehicle.lights) {
      if (bodies.link_moves(vehicle_index, light.link_index)) return std::nullopt;
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

Eigen::Array3d surface_albedo(const Model& model, const geometry::RayBodies& bodies,
                              const std::vector<Eigen::Isometry3d>& X_WB, const render::SurfacePoint& hit) {
  const OpticsSpec& optics = model.world.optics;
  const Eigen::Vector3d& p_W = hit.p_W;
  if (hit.material == geometry::kSeabedMaterial || hit.body < 0) {
    return render::sediment_albedo(optics.seabed_pattern, optics.seabed_albedo, p_W.x(), p_W.y());
  }
  // The hit's ray body b carries its links at X_W(b) X_BL (geometry/world_scene.h).
  const auto b = static_cast<std::size_t>(hit.body);
  const std::uint32_t code = hit.material - geometry::kVehicleMaterial;  // geometry::link_material(link, m)
  const std::size_t link = geometry::link_of_material(code);
  if (hit.material < geometry::kVehicleMaterial || hit.body >= bodies.count() || b >= X_WB.size()) {
    return optics.vehicle_albedo;
  }
  const VehicleSpec& vehicle = model.vehicles[static_cast<std::size_t>(bodies.vehicle(hit.body))];
  if (link >= vehicle.links.size()) return optics.vehicle_albedo;
  const LinkSpec& spec = vehicle.links[link];
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

void surface_albedos(const Model& model, const geometry::RayBodies& bodies, const std::vector<Eigen::Isometry3d>& X_WB,
                     const render::SurfacePoints& points, float* r, float* g, float* b) {
  const OpticsSpec& optics = model.world.optics;
  render::sediment_albedo(optics.seabed_pattern, optics.seabed_albedo, points.origin_W.head<2>(), points.x, points.y,
                          points.count, r, g, b);
  for (std::size_t i = 0; i < points.count; ++i) {
    if (points.material[i] == geometry::kSeabedMaterial || points.body[i] < 0) continue;  // the seabed, or a miss
    const Eigen::Array3d albedo = surface_albedo(model, bodies, X_WB, points.point(i));
    r[i] = static_cast<float>(albedo[0]);
    g[i] = static_cast<float>(albedo[1]);
    b[i] = static_cast<float>(albedo[2]);
  }
}

namespace {

// The calibration keys a preset sets: given with `preset`, they are errors.
constexpr const char* kCalibrationKeys[] = {"width", "height", "hfov_deg", "fx", "fy", "cx", "cy", "lens_model", "distortion"};

// The lens of the calibration keys (a preset's, or a field of view or fx, fy with cx, cy, the model and its
// distortion), downscaled; nullopt after reporting. Errors at the keys.
std::optional<render::LensSpec> make_lens_spec(const config::KeyReads& reads, const CameraSensor::Calibration& c) {
  const config::MapReader& map = reads.map();
  render::LensSpec lens;
  bool lens_read = true;  // false after a preset's error: no lens is made
  if (reads.has("preset")) {
    std::optional<render::LensSpec> preset;  // none after an unknown preset (reported at its key)
    if (c.preset != nullptr) preset = *c.preset;
    for (const char* key : kCalibrationKeys) {
      if (map.has(key)) {
        map.error_at_key(key, std::string("the preset sets the calibration; give either '") + key +
                                  "' or 'preset' (use 'downscale' for a smaller image)");
        preset.reset();
      }
    }
    lens_read = preset.has_value();
    if (preset) lens = *preset;
  } else {
    const bool calibrated = map.has("fx") || map.has("fy");
    if (map.has("hfov_deg") && calibrated) {
      map.error_at_key("hfov_deg", "give either hfov_deg or the calibration fx, fy, not both");
    }
    lens = render::lens_from_horizontal_fov(c.width_px, c.height_px, c.hfov);
    if (calibrated) {
      for (const char* key : {"fx", "fy"}) {
        if (!map.has(key)) map.required(key);
      }
      if (c.fx) lens.fx = *c.fx;
      if (c.fy) lens.fy = *c.fy;
    }
    if (c.cx) lens.cx = *c.cx;
    if (c.cy) lens.cy = *c.cy;
    lens.model = c.model;
    if (map.has("distortion") && c.model == render::LensModel::kPinhole) {
      map.error_at_key("distortion", "a pinhole lens has no distortion (set lens_model: plumb_bob or equidistant)");
    }
    lens.distortion = c.distortion;
  }
  if (reads.ok("downscale") && lens_read) {
    try {
      lens = render::downscaled(lens, c.downscale);
    } catch (const std::invalid_argument& e) {
      map.error_at_key("downscale", e.what());
      lens_read = false;
    }
  }
  if (!lens_read) return std::nullopt;
  return lens;
}

}  // namespace

SensorReach CameraSensor::reach(const Spec& spec) {
  const render::LensSpec& lens = spec.lens->spec();
  return {spec.far_clip, std::atan2(0.5 * lens.width_px, lens.fx)};
}

const config::KeyTable<CameraSensor::Spec, SensorReader>& CameraSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].camera", "a ray-traced camera: lens, deep-sea optics, lights, the image sensor");
    const auto calibration = [](auto field) {
      return [field](Spec& s) -> auto& { return s.calibration.*field; };
    };
    t.preset("camera", render::camera_presets(),
             [](Spec& spec, const config::Preset<render::LensSpec>& p, SensorReader&) { spec.calibration.preset = &p.figures; })
        .doc("a real camera's published calibration (table below) instead of the calibration keys");
    t.number("width", calibration(&Calibration::width_px)).unit("px").range(Range::closed(1.0, 8192.0))
        .doc("image width");
    t.number("height", calibration(&Calibration::height_px)).unit("px").range(Range::closed(1.0, 8192.0))
        .doc("image height");
    t.number("hfov_deg", calibration(&Calibration::hfov)).degrees().range(Range::closed(1.0, 179.0))
        .doc("horizontal field of view of a centred pinhole with square pixels; or give fx, fy");
    t.number("fx", calibration(&Calibration::fx)).unit("px").range(Range::positive()).doc("focal length (with fy)");
    t.number("fy", calibration(&Calibration::fy)).unit("px").range(Range::positive()).doc("focal length (with fx)");
    t.number("cx", calibration(&Calibration::cx)).unit("px").default_text("the image centre")
        .doc("principal point; the centre of pixel (i, j) is (i, j)");
    t.number("cy", calibration(&Calibration::cy)).unit("px").default_text("the image centre").doc("principal point");
    t.choice("lens_model", calibration(&Calibration::model),
             {{"pinhole", render::LensModel::kPinhole},
              {"plumb_bob", render::LensModel::kRadialTangential},
              {"radial_tangential", render::LensModel::kRadialTangential, "= plumb_bob"},
              {"equidistant", render::LensModel::kEquidistant, "OpenCV fisheye"}})
        .doc("the lens model");
    t.custom(
         "distortion",
         [](const config::Value& value, Spec& spec, SensorReader&) {
           if (spec.calibration.model == render::LensModel::kPinhole) return true;  // an error at the key (check)
           const std::size_t count = spec.calibration.model == render::LensModel::kEquidistant ? 4 : 5;
           const auto d = value.numbers(count);
           if (d) std::copy(d->begin(), d->end(), spec.calibration.distortion.begin());
           return d.has_value();
         },
         R"({"type": "array", "items": {"type": "number"}, "minItems": 4, "maxItems": 5})", "4 or 5 numbers")
        .default_text("zeros")
        .doc("`plumb_bob`: [k1, k2, p1, p2, k3]; `equidistant`: [k1, k2, k3, k4]; a lens that folds over inside "
             "the image is an error");
    t.number("downscale", calibration(&Calibration::downscale)).range(Range::closed(1.0, 64.0))
        .doc("the calibration of the image resized by 1/s (binned): fx/s, fy/s, c' = (c + 0.5)/s - 0.5; width and "
             "height must divide by s");
    t.number("near_clip", &Spec::near_clip).unit("m").range(Range::non_negative()).doc("along each ray");
    t.number("far_clip", &Spec::far_clip).unit("m").range(Range::positive()).rule("> near_clip").doc("along each ray");
    t.choice("encoding", &Spec::mono, {{"rgb8", false}, {"mono8", true, "Rec. 601 luma of the counts"}})
        .doc("the image's encoding");
    const auto sensor = [](auto field) {
      return [field](Spec& s) -> auto& { return s.sensor.*field; };
    };
    t.number("exposure_s", sensor(&ImageSensorSpec::exposure_s)).unit("s").range(Range::left_open(0.0, 10.0))
        .doc("exposure time");
    t.number("gain_dn_per_e", sensor(&ImageSensorSpec::gain_dn_per_e)).unit("counts/e⁻")
        .range(Range::left_open(0.0, 1e3)).doc("analog gain");
    t.number("full_well_e", sensor(&ImageSensorSpec::full_well_e)).unit("e⁻").range(Range::left_open(0.0, 1e8))
        .doc("full-well capacity");
    t.number("read_noise_e", sensor(&ImageSensorSpec::read_noise_e)).unit("e⁻").range(Range::closed(0.0, 1e4))
        .doc("rms read noise");
    t.boolean("shot_noise", sensor(&ImageSensorSpec::shot_noise)).doc("Poisson shot noise");
    t.boolean("vignetting", sensor(&ImageSensorSpec::vignetting)).doc("the cos^4 fall-off");
    t.vector("sensitivity", sensor(&ImageSensorSpec::sensitivity)).unit("e⁻/s per W/(m² sr)")
        .range(Range::left_open(0.0, 1e12)).doc("lens, pixel and quantum efficiency lumped per channel");
    t.check([](const config::KeyReads& reads, Spec& spec, SensorReader&) {
      const config::MapReader& map = reads.map();
      bool ok = true;
      if (!(spec.far_clip > spec.near_clip)) {
        map.error_at_key(map.has("far_clip") ? "far_clip" : "near_clip",
                         "far_clip (" + format_number(spec.far_clip) + " m) must exceed near_clip (" +
                             format_number(spec.near_clip) + " m)");
        ok = false;
      }
      const std::optional<render::LensSpec> lens = make_lens_spec(reads, spec.calibration);
      if (!lens) return false;
      // The lens: its own checks (a distortion without an inverse inside the image, say) at the lens keys.
      try {
        set_lens(spec, *lens);
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
        ok = false;
      }
      return ok;
    });
  });
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
  const std::int32_t own_body = static_cast<std::int32_t>(context.own_ray_body());
  const std::uint64_t key = state.noise_key, frame = context.step_count;
  geometry::RayBodies bodies(*context.model);
  render::FrameLighting lighting = lighting_at(*context.model, bodies, context.X_WB);
  lighting.negligible_radiance_W_per_m2_sr = negligible_radiance(spec.sensor);
  if (context.ocean != nullptr && context.ocean->waves().enabled()) {
    // The surface over the camera as the waves have it at the snapshot: its height and tilt (Snell's window moves).
    const Eigen::Vector3d& p_WC = X_WC.translation();
    Eigen::Vector2d slope;
    context.ocean->surface_tangent(p_WC.x(), p_WC.y(), context.time, &lighting.daylight.surface_z_m, &slope);
    lighting.daylight.surface_normal_W = Eigen::Vector3d(-slope.x(), -slope.y(), 1.0).normalized();
  }
  std::optional<std::vector<render::SpotLight>> lights_C =
      own_lights_C(*context.model, bodies, context.vehicle_index, own_body, context.X_BS);
  return [&out, spec, X_WC, own_body, key, frame, model = context.model, bodies = std::move(bodies),
          X_WB = context.X_WB, lighting = std::move(lighting), lights_C = std::move(lights_C)](
             const geometry::EmbreeScene& scene, const ParallelFor& parallel) mutable {
    const render::AlbedoOfPoints albedo = [&](const render::SurfacePoints& points, float* r, float* g, float* b) {
      surface_albedos(*model, bodies, X_WB, points, r, g, b);
    };
    if (lights_C && spec.backscatter_cache) {
      lighting.backscatter = spec.backscatter_cache->get(lighting, *lights_C, spec.lens, static_cast<float>(spec.near_clip),
                                                         static_cast<float>(spec.far_clip), parallel);
    }
    render::RadianceFrame frame_radiance =
        render::render_radiance(scene, *spec.lens, X_WC, static_cast<float>(spec.near_clip), static_cast<float>(spec.far_clip),
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
