#include "hadal/sensors/fls_sensor.h"

#include <marine_acoustic_msgs.h>
#include <marine_acoustic_msgsPubSubTypes.h>
#include <sensor_msgs.h>

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

const config::Presets<FlsFigures>& fls_presets() {
  // The makers' figures as cited; the window (max_range, bins) and rate are a working setting within the
  // product's limits (a ping's two-way travel time bounds the rate: sensors/sonar.h).
  static const config::Presets<FlsFigures> presets = {
      {.id = "oculus_m750d",
       .product = "Blueprint Subsea Oculus M750d, 750 kHz mode",
       .source = "Oculus M-series user manual; liboculus Constants.h (Oculus_M750d): 512 beams over 130 deg, "
                 "1.0 deg x 20 deg beams, 120 m maximum range. Window 40 m",
       .figures = {.frequency_hz = 750e3, .beams = 512, .fov_deg = 130.0, .beam_width_deg = 1.0,
                   .vertical_aperture_deg = 20.0, .max_range = 40.0, .bins = 512, .rate_hz = 10.0}},
      {.id = "oculus_m750d_1200khz",
       .product = "Blueprint Subsea Oculus M750d, 1.2 MHz mode",
       .source = "liboculus: 0.6 deg x 12 deg beams, 40 m maximum; the 70 deg field of view is the maker's data "
                 "sheet figure (not re-checked here). Window 20 m",
       .figures = {.frequency_hz = 1.2e6, .beams = 512, .fov_deg = 70.0, .beam_width_deg = 0.6,
                   .vertical_aperture_deg = 12.0, .max_range = 20.0, .bins = 512, .rate_hz = 15.0}},
      {.id = "gemini_720is",
       .product = "Tritech Gemini 720is",
       .source = "product manual 0703-SOM-00002, sections 1.1 and 2.1: 720 kHz, 120 deg x 20 deg, 1.0 deg "
                 "acoustic beam width, up to 30 Hz; 256 beams. Window 50 m",
       .figures = {.frequency_hz = 720e3, .beams = 256, .fov_deg = 120.0, .beam_width_deg = 1.0,
                   .vertical_aperture_deg = 20.0, .max_range = 50.0, .bins = 512, .rate_hz = 10.0}},
      {.id = "aris_explorer_3000",
       .product = "Sound Metrics ARIS Explorer 3000, 3 MHz mode",
       .source = "Ocean Networks Canada, ARIS sonar data: 128 beams over 28 deg x 14 deg; beam width 0.25 deg. "
                 "Window 5 m",
       .figures = {.frequency_hz = 3.0e6, .beams = 128, .fov_deg = 28.0, .beam_width_deg = 0.25,
                   .vertical_aperture_deg = 14.0, .max_range = 5.0, .bins = 512, .rate_hz = 15.0}},
  };
  return presets;
}

void FlsFigures::apply(FlsSpec& spec) const {
  spec.acoustics.frequency_hz = frequency_hz;
  spec.beams = beams;
  spec.fov = fov_deg * kDegToRad;
  spec.beam_width = beam_width_deg * kDegToRad;
  spec.vertical_aperture = vertical_aperture_deg * kDegToRad;
  spec.acoustics.max_range = max_range;
  spec.acoustics.bins = bins;
}

double FlsSensor::beam_azimuth(const Spec& spec, int k) { return -0.5 * spec.fov + (k + 0.5) * spec.fov / spec.beams; }

void FlsSensor::make_ping(Spec& spec) {
  auto ping = std::make_shared<render::SonarPingSpec>();
  set_acoustics(spec.acoustics, *ping);
  ping->beams = render::fan_beams(spec.beams, spec.fov, spec.beam_width, spec.vertical_aperture);
  ping->rays_u = spec.azimuth_rays;
  ping->rays_v = (spec.rays_per_cell * spec.acoustics.bins + spec.azimuth_rays - 1) / spec.azimuth_rays;
  ping->validate();
  spec.ping = std::move(ping);
}

SensorReach FlsSensor::reach(const Spec& spec) { return {spec.acoustics.max_range, 0.5 * spec.fov}; }

const config::KeyTable<FlsSensor::Spec, SensorReader>& FlsSensor::keys() {
  return config::declare_keys<Spec, SensorReader>(Spec{}, [](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].fls", "a forward-looking imaging sonar: a fan of beams in S's x-y plane");
    t.preset("forward-looking sonar", fls_presets(), apply_rated_preset<Spec, FlsFigures>).doc(kRatedPresetDoc);
    t.number("beams", &Spec::beams).range(Range::closed(1.0, 4096.0)).doc("beams over the fan");
    t.number("fov_deg", &Spec::fov).degrees().range(Range::left_open(0.0, 180.0)).doc("the fan's width");
    t.number("beam_width_deg", &Spec::beam_width).degrees().range(Range::left_open(0.0, 30.0)).doc("a beam's width in the fan");
    t.number("vertical_aperture_deg", &Spec::vertical_aperture).degrees().range(Range::left_open(0.0, 90.0))
        .doc("a beam's height across the fan");
    t.number("azimuth_rays", &Spec::azimuth_rays).range(Range::closed(1.0, 64.0)).doc("rays across a beam");
    t.number("rays_per_cell", &Spec::rays_per_cell).range(Range::closed(1.0, 64.0)).doc("rays per beam and range bin");
    declare_sonar_acoustic_keys(t);
    declare_sonar_image_keys(t);
    declare_sonar_check(t, &FlsSensor::make_ping);
  });
}

