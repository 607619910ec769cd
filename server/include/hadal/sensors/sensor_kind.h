// The contract every sensor kind fulfils, and the contexts each layer hands to it (docs/ARCHITECTURE.md,
// "Sensor kinds", with a worked example of adding one).
//
// A kind is a struct K in sensors/<kind>_sensor.{h,cc} with
//
//   static constexpr std::string_view kType;   the YAML `type:` ("pressure") and its name in messages
//   static constexpr bool kCastsRays;          samples by casting rays into the world scene
//   static constexpr bool kCaptures;           captured asynchronously (below) instead of sample()
//   using Message, PubSubType;                 its ROS 2 message: the fastddsgen class and its type support
//   struct Spec { using Kind = K; ... };       immutable, from YAML, SI (the model holds it)
//   struct State { ... };                      what evolves: noise streams, biases, the last sample
//   static const config::KeyTable<Spec, SensorReader>& keys();  its YAML keys besides the common ones,
//                                                   each declared once (config/key_table.h): they read
//                                                   the Spec, strictly, errors at file:line:col
//   static State initial_state(const Spec&, const SensorSetup&);  turn-on draws of its noise
//   static void sample(const SampleContext&, const Spec&, State&);  the ideal value, then the noise
//   static void fill_message(const Spec&, const State&, const MessageHeader&, Message&);
//   static SensorReach reach(const Spec&);                       what a monitor draws of it
//
// and one line in sensors/sensor_kinds.h. Every layer dispatches once over that list with std::visit
// (the loader by `type:`, the simulation per sample, the DDS endpoints per topic), so nothing else
// names a kind. Common to every sensor (SensorSpec in core/model.h): name, link, pose X_LS, rate_hz,
// frame_id; the simulation decides when a sample is due and stamps it.
//
// Asynchronous capture (kCaptures = true), for ray-cast sensors too expensive for the stepping thread
// (docs/ARCHITECTURE.md, "Deterministic capture"): at each sample time the simulation records the
// snapshot (every body's pose) in the sensor's state and hands the kind's rays to the ray-cast workers;
// at capture time + latency_s (SensorSpec) it waits for the hits (or, in real time, drops a late capture)
// and lets the kind turn them into the sample, stamped with the capture time. Such a kind has, instead
// of sample(),
//   static geometry::RayBatch capture_rays(const CaptureContext&, const Spec&);   the snapshot's rays
//   static void deliver(const SampleContext&, const Spec&, State&, const geometry::RayHits&);
// Both are functions of their inputs only, so a restored state re-casts its pending captures and
// continues bit-identically.
// A captured kind whose capture is more than one batch of rays (a camera: shadow rays, shading) defines
// instead of capture_rays() and deliver(hits)
//   using Capture = ...;                       what the workers make (a frame)
//   static CaptureWork capture(const CaptureContext&, const Spec&, const State&, Capture& out);
//   static void deliver(const SampleContext&, const Spec&, State&, Capture&&);
// capture() returns the scene work (geometry/raycast_service.h) that fills `out` on the workers; it may
// read the State's constants (noise keys) but nothing that delivery changes.
//
// Samples that are events (an acoustic fix arrives when the transponder's reply does, not on a rate's tick): a
// kind defines
//   static std::optional<double> advance(const SampleContext&, const Spec&, State&);
// which the simulation calls at the end of every step, before a sample due then. It follows what is in
// flight over the step just taken and returns the time of a sample that arrived within it (its stamp; the
// publisher sends it), or nullopt. Its sample(), on the rate's ticks, starts what the rate paces (an
// interrogation) and makes no sample itself.
//
// What an acoustic kind has in flight (a modem's packets, a USBL's or an LBL's interrogations and replies), for
// monitors that draw it (rt/hadal/acoustic_links): a kind may define
//   static void acoustic_links(const SampleContext&, const Spec&, const State&, std::vector<AcousticLink>&);
// appending one link per signal travelling from where it was emitted towards one receiver.
//
// Topics: a kind publishes rt/<vehicle>/<sensor> with Message and fill_message(), or, to publish
// several topics (a camera's image_raw, depth and camera_info), lists them as
//   using Topics = TopicList<T...>;
// where each T has kSuffix (the topic is rt/<vehicle>/<sensor>/<suffix>), Message, PubSubType and
//   static void fill(const Spec&, const State&, const MessageHeader&, Message&);
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <type_traits>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/config/preset.h"
#include "hadal/core/kind_list.h"
#include "hadal/core/parallel_for.h"

