#include "hadal/sensors/multibeam_sensor.h"

#include <marine_acoustic_msgs.h>
#include <marine_acoustic_msgsPubSubTypes.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "hadal/config/key_table.h"
#include "hadal/sensors/sonar_keys.h"
#include "hadal/dds/time_msg.h"

namespace hadal::sensors {

using config::MapReader;
using config::Need;
using config::Range;

const config::Presets<MultibeamFigures>& multibeam_presets() {
  // The makers' figures as cited; window and rate a working setting within them.
  static const config::Presets<MultibeamFigures> presets = {
      {.id = "reson_seabat_7125_400khz",
       .product = "Teledyne RESON SeaBat 7125 at 400 kHz",
       .source = "CSUMB Seafloor Mapping Lab's 7125 description: 512 beams over 128 deg, 0.54 deg across x 1.1 deg "
                 "along, up to 50 pings/s, ~200 m typical range. Window 75 m, 2.5 cm",
       .figures = {.frequency_hz = 400e3, .beams = 512, .swath_deg = 128.0, .across_beam_width_deg = 0.54,
                   .along_beam_width_deg = 1.1, .max_range = 75.0, .bins = 3000, .rate_hz = 10.0}},
      {.id = "r2sonic_2024",
       .product = "R2Sonic Sonic 2024 at 400 kHz",
       .source = "operation manual V3.0, head commands: 256 beams, swath selectable 10-160 deg (here 130), ping "
                 "rate up to 60 Hz; 0.5 deg across x 1 deg along at 400 kHz (maker's data sheet). Window 50 m, 1.25 cm",
       .figures = {.frequency_hz = 400e3, .beams = 256, .swath_deg = 130.0, .across_beam_width_deg = 0.5,
                   .along_beam_width_deg = 1.0, .max_range = 50.0, .bins = 4000, .rate_hz = 15.0}},
  };
  return presets;
}

void MultibeamFigures::apply(MultibeamSpec& spec) const {
  spec.acoustics.frequency_hz = frequency_hz;
  spec.beams = beams;
  spec.swath = swath_deg * kDegToRad;
  spec.across_beam_width = across_beam_width_deg * kDegToRad;
  spec.along_beam_width = along_beam_width_deg * kDegToRad;
  spec.acoustics.max_range = max_range;
  spec.acoustics.bins = bins;
}

SonarAcoustics multibeam_default_acoustics() {
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

SensorReach MultibeamSensor::reach(const Spec& spec) { return {spec.acoustics.max_range, 0.5 * spec.swath}; }

const config::KeyTable<MultibeamSensor::Spec, SensorReader>& MultibeamSensor::keys() {
  return config::declare_keys<Spec, SensorReader>(Spec{}, [](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].multibeam", "a multibeam echosounder: bottom detection per beam");
    t.preset("multibeam", multibeam_presets(), apply_rated_preset<Spec, MultibeamFigures>).doc(kRatedPresetDoc);
    t.number("beams", &Spec::beams).range(Range::closed(1.0, 4096.0)).doc("beams over the swath");
    t.number("swath_deg", &Spec::swath).degrees().range(Range::left_open(0.0, 180.0)).doc("the swath's width");
    t.number("across_beam_width_deg", &Spec::across_beam_width).degrees().range(Range::left_open(0.0, 30.0))
        .doc("a beam's width in the swath");
    t.number("along_beam_width_deg", &Spec::along_beam_width).degrees().range(Range::left_open(0.0, 30.0))
        .doc("a beam's width across it");
    t.number("rays_across", &Spec::rays_across).range(Range::closed(1.0, 1024.0))
        .doc("rays across a beam: enough that an oblique beam's footprint fills its bins");
    t.number("rays_along", &Spec::rays_along).range(Range::closed(1.0, 256.0)).doc("rays along a beam");
    t.number("min_snr_db", &Spec::min_snr_db).unit("dB").range(Range::closed(0.0, 100.0))
        .doc("a beam's profile smoothed over 5 bins must peak this far over the noise");
    declare_sonar_acoustic_keys(t);
    declare_sonar_check(t, &MultibeamSensor::make_ping);
  });
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
