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

namespace {

// The sound speed bounding seawater's from above, for the ping-rate check [m/s].
constexpr double kMaxSoundSpeed = 1600.0;

}  // namespace

const std::vector<std::string>& sonar_acoustic_keys() {
  static const std::vector<std::string> keys = {
      "frequency_hz",  "min_range", "max_range",      "bins",         "source_level_db",        "noise_level_db",
      "speckle",       "receiver_noise", "spreading_db_per_decade", "tvg_db_per_decade", "tvg_absorption"};
  return keys;
}

bool read_sonar_acoustics(const SensorReader& reader, SonarAcoustics& a) {
  const MapReader& map = reader.map;
  map.read_number("frequency_hz", Need::kOptional, Range::closed(1e3, 5e6), &a.frequency_hz);
  bool window = map.read_number("min_range", Need::kOptional, Range::non_negative(), &a.min_range) &
                map.read_number("max_range", Need::kOptional, Range::closed(0.1, 10000.0), &a.max_range);
  if (window && !(a.max_range > a.min_range)) {
    window = false;
    map.error_at_key(map.has("max_range") ? "max_range" : "min_range",
                     "max_range (" + format_number(a.max_range) + " m) must exceed min_range (" +
                         format_number(a.min_range) + " m)");
  }
  map.read_whole_number("bins", Need::kOptional, Range::closed(1.0, 65536.0), &a.bins);
  map.read_number("source_level_db", Need::kOptional, Range::closed(100.0, 260.0), &a.source_level_db);
  map.read_number("noise_level_db", Need::kOptional, Range::closed(-50.0, 200.0), &a.noise_level_db);
  map.read_bool("speckle", Need::kOptional, &a.speckle);
  map.read_bool("receiver_noise", Need::kOptional, &a.receiver_noise);
  map.read_number("spreading_db_per_decade", Need::kOptional, Range::closed(0.0, 40.0), &a.spreading_db_per_decade);
  map.read_number("tvg_db_per_decade", Need::kOptional, Range::closed(0.0, 60.0), &a.tvg_db_per_decade);
  map.read_bool("tvg_absorption", Need::kOptional, &a.tvg_absorption);
  const double limit_hz = kMaxSoundSpeed / (2.0 * a.max_range);
  if (window && reader.rate_hz > limit_hz) {
    const std::string message = "a ping every " + format_number(1.0 / reader.rate_hz) + " s (rate_hz " +
                                format_number(reader.rate_hz) + ") is shorter than the echoes' two-way travel time over " +
                                "max_range " + format_number(a.max_range) + " m: rate_hz must be <= " +
                                format_number(limit_hz) + " (1600 m/s / (2 max_range))";
    if (map.has("rate_hz")) {
      map.error_at_key("rate_hz", message);
    } else if (map.has("max_range")) {
      map.error_at_key("max_range", message);
    } else {
      map.value().error(message);
    }
  }
  return window;
}

int read_preset_index(const MapReader& map, const std::vector<std::string_view>& names, const std::string& what) {
  if (!map.has("preset")) return -1;
  std::string name;
  if (!map.read_string("preset", Need::kRequired, &name)) return -1;
  std::vector<std::string> listed;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<int>(i);
    listed.push_back(config::quoted(std::string(names[i])));
  }
  map.error_at_key("preset", "unknown " + what + " preset " + config::quoted(name) + " (presets: " +
                                 config::join_names(listed) + ")");
  return -1;
}

void read_sonar_common(const SensorReader& reader, SonarAcoustics& acoustics, SonarImageEncoding* encoding,
                       const std::function<void()>& make_ping) {
  const bool window = read_sonar_acoustics(reader, acoustics);
  if (encoding != nullptr) read_sonar_image_encoding(reader.map, *encoding);
  if (!window) return;
  try {
    make_ping();
  } catch (const std::invalid_argument& e) {
    reader.map.value().error(std::string("unusable sonar: ") + e.what());
  }
}