namespace hadal {
struct Model;
struct AcousticsSpec;
}
#include "hadal/config/key_table_fwd.h"
namespace hadal::geometry {
class EmbreeScene;
}
namespace hadal::physics {
class Ocean;
}
namespace hadal::sensors {

class AcousticChannel;
class GeomagneticModel;
class LocalEnuFrame;
struct GeodeticPosition;
struct SampleContext;  // sensors/sample_context.h

// What a kind's keys read with besides their map (the sensor entry, whose common keys are already read):
// the vehicle's actuators' names and kinds in VehicleSpec::actuators order (a sensor may refer to one;
// empty when the actuator list is unusable) and the sample rate, which a data-sheet preset may set when
// the file does not.
struct SensorReader {
  const std::vector<std::string>& actuator_names;
  const std::vector<std::string>& actuator_types;  // e.g. "thruster"
  bool rate_given = false;  // rate_hz appears in the file
  double& rate_hz;          // [Hz]; a kind may set it when !rate_given
};

// A `preset:` whose figures set the spec themselves (Figures::apply(Spec&)) and carry a sample rate
// (Figures::rate_hz), which they set unless the file gives rate_hz: the sonars'. Declared as
//   t.preset("multibeam", multibeam_presets(), apply_rated_preset<Spec, MultibeamFigures>).doc(kRatedPresetDoc);
template <class Spec, class Figures>
void apply_rated_preset(Spec& spec, const config::Preset<Figures>& preset, SensorReader& reader) {
  preset.figures.apply(spec);
  if (!reader.rate_given) reader.rate_hz = preset.figures.rate_hz;
}
inline constexpr const char* kRatedPresetDoc =
    "a product (table below): sets the keys the file does not give, and rate_hz unless given";

// Data shared by every sensor of a simulation that needs it, made on first use: the World Magnetic
// Model, W as a local East-North-Up frame on WGS84 (world.origin; sensors/geodesy.h) and the acoustic
// channel (sensors/acoustic_channel.h).
class SensorEnvironment {
 public:
  explicit SensorEnvironment(const GeodeticPosition& origin);
  ~SensorEnvironment();
  SensorEnvironment(const SensorEnvironment&) = delete;
  SensorEnvironment& operator=(const SensorEnvironment&) = delete;

  // WMM2025 (server/data/WMM2025.COF), loaded on the first call; throws std::runtime_error if the
  // file cannot be read.
  const GeomagneticModel& geomagnetic();
  const LocalEnuFrame& frame_W() const { return *frame_W_; }
  // The acoustic channel of this water and these acoustics, made on the first call (its slowness table
  // takes a few milliseconds); later calls return it whatever they pass.
  const AcousticChannel& acoustic_channel(const physics::Ocean& ocean, const AcousticsSpec& acoustics);

 private:
  std::unique_ptr<GeomagneticModel> geomagnetic_;
  std::unique_ptr<AcousticChannel> acoustic_channel_;
  std::unique_ptr<LocalEnuFrame> frame_W_;
};

// What initial_state() gets: the names that key the sensor's random streams (noise.h channel_key), its
// sample period and the shared environment.
struct SensorSetup {
  std::uint64_t seed = 0;  // world.seed
  std::string_view vehicle;
  std::string_view sensor;
  double period = 0.0;  // 1 / rate_hz [s]
  SensorEnvironment& environment;
};

// What capture_rays() / capture() get: the snapshot of the capture, the model (lights, optics) and the
// ocean (a sonar's sound speed and absorption).
struct CaptureContext {
  double time = 0.0;  // sim time of the snapshot [s]
  std::uint64_t step_count = 0;
  // Every ray body's pose at the snapshot (geometry/world_scene.h: the vehicles' X_WB in SimState order, then
  // the moving bodies' "B as the body carries it").
  const std::vector<Eigen::Isometry3d>& X_WB;
  int vehicle_index = 0;                       // the sensor's vehicle
  const Eigen::Isometry3d& X_BS;               // mounting pose of S in B (the vehicle's B) at the snapshot
  const Model* model = nullptr;               // the simulation's model (a camera's lights and optics)
  const physics::Ocean* ocean = nullptr;       // the simulation's water column
  int ray_body = -1;  // the ray body the sensor is on, which its rays pass through; -1: vehicle_index's base

