#include "hadal/sensors/multibeam_sensor.h"

#include <marine_acoustic_msgs.h>
#include <marine_acoustic_msgsPubSubTypes.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "hadal/config/yaml_reader.h"
#include "hadal/dds/time_msg.h"

namespace hadal::sensors {

using config::MapReader;
using config::Need;
using config::Range;

const std::vector<MultibeamPreset>& multibeam_presets() {
  // Figures from the makers' documents as cited; window and rate a working setting within them.
  static const std::vector<MultibeamPreset> presets = {
      // Teledyne RESON SeaBat 7125 at 400 kHz: 512 beams over 128 deg, 0.54 deg across x 1.1 deg along, up to
      // 50 pings/s, ~200 m typical range (CSUMB Seafloor Mapping Lab's 7125 description). Window 75 m, 2.5 cm.
      {"reson_seabat_7125_400khz", 400e3, 512, 128.0, 0.54, 1.1, 75.0, 3000, 10.0},
      // R2Sonic Sonic 2024 at 400 kHz: 256 beams, swath selectable 10-160 deg (here 130), ping rate up to 60 Hz
      // (operation manual V3.0, head commands); 0.5 deg across x 1 deg along at 400 kHz (maker's data sheet).
      // Window 50 m, 1.25 cm.
      {"r2sonic_2024", 400e3, 256, 130.0, 0.5, 1.0, 50.0, 4000, 15.0},
  };
  return presets;
}

SonarAcoustics MultibeamSensor::default_acoustics() {
  SonarAcoustics a;
  a.bins = 4000;
  a.source_level_db = 215.0;
  return a;
}

double MultibeamSensor::beam_angle(const Spec& spec, int k) { return -0.5 * spec.swath + (k + 0.5) * spec.swath / spec.beams; }

void MultibeamSensor::make_ping(Spec& spec) {
  auto ping = std::make_shared<render::SonarPingSpec>();
  set_acoustics(spec.acoustics, *ping);
  ping->beams = render::fan_beams(spec.beams, spec.swath, spec.across_beam_width, spec.along_beam_width);
  ping->rays_u = spec.rays_across;
  ping->rays_v = spec.rays_along;
  ping->validate();
  spec.ping = std::move(ping);
}

const std::vector<std::string>& MultibeamSensor::keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> k = {"preset",      "beams",      "swath_deg", "across_beam_width_deg", "along_beam_width_deg",
                                  "rays_across", "rays_along", "min_snr_db"};
    k.insert(k.end(), sonar_acoustic_keys().begin(), sonar_acoustic_keys().end());
    return k;
  }();
  return keys;
}

MultibeamSensor::Spec MultibeamSensor::read(const SensorReader& reader) {
  const MapReader& map = reader.map;
  Spec spec;
  std::vector<std::string_view> names;
  for (const MultibeamPreset& p : multibeam_presets()) names.push_back(p.name);
  const int index = read_preset_index(map, names, "multibeam");
  if (index >= 0) {
    const MultibeamPreset& preset = multibeam_presets()[static_cast<std::size_t>(index)];
    spec.acoustics.frequency_hz = preset.frequency_hz;
    spec.beams = preset.beams;
    spec.swath = preset.swath_deg * kDegToRad;
    spec.across_beam_width = preset.across_beam_width_deg * kDegToRad;
    spec.along_beam_width = preset.along_beam_width_deg * kDegToRad;
    spec.acoustics.max_range = preset.max_range_m;
    spec.acoustics.bins = preset.bins;
    if (!reader.rate_given) reader.rate_hz = preset.rate_hz;
  }
  map.read_whole_number("beams", Need::kOptional, Range::closed(1.0, 4096.0), &spec.beams);
  double swath_deg = spec.swath / kDegToRad, across_deg = spec.across_beam_width / kDegToRad,
         along_deg = spec.along_beam_width / kDegToRad;
  if (map.read_number("swath_deg", Need::kOptional, Range::left_open(0.0, 180.0), &swath_deg)) spec.swath = swath_deg * kDegToRad;
  if (map.read_number("across_beam_width_deg", Need::kOptional, Range::left_open(0.0, 30.0), &across_deg)) {
    spec.across_beam_width = across_deg * kDegToRad;
  }
  if (map.read_number("along_beam_width_deg", Need::kOptional, Range::left_open(0.0, 30.0), &along_deg)) {
    spec.along_beam_width = along_deg * kDegToRad;
  }
  map.read_whole_number("rays_across", Need::kOptional, Range::closed(1.0, 1024.0), &spec.rays_across);
  map.read_whole_number("rays_along", Need::kOptional, Range::closed(1.0, 256.0), &spec.rays_along);
  map.read_number("min_snr_db", Need::kOptional, Range::closed(0.0, 100.0), &spec.min_snr_db);
  read_sonar_common(reader, spec.acoustics, nullptr, [&spec] { make_ping(spec); });
  return spec;
}

