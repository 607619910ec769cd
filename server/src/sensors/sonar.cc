#include "hadal/sensors/sonar.h"

#include <marine_acoustic_msgs.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "hadal/config/yaml_reader.h"
#include "hadal/core/model.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/ray_batch.h"
#include "hadal/geometry/world_scene.h"
#include "hadal/physics/ocean.h"
#include "hadal/sensors/noise.h"

namespace hadal::sensors {

using config::format_number;
using config::MapReader;
using config::Need;
using config::Range;

std::uint64_t sonar_noise_key(const SensorSetup& setup) {
  return channel_key(setup.seed, setup.vehicle, setup.sensor, "echo");
}

void set_acoustics(const SonarAcoustics& a, render::SonarPingSpec& ping) {
  ping.min_range = a.min_range;
  ping.max_range = a.max_range;
  ping.bins = a.bins;
  ping.source_level_db = a.source_level_db;
  ping.noise_level_db = a.noise_level_db;
  ping.speckle = a.speckle;
  ping.receiver_noise = a.receiver_noise;
  ping.spreading_db_per_decade = a.spreading_db_per_decade;
  ping.tvg_spreading_db_per_decade = a.tvg_db_per_decade;
  ping.tvg_absorption = a.tvg_absorption;
}

namespace {

// Intensity I [uPa^2] over the display window [dB], 0..255.
std::uint8_t display_level(float intensity, double display_min_db, double display_max_db) {
  if (!(intensity > 0.0f)) return 0;
  const double level = 10.0 * std::log10(static_cast<double>(intensity));
  const double x = 255.0 * (level - display_min_db) / (display_max_db - display_min_db);
  return static_cast<std::uint8_t>(std::lround(std::clamp(x, 0.0, 255.0)));
}

}  // namespace

void SonarImageEncoding::encode(float intensity, std::uint8_t* out) const {
  if (float32) {
    std::memcpy(out, &intensity, sizeof(float));  // x86-64 and ARM64 hosts: little-endian
    return;
  }
  *out = display_level(intensity, display_min_db, display_max_db);
}

std::uint8_t SonarImageEncoding::grey(const std::uint8_t* sample) const {
  if (!float32) return *sample;
  float intensity = 0.0f;
  std::memcpy(&intensity, sample, sizeof(float));
  return display_level(intensity, display_min_db, display_max_db);
}

void fill_sonar_image_data(const SonarImageEncoding& encoding, std::uint32_t beam_count,
                           const std::vector<std::uint8_t>& data, marine_acoustic_msgs::msg::SonarImageData& out) {
  namespace dtype = marine_acoustic_msgs::msg::SonarImageData_Constants;
  out.is_bigendian(false);
  out.dtype(encoding.float32 ? dtype::DTYPE_FLOAT32 : dtype::DTYPE_UINT8);
  out.beam_count(beam_count);
  out.data() = data;
}

void fill_ping_info(const SonarAcoustics& acoustics, double sound_speed_m_per_s, const render::SonarPingSpec& ping,
                    marine_acoustic_msgs::msg::PingInfo& out) {
  out.frequency(static_cast<float>(acoustics.frequency_hz));
  out.sound_speed(static_cast<float>(sound_speed_m_per_s));
  out.tx_beamwidths().resize(ping.beams.size());
  out.rx_beamwidths().resize(ping.beams.size());
  for (std::size_t k = 0; k < ping.beams.size(); ++k) {
    out.tx_beamwidths()[k] = static_cast<float>(ping.beams[k].width_v_rad);
    out.rx_beamwidths()[k] = static_cast<float>(ping.beams[k].width_u_rad);
  }
}

render::SonarWater sonar_water(const physics::Ocean& ocean, const Eigen::Vector3d& p_WS, double frequency_hz, double t,
                               double surface_backscatter_db) {
  const double depth = std::max(ocean.depth(p_WS.z()), 0.0);
  render::SonarWater water;
  water.sound_speed_m_per_s = ocean.sound_speed(depth);
  water.absorption_db_per_m = ocean.sound_absorption_db_per_m(depth, frequency_hz);
  double height = 0.0;
  Eigen::Vector2d slope;
  ocean.surface_tangent(p_WS.x(), p_WS.y(), t, &height, &slope);
  water.surface = true;
  water.surface_point_W = Eigen::Vector3d(p_WS.x(), p_WS.y(), height);
  water.surface_normal_W = Eigen::Vector3d(-slope.x(), -slope.y(), 1.0).normalized();
  water.surface_mu = std::pow(10.0, surface_backscatter_db / 10.0);
  return water;
}

render::BackscatterOfHits model_backscatter(const Model& model) {
  const AcousticsSpec& acoustics = model.world.acoustics;
  const float seabed = static_cast<float>(std::pow(10.0, acoustics.seabed_backscatter_db / 10.0));
  const float hull = static_cast<float>(std::pow(10.0, acoustics.vehicle_backscatter_db / 10.0));
  // Per vehicle and link: its appearance's backscatter if given, else the hulls'; each ray body's vehicle.
  std::vector<std::vector<float>> links(model.vehicles.size());
  const geometry::RayBodies bodies(model);
  std::vector<std::size_t> vehicle_of;
  for (int b = 0; b < bodies.count(); ++b) vehicle_of.push_back(static_cast<std::size_t>(bodies.vehicle(b)));
  for (std::size_t v = 0; v < model.vehicles.size(); ++v) {
    for (const LinkSpec& link : model.vehicles[v].links) {
      const std::optional<double>& db = link.appearance.backscatter_db;
      links[v].push_back(db ? static_cast<float>(std::pow(10.0, *db / 10.0)) : hull);
    }
  }
  return [seabed, hull, links = std::move(links), vehicle_of = std::move(vehicle_of)](const geometry::RayHits& hits,
                                                                                    std::size_t count, float* mu) {
    for (std::size_t i = 0; i < count; ++i) {
      const std::int32_t body = hits.body[i];
      if (body == geometry::kNoHit) {
        mu[i] = 0.0f;
      } else if (body < 0 || hits.material[i] == geometry::kSeabedMaterial) {
        mu[i] = seabed;
      } else {
        const auto b = static_cast<std::size_t>(body);
        const std::size_t link = geometry::link_of_material(hits.material[i] - geometry::kVehicleMaterial);
        const std::size_t v = b < vehicle_of.size() ? vehicle_of[b] : links.size();
        mu[i] = v < links.size() && hits.material[i] >= geometry::kVehicleMaterial && link < links[v].size()
                    ? links[v][link]
                    : hull;
      }
    }
  };
}

CaptureWork sonar_ping_work(const CaptureContext& context, std::shared_ptr<const render::SonarPingSpec> ping,
                            double frequency_hz, std::uint64_t noise_key, render::BeamEchoSink sink,
                            render::SonarWater* water) {
  if (context.model == nullptr || context.ocean == nullptr) {
    throw std::logic_error("sonar capture: no model or ocean in the capture context");
  }
  if (!ping) throw std::logic_error("sonar capture: the sonar has no ping spec (a failed read)");
  const Eigen::Isometry3d X_WS = context.X_WS();
  *water = sonar_water(*context.ocean, X_WS.translation(), frequency_hz, context.time,
                       context.model->world.acoustics.surface_backscatter_db);
  const std::int32_t own_body = static_cast<std::int32_t>(context.own_ray_body());
  return [ping = std::move(ping), X_WS, own_body, w = *water, backscatter = model_backscatter(*context.model), noise_key,
          index = context.step_count, sink = std::move(sink)](const geometry::EmbreeScene& scene, const ParallelFor& parallel) {
    render::ping(scene, *ping, X_WS, own_body, w, backscatter, noise_key, index, parallel, sink);
  };
}

}  // namespace hadal::sensors