FlsSensor::State FlsSensor::initial_state(const Spec& /*spec*/, const SensorSetup& setup) {
  State state;
  state.noise_key = sonar_noise_key(setup);
  return state;
}

CaptureWork FlsSensor::capture(const CaptureContext& context, const Spec& spec, const State& state, Capture& out) {
  const std::size_t beams = static_cast<std::size_t>(spec.beams), size = spec.encoding.bytes_per_sample();
  out.image.assign(beams * static_cast<std::size_t>(spec.acoustics.bins) * size, 0);
  render::BeamEchoSink sink = [&out, beams, size, encoding = spec.encoding](const render::BeamEcho& echo) {
    for (int b = 0; b < echo.bins; ++b) {
      encoding.encode(echo.intensity[b], &out.image[(static_cast<std::size_t>(b) * beams + static_cast<std::size_t>(echo.beam)) * size]);
    }
  };
  return sonar_ping_work(context, spec.ping, spec.acoustics.frequency_hz, state.noise_key, std::move(sink), &out.water);
}

void FlsSensor::deliver(const SampleContext& /*context*/, const Spec& /*spec*/, State& state, Capture&& capture) {
  state.image = std::move(capture.image);
  state.sound_speed_m_per_s = capture.water.sound_speed_m_per_s;
}

void FlsSensor::ImageTopic::fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  fill_ping_info(spec.acoustics, state.sound_speed_m_per_s, *spec.ping, msg.ping_info());
  msg.beam_directions().resize(static_cast<std::size_t>(spec.beams));
  for (int k = 0; k < spec.beams; ++k) {
    const double phi = beam_azimuth(spec, k);
    geometry_msgs::msg::Vector3& d = msg.beam_directions()[static_cast<std::size_t>(k)];
    d.x(0.0);
    d.y(-std::sin(phi));
    d.z(std::cos(phi));
  }
  msg.ranges().resize(static_cast<std::size_t>(spec.acoustics.bins));
  for (int b = 0; b < spec.acoustics.bins; ++b) msg.ranges()[static_cast<std::size_t>(b)] = static_cast<float>(spec.ping->bin_centre_m(b));
  fill_sonar_image_data(spec.encoding, static_cast<std::uint32_t>(spec.beams), state.image, msg.image());
}

FlsSensor::FanImage FlsSensor::fan_image(const Spec& spec, const std::vector<std::uint8_t>& samples, int height) {
  constexpr int kMargin = 10;
  FanImage fan;
  fan.height = std::max(height, 2 * kMargin + 1);
  const double max_range = spec.acoustics.max_range, half = 0.5 * spec.fov;
  fan.px_per_m = (fan.height - 2 * kMargin) / max_range;
  fan.width = static_cast<int>(std::ceil(2.0 * max_range * std::sin(std::min(half, kPi / 2.0)) * fan.px_per_m)) + 2 * kMargin;
  fan.apex_u = fan.width / 2;
  fan.apex_v = fan.height - kMargin;
  fan.grey.assign(static_cast<std::size_t>(fan.width) * static_cast<std::size_t>(fan.height), 0);
  const auto beams = static_cast<std::size_t>(spec.beams);
  const std::size_t size = spec.encoding.bytes_per_sample();
  if (samples.size() != beams * static_cast<std::size_t>(spec.acoustics.bins) * size) return fan;
  for (int v = 0; v < fan.height; ++v) {
    for (int u = 0; u < fan.width; ++u) {
      // The pixel's centre: across (to starboard) and ahead [m].
      const double x = (u + 0.5 - fan.apex_u) / fan.px_per_m, y = (fan.apex_v - v - 0.5) / fan.px_per_m;
      const double azimuth = std::atan2(-x, y);  // about z_S from x_S: positive to port (the image's left)
      if (!(y > 0.0) || std::abs(azimuth) > half) continue;
      const int bin = spec.ping->bin_of(std::hypot(x, y));
      if (bin < 0) continue;
      const auto beam = static_cast<std::size_t>(
          std::clamp(static_cast<int>(std::floor((azimuth + half) / spec.fov * spec.beams)), 0, spec.beams - 1));
      fan.grey[static_cast<std::size_t>(v) * static_cast<std::size_t>(fan.width) + static_cast<std::size_t>(u)] =
          spec.encoding.grey(&samples[(static_cast<std::size_t>(bin) * beams + beam) * size]);
    }
  }
  return fan;
}

void FlsSensor::ImageTopic::fill_preview(const Spec& spec, const State& state, const MessageHeader& header,
                                         sensor_msgs::msg::Image& msg) {
  FanImage fan = fan_image(spec, state.image, kPreviewHeight);
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.height(static_cast<std::uint32_t>(fan.height));
  msg.width(static_cast<std::uint32_t>(fan.width));
  msg.encoding("mono8");
  msg.is_bigendian(0);
  msg.step(static_cast<std::uint32_t>(fan.width));
  msg.data() = std::move(fan.grey);
}

}  // namespace hadal::sensors