MultibeamSensor::State MultibeamSensor::initial_state(const Spec& spec, const SensorSetup& setup) {
  State state;
  state.noise_key = sonar_noise_key(setup);
  state.last.range_m.assign(static_cast<std::size_t>(spec.beams), std::numeric_limits<double>::quiet_NaN());
  state.last.intensity.assign(static_cast<std::size_t>(spec.beams), 0.0f);
  return state;
}

CaptureWork MultibeamSensor::capture(const CaptureContext& context, const Spec& spec, const State& state, Capture& out) {
  out.detections.range_m.assign(static_cast<std::size_t>(spec.beams), std::numeric_limits<double>::quiet_NaN());
  out.detections.intensity.assign(static_cast<std::size_t>(spec.beams), 0.0f);
  render::BeamEchoSink sink = [&out, ping = spec.ping, min_snr_db = spec.min_snr_db](const render::BeamEcho& echo) {
    const render::BottomDetection bottom = render::detect_bottom(*ping, out.water, echo, min_snr_db);
    const auto k = static_cast<std::size_t>(echo.beam);
    out.detections.range_m[k] = bottom.range_m;
    out.detections.intensity[k] = static_cast<float>(bottom.intensity);
  };
  return sonar_ping_work(context, spec.ping, spec.acoustics.frequency_hz, state.noise_key, std::move(sink), &out.water);
}

void MultibeamSensor::deliver(const SampleContext& /*context*/, const Spec& /*spec*/, State& state, Capture&& capture) {
  state.last = std::move(capture.detections);
  state.sound_speed_m_per_s = capture.water.sound_speed_m_per_s;
}

void MultibeamSensor::fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
  namespace flag = marine_acoustic_msgs::msg::DetectionFlag_Constants;
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  fill_ping_info(spec.acoustics, state.sound_speed_m_per_s, *spec.ping, msg.ping_info());
  const std::size_t n = static_cast<std::size_t>(spec.beams);
  msg.flags().resize(n);
  msg.two_way_travel_times().resize(n);
  msg.tx_delays().assign(n, 0.0f);
  msg.intensities().resize(n);
  msg.tx_angles().assign(n, 0.0f);
  msg.rx_angles().resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double range = k < state.last.range_m.size() ? state.last.range_m[k] : std::numeric_limits<double>::quiet_NaN();
    const bool ok = std::isfinite(range) && state.sound_speed_m_per_s > 0.0;
    msg.flags()[k].flag(ok ? flag::DETECT_OK : flag::DETECT_BAD_SONAR);
    msg.two_way_travel_times()[k] = ok ? static_cast<float>(2.0 * range / state.sound_speed_m_per_s) : 0.0f;
    msg.intensities()[k] = k < state.last.intensity.size() ? state.last.intensity[k] : 0.0f;
    msg.rx_angles()[k] = static_cast<float>(-beam_angle(spec, static_cast<int>(k)));
  }
}

}  // namespace hadal::sensors
