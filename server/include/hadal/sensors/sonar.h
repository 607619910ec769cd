// What the sonar kinds share (docs/ARCHITECTURE.md, "Sonars"): the forward-looking sonar
// (sensors/fls_sensor.h), the multibeam (sensors/multibeam_sensor.h) and the side-scan sonar
// (sensors/sidescan_sensor.h) each ping through render/sonar.h on the ray-cast workers; this module reads
// their common YAML keys, finds the water at the sonar, the backscatter of what a ray hit, runs a ping as a
// capture's scene work and encodes intensities as image samples.
//
// Their common keys are declared once in sensors/sonar_keys.h.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/render/sonar.h"
#include "hadal/sensors/sensor_kind.h"
#include "hadal/sensors/sonar_spec.h"

namespace hadal::physics {
class Ocean;
}
namespace marine_acoustic_msgs::msg {
class PingInfo;
class SonarImageData;
}  // namespace marine_acoustic_msgs::msg

namespace hadal::sensors {

// The key of a sonar's echo streams (jitter, speckle, noise): channel "echo" of the sensor.
std::uint64_t sonar_noise_key(const SensorSetup& setup);
// The ping spec's range window, bins, levels, noise switches, spreading and TVG from `acoustics`.
void set_acoustics(const SonarAcoustics& acoustics, render::SonarPingSpec& ping);

// SonarImageData: little-endian, dtype UINT8 or FLOAT32, beam_count, data.
void fill_sonar_image_data(const SonarImageEncoding& encoding, std::uint32_t beam_count,
                           const std::vector<std::uint8_t>& data, marine_acoustic_msgs::msg::SonarImageData& out);
// PingInfo: frequency, sound speed, and per beam its -3 dB widths (tx: across the fan, rx: in the fan).
void fill_ping_info(const SonarAcoustics& acoustics, double sound_speed_m_per_s, const render::SonarPingSpec& ping,
                    marine_acoustic_msgs::msg::PingInfo& out);

// The water at the sonar's position p_WS at sim time t: sound speed and absorption at the sonar's frequency at its
// depth (physics/ocean.h; straight rays, the water at the sonar for the whole path), and the sea surface over it (its
// tangent plane, tilted by waves) as a reflector of Lambert's mu surface_backscatter_db.
render::SonarWater sonar_water(const physics::Ocean& ocean, const Eigen::Vector3d& p_WS, double frequency_hz, double t,
                               double surface_backscatter_db);

// Lambert's mu (linear) of each hit from the model: the seabed's world.acoustics.seabed_backscatter_db, a
// link's appearance.backscatter_db if given, else world.acoustics.vehicle_backscatter_db.
render::BackscatterOfHits model_backscatter(const Model& model);

// One ping at the capture's snapshot as scene work: S at X_WS, its own vehicle transparent, the water at S
// (written to *water before the work is returned), the model's backscatter, streams keyed by `noise_key`
// and the capture's step; each beam's echo goes to `sink` on the workers.
CaptureWork sonar_ping_work(const CaptureContext& context, std::shared_ptr<const render::SonarPingSpec> ping,
                            double frequency_hz, std::uint64_t noise_key, render::BeamEchoSink sink,
                            render::SonarWater* water);

}  // namespace hadal::sensors
