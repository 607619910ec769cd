#include "hadal/sensors/sidescan_sensor.h"

#include <marine_acoustic_msgs.h>
#include <marine_acoustic_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hadal/config/key_table.h"
#include "hadal/sensors/sonar_keys.h"
#include "hadal/dds/time_msg.h"

namespace hadal::sensors {

using config::MapReader;
using config::Need;
using config::Range;

const config::Presets<SidescanFigures>& sidescan_presets() {
  static const config::Presets<SidescanFigures> presets = {
      {.id = "edgetech_2205_410khz",
       .product = "EdgeTech 2205 AUV side-scan, 410 kHz",
       .source = "2205 technical and user's guide 0022175 rev A, sections 9 and 11.4: tri-frequency 120/410/850 kHz, "
                 "arrays at a nominal 24-27 deg look-down. Beam widths (0.5 deg x 50 deg) and 150 m per side are "
                 "typical of side-scans at this frequency, not the maker's figures",
       .figures = {.frequency_hz = 410e3, .horizontal_beam_width_deg = 0.5, .vertical_beam_width_deg = 50.0,
                   .depression_deg = 25.0, .max_range = 150.0, .bins = 3000, .rate_hz = 5.0}},
      {.id = "edgetech_2205_850khz",
       .product = "EdgeTech 2205 AUV side-scan, 850 kHz",
       .source = "as edgetech_2205_410khz; beam widths (0.25 deg x 50 deg) and 75 m per side typical of side-scans "
                 "at this frequency, not the maker's figures",
       .figures = {.frequency_hz = 850e3, .horizontal_beam_width_deg = 0.25, .vertical_beam_width_deg = 50.0,
                   .depression_deg = 25.0, .max_range = 75.0, .bins = 3000, .rate_hz = 10.0}},
  };
  return presets;
}

void SidescanFigures::apply(SidescanSpec& spec) const {
  spec.acoustics.frequency_hz = frequency_hz;
  spec.horizontal_beam_width = horizontal_beam_width_deg * kDegToRad;
  spec.vertical_beam_width = vertical_beam_width_deg * kDegToRad;
  spec.depression = depression_deg * kDegToRad;
  spec.acoustics.max_range = max_range;
  spec.acoustics.bins = bins;
}

SonarAcoustics sidescan_default_acoustics() {
  SonarAcoustics a;
  a.min_range = 0.0;  // a side-scan records from its transmission on: sample0 = 0, exact sample ranges
  a.max_range = 75.0;
  a.bins = 2000;
  return a;
}

void SidescanSensor::make_ping(Spec& spec) {
  auto ping = std::make_shared<render::SonarPingSpec>();
  set_acoustics(spec.acoustics, *ping);
  const double c = std::cos(spec.depression), s = std::sin(spec.depression);
  for (const double side : {1.0, -1.0}) {  // port (+y_S), then starboard
    render::SonarBeam beam;
    beam.axis_S = Eigen::Vector3d(0.0, side * c, -s);
    beam.u_S = Eigen::Vector3d::UnitX();
    beam.width_u_rad = spec.horizontal_beam_width;
    beam.width_v_rad = spec.vertical_beam_width;
    // The rays reach from the axis down to nadir (and as far up): the first bottom return, weak under the
    // pattern, comes from straight below, as in a real record.
    beam.sampled_v_rad = std::max(spec.vertical_beam_width, std::min(2.0 * (kPi / 2.0 - spec.depression), kPi));
    ping->beams.push_back(beam);
  }
  ping->rays_u = spec.along_rays;
  ping->rays_v = (spec.rays_per_cell * spec.acoustics.bins + spec.along_rays - 1) / spec.along_rays;
  ping->validate();
  spec.ping = std::move(ping);
}

SensorReach SidescanSensor::reach(const Spec& /*spec*/) { return {}; }

const config::KeyTable<SidescanSensor::Spec, SensorReader>& SidescanSensor::keys() {
  return config::declare_keys<Spec, SensorReader>(Spec{}, [](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].sidescan", "a side-scan sonar: a beam to either side of x_S");
    t.preset("side-scan sonar", sidescan_presets(), apply_rated_preset<Spec, SidescanFigures>).doc(kRatedPresetDoc);
    t.number("horizontal_beam_width_deg", &Spec::horizontal_beam_width).degrees().range(Range::left_open(0.0, 30.0))
        .doc("along track");
    t.number("vertical_beam_width_deg", &Spec::vertical_beam_width).degrees().range(Range::left_open(0.0, 120.0))
        .doc("across track");
    t.number("depression_deg", &Spec::depression).degrees().range(Range::closed(-30.0, 90.0))
        .doc("the beams' axes below S's x-y plane");
    t.number("along_rays", &Spec::along_rays).range(Range::closed(1.0, 64.0)).doc("rays along track");
    t.number("rays_per_cell", &Spec::rays_per_cell).range(Range::closed(1.0, 64.0)).doc("rays per range bin");
    declare_sonar_acoustic_keys(t);
    declare_sonar_image_keys(t);
    declare_sonar_check(t, &SidescanSensor::make_ping);
  });
}