std::uint64_t sonar_noise_key(const SensorSetup& setup) {
  return channel_key(setup.seed, setup.vehicle, setup.sensor, "echo");
}

void set_acoustics(const SonarAcoustics& a, render::SonarPingSpec& ping) {
  ping.min_range_m = a.min_range;
  ping.max_range_m = a.max_range;
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

const std::vector<std::string>& sonar_image_keys() {
  static const std::vector<std::string> keys = {"image_dtype", "display_min_db", "display_max_db"};
  return keys;
}

void read_sonar_image_encoding(const MapReader& map, SonarImageEncoding& encoding) {
  map.read_choice("image_dtype", Need::kOptional, {{"uint8", false}, {"float32", true}}, &encoding.float32);
  if (map.read_number("display_min_db", Need::kOptional, Range::closed(-100.0, 300.0), &encoding.display_min_db) &
          map.read_number("display_max_db", Need::kOptional, Range::closed(-100.0, 300.0), &encoding.display_max_db) &&
      !(encoding.display_max_db > encoding.display_min_db)) {
    map.error_at_key(map.has("display_max_db") ? "display_max_db" : "display_min_db",
                     "display_max_db (" + format_number(encoding.display_max_db) + ") must exceed display_min_db (" +
                         format_number(encoding.display_min_db) + ")");
  }
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

render::SonarWater sonar_water(const physics::Ocean& ocean, const Eigen::Vector3d& p_WS, double frequency_hz) {
  const double depth = std::max(ocean.depth(p_WS.z()), 0.0);
  render::SonarWater water;
  water.sound_speed_m_per_s = ocean.sound_speed(depth);
  water.absorption_db_per_m = ocean.sound_absorption_db_per_m(depth, frequency_hz);
  return water;
}

render::BackscatterOfHits model_backscatter(const Model& model) {
  const AcousticsSpec& acoustics = model.world.acoustics;
  const float seabed = static_cast<float>(std::pow(10.0, acoustics.seabed_backscatter_db / 10.0));
  const float hull = static_cast<float>(std::pow(10.0, acoustics.vehicle_backscatter_db / 10.0));
  // Per vehicle and link: its appearance's backscatter if given, else the hulls'.
  std::vector<std::vector<float>> links(model.vehicles.size());
  for (std::size_t v = 0; v < model.vehicles.size(); ++v) {
    for (const LinkSpec& link : model.vehicles[v].links) {
      const std::optional<double>& db = link.appearance.backscatter_db;
      links[v].push_back(db ? static_cast<float>(std::pow(10.0, *db / 10.0)) : hull);
    }
  }
  return [seabed, hull, links = std::move(links)](const geometry::RayHits& hits, std::size_t count, float* mu) {
    for (std::size_t i = 0; i < count; ++i) {
      const std::int32_t body = hits.body[i];
      if (body == geometry::kNoHit) {
        mu[i] = 0.0f;
      } else if (body < 0 || hits.material[i] == geometry::kSeabedMaterial) {
        mu[i] = seabed;
      } else {
        const auto b = static_cast<std::size_t>(body);
        const std::size_t link = geometry::link_of_material(hits.material[i] - geometry::kVehicleMaterial);
        mu[i] = b < links.size() && hits.material[i] >= geometry::kVehicleMaterial && link < links[b].size()
                    ? links[b][link]
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
  *water = sonar_water(*context.ocean, X_WS.translation(), frequency_hz);
  const std::int32_t own_body = static_cast<std::int32_t>(context.vehicle_index);
  return [ping = std::move(ping), X_WS, own_body, w = *water, backscatter = model_backscatter(*context.model), noise_key,
          index = context.step_count, sink = std::move(sink)](const geometry::EmbreeScene& scene, const ParallelFor& parallel) {
    render::ping(scene, *ping, X_WS, own_body, w, backscatter, noise_key, index, parallel, sink);
  };
}

}  // namespace hadal::sensors