  Eigen::Isometry3d X_WS() const { return X_WB[static_cast<std::size_t>(vehicle_index)] * X_BS; }
  int own_ray_body() const { return ray_body >= 0 ? ray_body : vehicle_index; }
};

// How far a sensor looks along x_S and the half angle of its cone, for monitors that draw it
// (rt/hadal/scene); zeros: nothing to draw (a pressure sensor; a side-scan, which looks to both sides).
struct SensorReach {
  double range_m = 0.0;
  double half_angle_rad = 0.0;
};

// A signal in the water (above): from its emitter's position when it left, towards a receiver's position now.
struct AcousticLink {
  enum class Kind : std::uint8_t { kPacket = 0, kInterrogation = 1, kReply = 2 };
  Kind kind = Kind::kPacket;
  std::string source;  // "<vehicle>/<sensor>", a vehicle's transponder ("<vehicle>") or a beacon's name
  std::string target;  // the same for the receiver
  Eigen::Vector3d p_Wemit = Eigen::Vector3d::Zero();    // [m]
  Eigen::Vector3d p_Wtarget = Eigen::Vector3d::Zero();  // [m]
  double emit_time = 0.0;    // when it left [s]
  double duration = 0.0;     // how long it lasts (a packet's; 0 for a ping) [s]
  double sound_speed = 0.0;  // harmonic mean along the path [m/s] (the simulation fills it)
};

// Whether a kind reports what it has in flight (acoustic_links(), above).
template <class Kind, class = void>
struct HasAcousticLinks : std::false_type {};
template <class Kind>
struct HasAcousticLinks<Kind, std::void_t<decltype(&Kind::acoustic_links)>> : std::true_type {};

// The header fields of a sensor's message.
struct MessageHeader {
  double stamp = 0.0;  // sim time of the sample [s]
  const std::string& frame_id;
  double rate_hz = 0.0;
};

// A kind that measures the joint of its link (kOnJoint = true: the force/torque sensor) must be on a link
// that hangs on a moving joint; other kinds are refused on moving links.
template <class K, class = void>
struct OnJoint : std::false_type {};
template <class K>
struct OnJoint<K, std::void_t<decltype(K::kOnJoint)>> : std::bool_constant<K::kOnJoint> {};

// A kind that reads the motion of its vehicle's body (its velocity and accelerations: the IMU, the DVL) sets
// kOnMovingLink = false: it may not be on a link that moves on a joint (the body's motion is not the
// link's). Every other kind may: its mounting follows its link (Simulation::sample_sensors).
template <class K, class = void>
struct OnMovingLink : std::true_type {};
template <class K>
struct OnMovingLink<K, std::void_t<decltype(K::kOnMovingLink)>> : std::bool_constant<K::kOnMovingLink> {};

// Kind<Spec>: the kind a spec belongs to.
template <class Spec>
using KindOf = typename Spec::Kind;

// Scene work of a capture (RaycastService::SceneWork's signature): run on the workers with the scene
// posed at the snapshot; `parallel` spreads a loop over them.
using CaptureWork = std::function<void(const geometry::EmbreeScene& scene, const ParallelFor& parallel)>;

// A kind's topics (above): TopicList<T...>::for_each(f) calls f(KindTag<T>{}, index) in order.
template <class... Topics>
struct TopicList {
  static constexpr std::size_t kSize = sizeof...(Topics);
  template <class F>
  static void for_each(F&& f) {
    std::size_t index = 0;
    (f(KindTag<Topics>{}, index++), ...);
  }
};

// The one topic of a kind without a Topics list.
template <class Kind>
struct SingleTopic {
  static constexpr std::string_view kSuffix = "";
  using Message = typename Kind::Message;
  using PubSubType = typename Kind::PubSubType;
  template <class Spec, class State>
  static void fill(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
    Kind::fill_message(spec, state, header, msg);
  }
};

template <class Kind, class = void>
struct TopicsOfKind {
  using type = TopicList<SingleTopic<Kind>>;
};
template <class Kind>
struct TopicsOfKind<Kind, std::void_t<typename Kind::Topics>> {
  using type = typename Kind::Topics;
};
template <class Kind>
using TopicsOf = typename TopicsOfKind<Kind>::type;

// Samples a topic's writer keeps for readers that have not acknowledged them yet (dds/topic_registry.h):
// enough that a lockstep burst (a 2 s step publishes 20 samples of a 10 Hz sensor within ~60 ms) is
// still there when a reader asks again for a sample the transport lost (after the next heartbeat,
// 0.1 s). A topic of large messages (camera images) declares a smaller kHistoryDepth.
inline constexpr int kSensorHistoryDepth = 100;
template <class Topic, class = void>
struct TopicHistoryDepth : std::integral_constant<int, kSensorHistoryDepth> {};
template <class Topic>
struct TopicHistoryDepth<Topic, std::void_t<decltype(Topic::kHistoryDepth)>>
    : std::integral_constant<int, Topic::kHistoryDepth> {};

// A topic may declare kPreview = true: the DDS endpoints then also offer rt/<vehicle>/<sensor>/preview, a
// sensor_msgs/Image written at most 5 times per wall second and only while a reader is matched
// (dds/image_preview.h), for monitors such as hadal-viewer, so that watching a sensor does not cost the server
// its full-rate stream. The preview is the topic's 8-bit image at half resolution, or what the topic draws
// when it defines
//   static void fill_preview(const Spec&, const State&, const MessageHeader&, sensor_msgs::msg::Image&)
// (the forward-looking sonar's fan).
template <class Topic, class = void>
struct TopicHasPreview : std::false_type {};
template <class Topic>
struct TopicHasPreview<Topic, std::void_t<decltype(Topic::kPreview)>> : std::bool_constant<Topic::kPreview> {};
template <class Topic, class = void>
struct TopicDrawsPreview : std::false_type {};
template <class Topic>
struct TopicDrawsPreview<Topic, std::void_t<decltype(&Topic::fill_preview)>> : std::true_type {};

// rt/hadal/monitor (dds/monitor.h) carries the latest sample of every topic but those that declare
// kInMonitor = false: topics of large messages (camera images), which a monitor reads as previews if at all.
template <class Topic, class = void>
struct TopicInMonitor : std::true_type {};
template <class Topic>
struct TopicInMonitor<Topic, std::void_t<decltype(Topic::kInMonitor)>> : std::bool_constant<Topic::kInMonitor> {};

// A kind that renders images declares kRendersImages = true (the camera): hadald --no-cameras leaves such
// sensors out.
template <class Kind, class = void>
struct RendersImages : std::false_type {};
template <class Kind>
struct RendersImages<Kind, std::void_t<decltype(Kind::kRendersImages)>> : std::bool_constant<Kind::kRendersImages> {};

// Whether a kind's samples are events (advance(), above).
template <class Kind, class = void>
struct SamplesByEvent : std::false_type {};
template <class Kind>
struct SamplesByEvent<Kind, std::void_t<decltype(&Kind::advance)>> : std::true_type {};

// Whether a captured kind captures by scene work (defines Capture) rather than by a ray batch.
template <class Kind, class = void>
struct CapturesByWork : std::false_type {};
template <class Kind>
struct CapturesByWork<Kind, std::void_t<typename Kind::Capture>> : std::true_type {};

}  // namespace hadal::sensors