SidescanSensor::State SidescanSensor::initial_state(const Spec& /*spec*/, const SensorSetup& setup) {
  State state;
  state.noise_key = sonar_noise_key(setup);
  return state;
}

CaptureWork SidescanSensor::capture(const CaptureContext& context, const Spec& spec, const State& state, Capture& out) {
  const std::size_t size = spec.encoding.bytes_per_sample(), bins = static_cast<std::size_t>(spec.acoustics.bins);
  out.port.assign(bins * size, 0);
  out.starboard.assign(bins * size, 0);
  render::BeamEchoSink sink = [&out, size, encoding = spec.encoding](const render::BeamEcho& echo) {
    std::vector<std::uint8_t>& side = echo.beam == kPort ? out.port : out.starboard;
    for (int b = 0; b < echo.bins; ++b) encoding.encode(echo.intensity[b], &side[static_cast<std::size_t>(b) * size]);
  };
  return sonar_ping_work(context, spec.ping, spec.acoustics.frequency_hz, state.noise_key, std::move(sink), &out.water);
}

void SidescanSensor::deliver(const SampleContext& /*context*/, const Spec& /*spec*/, State& state, Capture&& capture) {
  state.port = std::move(capture.port);
  state.starboard = std::move(capture.starboard);
  state.sound_speed_m_per_s = capture.water.sound_speed_m_per_s;
}

void SidescanSensor::fill_side(const Spec& spec, const State& state, const MessageHeader& header, int side,
                               marine_acoustic_msgs::msg::RawSonarImage& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  const SonarAcoustics& a = spec.acoustics;
  fill_ping_info(a, state.sound_speed_m_per_s, *spec.ping, msg.ping_info());
  // This side's widths only.
  const auto k = static_cast<std::size_t>(side);
  msg.ping_info().tx_beamwidths() = {msg.ping_info().tx_beamwidths()[k]};
  msg.ping_info().rx_beamwidths() = {msg.ping_info().rx_beamwidths()[k]};
  const double bin = spec.ping->bin_size_m();
  msg.sample_rate(static_cast<float>(state.sound_speed_m_per_s / (2.0 * bin)));
  msg.samples_per_beam(static_cast<std::uint32_t>(a.bins));
  msg.sample0(static_cast<std::uint32_t>(std::lround(a.min_range / bin)));
  msg.tx_delays() = {0.0f};
  msg.tx_angles() = {0.0f};
  const double across = 0.5 * kPi - spec.depression;
  msg.rx_angles() = {static_cast<float>(side == kPort ? -across : across)};
  fill_sonar_image_data(spec.encoding, 1, side == kPort ? state.port : state.starboard, msg.image());
}

void SidescanSensor::PortTopic::fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
  fill_side(spec, state, header, kPort, msg);
}

void SidescanSensor::StarboardTopic::fill(const Spec& spec, const State& state, const MessageHeader& header,
                                          Message& msg) {
  fill_side(spec, state, header, kStarboard, msg);
}

}  // namespace hadal::sensors
