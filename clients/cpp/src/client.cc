#include "hadal_client/client.h"

#include "hadal/config/security_block.h"
#include "hadal/dds/domain_id.h"
#include "hadal/dds/participant.h"
#include "hadal/dds/time_msg.h"
#include "hadal/dds/topic_names.h"
#include "hadal/dds/topic_registry.h"

#include <fastdds/dds/core/status/PublicationMatchedStatus.hpp>
#include <fastdds/dds/core/status/SubscriptionMatchedStatus.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <hadal_msgsPubSubTypes.h>
#include <marine_acoustic_msgsPubSubTypes.h>
#include <geometry_msgsPubSubTypes.h>
#include <nav_msgsPubSubTypes.h>
#include <rosgraph_msgsPubSubTypes.h>
#include <sensor_msgsPubSubTypes.h>
#include <std_msgsPubSubTypes.h>
#include <trajectory_msgsPubSubTypes.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <limits>
#include <map>
#include <mutex>
#include <random>
#include <cstdlib>
#include <stdexcept>
#include <thread>
#include <unistd.h>

namespace hadal {

namespace fdds = eprosima::fastdds::dds;

namespace {

constexpr int kHistoryDepth = 100;

// Calls `handle(msg)` for every valid sample a reader has.
template <class Msg, class Handler>
class TakeAllListener : public fdds::DataReaderListener {
 public:
  explicit TakeAllListener(Handler handler) : handler_(std::move(handler)) {}
  void on_data_available(fdds::DataReader* reader) override {
    Msg msg;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) handler_(msg);
    }
  }

 private:
  Handler handler_;
};

template <class Msg, class Handler>
std::unique_ptr<fdds::DataReaderListener> make_listener(Handler handler) {
  return std::make_unique<TakeAllListener<Msg, Handler>>(std::move(handler));
}

Odometry from_msg(const nav_msgs::msg::Odometry& m) {
  Odometry o;
  o.stamp = dds::from_time_msg(m.header().stamp());
  o.frame_id = m.header().frame_id();
  o.child_frame_id = m.child_frame_id();
  const auto& pose = m.pose().pose();
  o.p_WB = {pose.position().x(), pose.position().y(), pose.position().z()};
  o.q_WB = {pose.orientation().x(), pose.orientation().y(), pose.orientation().z(), pose.orientation().w()};
  const auto& twist = m.twist().twist();
  o.v_WB_B = {twist.linear().x(), twist.linear().y(), twist.linear().z()};
  o.w_WB_B = {twist.angular().x(), twist.angular().y(), twist.angular().z()};
  return o;
}

SimStatus from_msg(const hadal_msgs::msg::SimStatus& m) {
  SimStatus s;
  s.sim_time = m.sim_time();
  s.wall_time = m.wall_time();
  s.real_time_factor = m.real_time_factor();
  s.step_count = m.step_count();
  s.step_size = m.step_size();
  s.mode = static_cast<ServerMode>(m.mode());
  s.vehicle_names = m.vehicle_names();
  s.vehicle_faults = m.vehicle_faults();
  s.rejected_commands = m.rejected_commands();
  s.last_error = m.last_error();
  s.dropped_captures = m.dropped_captures();
  return s;
}

TrackStates from_msg(const hadal_msgs::msg::TrackState& m) {
  TrackStates t;
  t.stamp = dds::from_time_msg(m.header().stamp());
  t.names = m.name();
  t.setpoint = m.setpoint();
  t.belt_speed = m.belt_speed();
  t.sprocket_speed = m.sprocket_speed();
  t.motor_torque = m.motor_torque();
  t.current = m.current();
  t.power = m.power();
  t.load = m.load();
  t.command_source = m.command_source();
  return t;
}

FinStates from_msg(const hadal_msgs::msg::FinState& m) {
  FinStates f;
  f.stamp = dds::from_time_msg(m.header().stamp());
  f.names = m.name();
  f.setpoint = m.setpoint();
  f.angle = m.angle();
  f.attack_angle = m.attack_angle();
  f.lift = m.lift();
  f.drag = m.drag();
  f.command_source = m.command_source();
  return f;
}

BuoyancyEngineStates from_msg(const hadal_msgs::msg::BuoyancyEngineState& m) {
  BuoyancyEngineStates b;
  b.stamp = dds::from_time_msg(m.header().stamp());
  b.names = m.name();
  b.setpoint = m.setpoint();
  b.volume_change = m.volume_change();
  b.volume_rate = m.volume_rate();
  b.force = m.force();
  b.power = m.power();
  b.energy = m.energy();
  b.command_source = m.command_source();
  return b;
}

DropWeightStates from_msg(const hadal_msgs::msg::DropWeightState& m) {
  DropWeightStates d;
  d.stamp = dds::from_time_msg(m.header().stamp());
  d.names = m.name();
  d.attached.assign(m.attached().begin(), m.attached().end());
  d.reason = m.reason();
  d.release_time = m.release_time();
  d.force = m.force();
  d.command_source = m.command_source();
  return d;
}

JointStates from_msg(const sensor_msgs::msg::JointState& m) {
  JointStates j;
  j.stamp = dds::from_time_msg(m.header().stamp());
  j.frame_id = m.header().frame_id();
  j.names = m.name();
  j.position = m.position();
  j.velocity = m.velocity();
  j.effort = m.effort();
  return j;
}

ThrusterStates from_msg(const hadal_msgs::msg::ThrusterState& m) {
  ThrusterStates t;
  t.stamp = dds::from_time_msg(m.header().stamp());
  t.names = m.name();
  t.setpoint = m.setpoint();
  t.rotor_speed = m.rotor_speed();
  t.thrust = m.thrust();
  t.torque = m.torque();
  t.command_source = m.command_source();
  return t;
}

// The client header's named constants are the IDL's (the header cannot include generated types).
static_assert(NavSatFix::kStatusNoFix == sensor_msgs::msg::NavSatStatus_Constants::STATUS_NO_FIX);
static_assert(NavSatFix::kStatusFix == sensor_msgs::msg::NavSatStatus_Constants::STATUS_FIX);
static_assert(NavSatFix::kStatusSbasFix == sensor_msgs::msg::NavSatStatus_Constants::STATUS_SBAS_FIX);
static_assert(NavSatFix::kStatusGbasFix == sensor_msgs::msg::NavSatStatus_Constants::STATUS_GBAS_FIX);
static_assert(NavSatFix::kServiceGps == sensor_msgs::msg::NavSatStatus_Constants::SERVICE_GPS);
static_assert(NavSatFix::kServiceGlonass == sensor_msgs::msg::NavSatStatus_Constants::SERVICE_GLONASS);
static_assert(NavSatFix::kServiceCompass == sensor_msgs::msg::NavSatStatus_Constants::SERVICE_COMPASS);
static_assert(NavSatFix::kServiceGalileo == sensor_msgs::msg::NavSatStatus_Constants::SERVICE_GALILEO);
static_assert(NavSatFix::kCovarianceTypeUnknown == sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_UNKNOWN);
static_assert(NavSatFix::kCovarianceTypeApproximated ==
              sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_APPROXIMATED);
static_assert(NavSatFix::kCovarianceTypeDiagonalKnown ==
              sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_DIAGONAL_KNOWN);
static_assert(NavSatFix::kCovarianceTypeKnown == sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_KNOWN);
static_assert(Dvl::kVelocityModeBottomTrack == marine_acoustic_msgs::msg::Dvl_Constants::DVL_MODE_BOTTOM);
static_assert(Dvl::kVelocityModeWaterTrack == marine_acoustic_msgs::msg::Dvl_Constants::DVL_MODE_WATER);
static_assert(Dvl::kDvlTypePiston == marine_acoustic_msgs::msg::Dvl_Constants::DVL_TYPE_PISTON);
static_assert(Dvl::kDvlTypePhasedArray == marine_acoustic_msgs::msg::Dvl_Constants::DVL_TYPE_PHASED_ARRAY);
static_assert(Range::kUltrasound == sensor_msgs::msg::Range_Constants::ULTRASOUND);
static_assert(Range::kInfrared == sensor_msgs::msg::Range_Constants::INFRARED);

std::array<double, 3> to_array(const geometry_msgs::msg::Vector3& v) { return {v.x(), v.y(), v.z()}; }

// Element-wise copy of a fixed-size message array (float or double) into doubles.
template <class T, std::size_t N>
std::array<double, N> to_doubles(const std::array<T, N>& values) {
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = static_cast<double>(values[i]);
  return out;
}

Wrench from_msg(const geometry_msgs::msg::WrenchStamped& m) {
  Wrench w;
  w.stamp = dds::from_time_msg(m.header().stamp());
  w.frame_id = m.header().frame_id();
  w.force = to_array(m.wrench().force());
  w.torque = to_array(m.wrench().torque());
  return w;
}

MagneticField from_msg(const sensor_msgs::msg::MagneticField& m) {
  MagneticField f;
  f.stamp = dds::from_time_msg(m.header().stamp());
  f.frame_id = m.header().frame_id();
  f.magnetic_field = to_array(m.magnetic_field());
  f.magnetic_field_covariance = m.magnetic_field_covariance();
  return f;
}

NavSatFix from_msg(const sensor_msgs::msg::NavSatFix& m) {
  NavSatFix f;
  f.stamp = dds::from_time_msg(m.header().stamp());
  f.frame_id = m.header().frame_id();
  f.status = m.status().status();
  f.service = m.status().service();
  f.latitude = m.latitude();
  f.longitude = m.longitude();
  f.altitude = m.altitude();
  f.position_covariance = m.position_covariance();
  f.position_covariance_type = m.position_covariance_type();
  return f;
}

Dvl from_msg(const marine_acoustic_msgs::msg::Dvl& m) {
  Dvl d;
  d.stamp = dds::from_time_msg(m.header().stamp());
  d.frame_id = m.header().frame_id();
  d.velocity_mode = m.velocity_mode();
  d.dvl_type = m.dvl_type();
  d.velocity = to_array(m.velocity());
  d.velocity_covariance = m.velocity_covar();
  d.altitude = m.altitude();
  d.course_gnd = m.course_gnd();
  d.speed_gnd = m.speed_gnd();
  d.num_good_beams = m.num_good_beams();
  d.sound_speed = m.sound_speed();
  d.beam_ranges_valid = m.beam_ranges_valid();
  d.beam_velocities_valid = m.beam_velocities_valid();
  for (std::size_t b = 0; b < 4; ++b) d.beam_unit_vec[b] = to_array(m.beam_unit_vec()[b]);
  d.ranges = m.range();
  d.range_covariance = to_doubles(m.range_covar());
  d.beam_quality = to_doubles(m.beam_quality());
  d.beam_velocity = to_doubles(m.beam_velocity());
  d.beam_velocity_covariance = to_doubles(m.beam_velocity_covar());
  return d;
}

Range from_msg(const sensor_msgs::msg::Range& m) {
  Range r;
  r.stamp = dds::from_time_msg(m.header().stamp());
  r.frame_id = m.header().frame_id();
  r.radiation_type = m.radiation_type();
  r.field_of_view = m.field_of_view();
  r.min_range = m.min_range();
  r.max_range = m.max_range();
  r.range = m.range();
  return r;
}

UsblFixes from_msg(const hadal_msgs::msg::UsblFixes& m) {
  UsblFixes out;
  out.stamp = dds::from_time_msg(m.header().stamp());
  out.frame_id = m.header().frame_id();
  for (const hadal_msgs::msg::UsblFix& f : m.fixes()) {
    UsblFix& fix = out.fixes.emplace_back();
    fix.stamp = dds::from_time_msg(f.stamp());
    fix.interrogation_stamp = dds::from_time_msg(f.interrogation_stamp());
    fix.target = f.target();
    fix.interrogation = f.interrogation();
    fix.travel_time = f.travel_time();
    fix.range = f.range();
    fix.bearing = f.bearing();
    fix.elevation = f.elevation();
    fix.position = {f.position().x(), f.position().y(), f.position().z()};
    fix.position_covariance = f.position_covariance();
    fix.position_world = {f.position_world().x(), f.position_world().y(), f.position_world().z()};
    fix.latitude = f.latitude();
    fix.longitude = f.longitude();
    fix.altitude = f.altitude();
    fix.snr_db = f.snr_db();
  }
  return out;
}

CableShape from_msg(const nav_msgs::msg::Path& m) {
  CableShape out;
  out.stamp = dds::from_time_msg(m.header().stamp());
  out.frame_id = m.header().frame_id();
  for (const geometry_msgs::msg::PoseStamped& pose : m.poses()) {
    out.points.push_back({pose.pose().position().x(), pose.pose().position().y(), pose.pose().position().z()});
  }
  return out;
}

WinchState from_msg(const hadal_msgs::msg::WinchState& m) {
  WinchState out;
  out.stamp = dds::from_time_msg(m.header().stamp());
  out.frame_id = m.header().frame_id();
  out.length = m.length_m();
  out.speed = m.speed_mps();
  out.command_speed = m.command_speed_mps();
  out.target_length = m.target_length_m();
  out.drum_length = m.drum_length_m();
  out.min_length = m.min_length_m();
  out.tension = m.tension_n();
  out.at_limit = m.at_limit();
  return out;
}

SeaState from_msg(const hadal_msgs::msg::SeaState& m) {
  SeaState out;
  out.stamp = dds::from_time_msg(m.header().stamp());
  out.frame_id = m.header().frame_id();
  out.surface_z = m.surface_z_m();
  out.surface_slope = {m.surface_slope_x(), m.surface_slope_y()};
  out.depth = m.depth_m();
  out.orbital_velocity = {m.orbital_velocity().x(), m.orbital_velocity().y(), m.orbital_velocity().z()};
  out.significant_height = m.significant_height_m();
  out.peak_period = m.peak_period_s();
  out.mean_direction = m.mean_direction_rad();
  out.build_up = m.build_up();
  return out;
}

AcousticPackets from_msg(const hadal_msgs::msg::AcousticPackets& m) {
  AcousticPackets out;
  out.stamp = dds::from_time_msg(m.header().stamp());
  out.frame_id = m.header().frame_id();
  for (const hadal_msgs::msg::AcousticPacket& p : m.packets()) {
    AcousticPacket& packet = out.packets.emplace_back();
    packet.transmit_stamp = dds::from_time_msg(p.transmit_stamp());
    packet.stamp = dds::from_time_msg(p.stamp());
    packet.source = p.source();
    packet.destination = p.destination();
    packet.sequence_number = p.sequence_number();
    packet.payload = p.payload();
    packet.travel_time = p.travel_time();
    packet.snr_db = p.snr_db();
  }
  return out;
}

LblRanges from_msg(const hadal_msgs::msg::LblRanges& m) {
  LblRanges out;
  out.stamp = dds::from_time_msg(m.header().stamp());
  out.frame_id = m.header().frame_id();
  for (const hadal_msgs::msg::LblRange& r : m.ranges()) {
    LblRange& range = out.ranges.emplace_back();
    range.stamp = dds::from_time_msg(r.stamp());
    range.interrogation_stamp = dds::from_time_msg(r.interrogation_stamp());
    range.beacon = r.beacon();
    range.interrogation = r.interrogation();
    range.travel_time = r.travel_time();
    range.range = r.range();
    range.range_variance = r.range_variance();
    range.beacon_position = {r.beacon_position().x(), r.beacon_position().y(), r.beacon_position().z()};
    range.snr_db = r.snr_db();
  }
  return out;
}

Image from_msg(const sensor_msgs::msg::Image& m) {
  Image image;
  image.stamp = dds::from_time_msg(m.header().stamp());
  image.frame_id = m.header().frame_id();
  image.height = m.height();
  image.width = m.width();
  image.encoding = m.encoding();
  image.is_bigendian = m.is_bigendian() != 0;
  image.step = m.step();
  image.data = m.data();
  return image;
}

CameraInfo from_msg(const sensor_msgs::msg::CameraInfo& m) {
  CameraInfo info;
  info.stamp = dds::from_time_msg(m.header().stamp());
  info.frame_id = m.header().frame_id();
  info.height = m.height();
  info.width = m.width();
  info.distortion_model = m.distortion_model();
  info.d = m.d();
  info.k = m.k();
  info.r = m.r();
  info.p = m.p();
  return info;
}

LaserScan from_msg(const sensor_msgs::msg::LaserScan& m) {
  LaserScan l;
  l.stamp = dds::from_time_msg(m.header().stamp());
  l.frame_id = m.header().frame_id();
  l.angle_min = m.angle_min();
  l.angle_max = m.angle_max();
  l.angle_increment = m.angle_increment();
  l.time_increment = m.time_increment();
  l.scan_time = m.scan_time();
  l.range_min = m.range_min();
  l.range_max = m.range_max();
  l.ranges = m.ranges();
  l.intensities = m.intensities();
  return l;
}

PingInfo from_msg(const marine_acoustic_msgs::msg::PingInfo& m) {
  PingInfo p;
  p.frequency_hz = m.frequency();
  p.sound_speed_m_per_s = m.sound_speed();
  p.tx_beamwidths_rad = m.tx_beamwidths();
  p.rx_beamwidths_rad = m.rx_beamwidths();
  return p;
}

SonarImageData from_msg(const marine_acoustic_msgs::msg::SonarImageData& m) {
  SonarImageData d;
  d.is_bigendian = m.is_bigendian();
  d.dtype = m.dtype();
  d.beam_count = m.beam_count();
  d.data = m.data();
  return d;
}

ProjectedSonarImage from_msg(const marine_acoustic_msgs::msg::ProjectedSonarImage& m) {
  ProjectedSonarImage s;
  s.stamp = dds::from_time_msg(m.header().stamp());
  s.frame_id = m.header().frame_id();
  s.ping_info = from_msg(m.ping_info());
  for (const geometry_msgs::msg::Vector3& d : m.beam_directions()) s.beam_directions.push_back({d.x(), d.y(), d.z()});
  s.ranges = m.ranges();
  s.image = from_msg(m.image());
  return s;
}

RawSonarImage from_msg(const marine_acoustic_msgs::msg::RawSonarImage& m) {
  RawSonarImage s;
  s.stamp = dds::from_time_msg(m.header().stamp());
  s.frame_id = m.header().frame_id();
  s.ping_info = from_msg(m.ping_info());
  s.sample_rate_hz = m.sample_rate();
  s.samples_per_beam = m.samples_per_beam();
  s.sample0 = m.sample0();
  s.tx_delays_s = m.tx_delays();
  s.tx_angles_rad = m.tx_angles();
  s.rx_angles_rad = m.rx_angles();
  s.image = from_msg(m.image());
  return s;
}

FluidPressure from_msg(const sensor_msgs::msg::FluidPressure& m) {
  return FluidPressure{dds::from_time_msg(m.header().stamp()), m.header().frame_id(), m.fluid_pressure(),
                       m.variance()};
}

Imu from_msg(const sensor_msgs::msg::Imu& m) {
  Imu imu;
  imu.stamp = dds::from_time_msg(m.header().stamp());
  imu.frame_id = m.header().frame_id();
  imu.angular_velocity = {m.angular_velocity().x(), m.angular_velocity().y(), m.angular_velocity().z()};
  imu.linear_acceleration = {m.linear_acceleration().x(), m.linear_acceleration().y(), m.linear_acceleration().z()};
  return imu;
}

double from_msg(const rosgraph_msgs::msg::Clock& m) { return dds::from_time_msg(m.clock()); }

SonarDetections from_msg(const marine_acoustic_msgs::msg::SonarDetections& m) {
  SonarDetections s;
  s.stamp = dds::from_time_msg(m.header().stamp());
  s.frame_id = m.header().frame_id();
  s.ping_info = from_msg(m.ping_info());
  for (const marine_acoustic_msgs::msg::DetectionFlag& f : m.flags()) s.flags.push_back(f.flag());
  s.two_way_travel_times_s = m.two_way_travel_times();
  s.tx_delays_s = m.tx_delays();
  s.intensities = m.intensities();
  s.tx_angles_rad = m.tx_angles();
  s.rx_angles_rad = m.rx_angles();
  return s;
}

bool wait_for_match(fdds::DataWriter* writer, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  fdds::PublicationMatchedStatus status;
  while (std::chrono::steady_clock::now() < deadline) {
    writer->get_publication_matched_status(status);
    if (status.current_count > 0) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  writer->get_publication_matched_status(status);
  return status.current_count > 0;
}

}  // namespace

struct Client::Impl {
  fdds::DomainParticipant* participant = nullptr;
  std::unique_ptr<dds::TopicRegistry> registry;
  std::vector<std::unique_ptr<fdds::DataReaderListener>> listeners;
  std::vector<fdds::DataReader*> readers;
  std::map<std::string, fdds::DataWriter*> setpoint_writers;
  fdds::DataWriter* step_writer = nullptr;

  mutable std::mutex mutex;
  std::condition_variable changed;
  std::optional<SimStatus> status;
  std::optional<std::vector<SceneSensor>> scene_sensors;  // from rt/hadal/scene
  // Heartbeat: when the last status arrived, and the interval between the last two (the server's status
  // period, as it arrives).
  double server_timeout_s = 10.0;
  std::chrono::steady_clock::time_point status_arrival{};
  double status_interval_s = 0.0;
  std::vector<std::function<void(const SimStatus&)>> status_callbacks;
  // This client's requests awaiting their reply (empty until it comes); replies to other clients' requests
  // on the same server are not kept.
  std::map<std::uint64_t, std::optional<hadal_msgs::msg::StepReply>> replies;
  // The ground truth of the last reply waited for (reply_odometry), by vehicle name.
  std::map<std::string, Odometry> reply_states;
  bool replied = false;
  std::map<std::string, std::vector<double>> pending_commands;  // attached to the next step()
  // Joint controller commands attached to the next step(), by (vehicle, controller), and their writers.
  std::map<std::pair<std::string, std::string>, std::vector<double>> pending_joint_commands;
  std::map<std::pair<std::string, std::string>, fdds::DataWriter*> joint_command_writers;
  // Joint trajectories attached to the next step(), by (vehicle, controller), and their writers.
  std::map<std::pair<std::string, std::string>, trajectory_msgs::msg::JointTrajectory> pending_joint_trajectories;
  std::map<std::pair<std::string, std::string>, fdds::DataWriter*> joint_trajectory_writers;
  // Modem packets attached to the next step(), in call order, and the tx writers by (vehicle, modem).
  struct PendingPacket {
    std::string vehicle, modem;
    hadal_msgs::msg::AcousticPacket packet;
  };
  std::vector<PendingPacket> pending_packets;
  std::map<std::pair<std::string, std::string>, fdds::DataWriter*> packet_writers;
  // Winch commands attached to the next step(), by cable, and their writers.
  std::map<std::string, hadal_msgs::msg::WinchCommand> pending_winches;
  std::map<std::string, fdds::DataWriter*> winch_writers;

  // Keeps `value` to attach to the next step() (pending[key]) and publishes `msg` on `topic` through
  // writers[key], made on first use (waiting up to 2 s for the server's reader).
  template <class PubSubType, class Key, class Pending, class Msg>
  void publish_and_attach(std::map<Key, Pending>& pending, std::map<Key, fdds::DataWriter*>& writers, const Key& key,
                          const std::string& topic, const Pending& value, Msg& msg) {
    fdds::DataWriter* writer = nullptr;
    {
      std::lock_guard<std::mutex> lock(mutex);
      pending[key] = value;
      auto found = writers.find(key);
      if (found != writers.end()) writer = found->second;
    }
    if (writer == nullptr) {
      writer = registry->writer<PubSubType>(topic, kHistoryDepth);
      wait_for_match(writer, 2.0);
      std::lock_guard<std::mutex> lock(mutex);
      writers[key] = writer;
    }
    writer->write(&msg);
  }
  // Setpoints, published as a std_msgs/Float64MultiArray.
  template <class Key>
  void publish_and_attach(std::map<Key, std::vector<double>>& pending, std::map<Key, fdds::DataWriter*>& writers,
                          const Key& key, const std::string& topic, const std::vector<double>& values) {
    std_msgs::msg::Float64MultiArray msg;
    msg.data(values);
    publish_and_attach<std_msgs::msg::Float64MultiArrayPubSubType>(pending, writers, key, topic, values, msg);
  }
  std::uint64_t next_request_id = 0;

  // Attaches the pending setpoints and sends a step or reset request: its id, for await().
  std::uint64_t submit(hadal_msgs::msg::StepRequest& request, double timeout_s);
  // Waits for the reply to request `id`: the sim time reached, or the refusal thrown.
  double await(std::uint64_t id, double timeout_s);
  // Under `mutex`: wall seconds since the last status (+inf before the first), and the silence after which
  // the server counts as gone.
  double silence_s() const {
    if (!status) return std::numeric_limits<double>::infinity();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - status_arrival).count();
  }
  double heartbeat_timeout_s() const { return std::max(server_timeout_s, 3.0 * status_interval_s); }
  bool alive() const { return silence_s() < heartbeat_timeout_s(); }

  template <class PubSubType, class Msg, class Handler>
  void subscribe(const std::string& topic, Handler handler) {
    auto listener = make_listener<Msg>(std::move(handler));
    // The server's kept samples too: a sample written after this reader matched the server's writer but
    // before that writer matched this reader is delivered all the same (topic_registry.h).
    fdds::DataReader* reader = registry->reader<PubSubType>(topic, kHistoryDepth, listener.get(),
                                                            dds::TopicRegistry::Durability::kKeptSamples);
    std::lock_guard<std::mutex> lock(mutex);
    readers.push_back(reader);
    listeners.push_back(std::move(listener));
  }
};

// ClientOptions::domain_id, or $ROS_DOMAIN_ID, or 0 (dds/domain_id.h); std::invalid_argument outside 0..232.
int resolve_domain_id(std::optional<int> domain_id) {
  if (domain_id) {
    if (*domain_id < 0 || *domain_id > 232) {
      throw std::invalid_argument("ClientOptions::domain_id must be in 0..232 (got " + std::to_string(*domain_id) +
                                  ")");
    }
    return *domain_id;
  }
  int domain = 0;
  if (const std::string error = dds::domain_id_from_environment(std::getenv("ROS_DOMAIN_ID"), &domain);
      !error.empty()) {
    throw std::invalid_argument(error);
  }
  return domain;
}

Client::Client(const ClientOptions& options) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  if (!(options.server_timeout_s > 0.0) || !std::isfinite(options.server_timeout_s)) {
    throw std::invalid_argument("ClientOptions::server_timeout_s must be a positive number of seconds (got " +
                                std::to_string(options.server_timeout_s) + ")");
  }
  d.server_timeout_s = options.server_timeout_s;
  const SecurityFiles security =
      options.security_file.empty() ? SecurityFiles{} : config::load_security_file(options.security_file);
  d.participant = dds::create_participant(resolve_domain_id(options.domain_id), options.name, nullptr, security);
  d.registry = std::make_unique<dds::TopicRegistry>(d.participant);
  // Request ids unique across clients of one server: a random 32-bit prefix per client.
  std::random_device entropy;
  d.next_request_id = (static_cast<std::uint64_t>(entropy()) << 32) ^ static_cast<std::uint64_t>(::getpid());
  d.next_request_id &= ~std::uint64_t{0xFFFFFFFF};

  d.subscribe<hadal_msgs::msg::SimStatusPubSubType, hadal_msgs::msg::SimStatus>(
      dds::status_topic(), [&d](const hadal_msgs::msg::SimStatus& m) {
        const SimStatus s = from_msg(m);
        std::vector<std::function<void(const SimStatus&)>> callbacks;
        {
          std::lock_guard<std::mutex> lock(d.mutex);
          const auto now = std::chrono::steady_clock::now();
          // A gap of a dead server is no period: only intervals while alive count.
          if (d.status && d.alive()) d.status_interval_s = std::chrono::duration<double>(now - d.status_arrival).count();
          d.status_arrival = now;
          d.status = s;
          callbacks = d.status_callbacks;
          d.changed.notify_all();
        }
        for (const auto& callback : callbacks) callback(s);
      });
  d.subscribe<hadal_msgs::msg::ScenePubSubType, hadal_msgs::msg::Scene>(
      dds::scene_topic(), [&d](const hadal_msgs::msg::Scene& m) {
        std::vector<SceneSensor> sensors;
        for (const auto& frame : m.frames()) {
          if (frame.kind() != "light") sensors.push_back(SceneSensor{frame.vehicle(), frame.name(), frame.kind()});
        }
        std::lock_guard<std::mutex> lock(d.mutex);
        d.scene_sensors = std::move(sensors);
      });
  d.subscribe<hadal_msgs::msg::StepReplyPubSubType, hadal_msgs::msg::StepReply>(
      dds::step_reply_topic(), [&d](const hadal_msgs::msg::StepReply& m) {
        std::lock_guard<std::mutex> lock(d.mutex);
        auto waiting = d.replies.find(m.request_id());
        if (waiting == d.replies.end()) return;
        waiting->second = m;
        d.changed.notify_all();
      });
  d.step_writer = d.registry->writer<hadal_msgs::msg::StepRequestPubSubType>(dds::step_request_topic(),
                                                                            kHistoryDepth);
}

Client::~Client() { dds::delete_participant(impl_->participant); }

bool Client::wait_for_server(double timeout_s) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  return impl_->changed.wait_for(lock, std::chrono::duration<double>(timeout_s), [this] { return impl_->alive(); });
}

bool Client::server_alive() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->alive();
}

double Client::seconds_since_status() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->silence_s();
}

bool Client::wait_for_subscriptions(double timeout_s) {
  std::vector<fdds::DataReader*> readers;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    readers = impl_->readers;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (fdds::DataReader* reader : readers) {
    fdds::SubscriptionMatchedStatus status;
    while (true) {
      reader->get_subscription_matched_status(status);
      if (status.current_count > 0) break;
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  return true;
}

std::optional<SimStatus> Client::latest_status() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->status;
}

std::optional<std::vector<SceneSensor>> Client::scene_sensors() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->scene_sensors;
}

void Client::on_clock(std::function<void(double)> callback) {
  impl_->subscribe<rosgraph_msgs::msg::ClockPubSubType, rosgraph_msgs::msg::Clock>(
      dds::clock_topic(),
      [callback = std::move(callback)](const rosgraph_msgs::msg::Clock& m) { callback(from_msg(m)); });
}

void Client::on_status(std::function<void(const SimStatus&)> callback) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->status_callbacks.push_back(std::move(callback));
}

void Client::on_odometry(const std::string& vehicle, std::function<void(const Odometry&)> callback) {
  impl_->subscribe<nav_msgs::msg::OdometryPubSubType, nav_msgs::msg::Odometry>(
      dds::odometry_topic(vehicle),
      [callback = std::move(callback)](const nav_msgs::msg::Odometry& m) { callback(from_msg(m)); });
}

void Client::on_track_state(const std::string& vehicle, std::function<void(const TrackStates&)> callback) {
  impl_->subscribe<hadal_msgs::msg::TrackStatePubSubType, hadal_msgs::msg::TrackState>(
      dds::actuator_state_topic(vehicle, "tracks"),
      [callback = std::move(callback)](const hadal_msgs::msg::TrackState& m) { callback(from_msg(m)); });
}

void Client::on_fin_state(const std::string& vehicle, std::function<void(const FinStates&)> callback) {
  impl_->subscribe<hadal_msgs::msg::FinStatePubSubType, hadal_msgs::msg::FinState>(
      dds::actuator_state_topic(vehicle, "fins"),
      [callback = std::move(callback)](const hadal_msgs::msg::FinState& m) { callback(from_msg(m)); });
}

void Client::on_buoyancy_engine_state(const std::string& vehicle,
                                      std::function<void(const BuoyancyEngineStates&)> callback) {
  impl_->subscribe<hadal_msgs::msg::BuoyancyEngineStatePubSubType, hadal_msgs::msg::BuoyancyEngineState>(
      dds::actuator_state_topic(vehicle, "buoyancy_engines"),
      [callback = std::move(callback)](const hadal_msgs::msg::BuoyancyEngineState& m) { callback(from_msg(m)); });
}

void Client::on_joint_state(const std::string& vehicle, std::function<void(const JointStates&)> callback) {
  impl_->subscribe<sensor_msgs::msg::JointStatePubSubType, sensor_msgs::msg::JointState>(
      dds::joint_states_topic(vehicle),
      [callback = std::move(callback)](const sensor_msgs::msg::JointState& m) { callback(from_msg(m)); });
}

void Client::on_drop_weight_state(const std::string& vehicle, std::function<void(const DropWeightStates&)> callback) {
  impl_->subscribe<hadal_msgs::msg::DropWeightStatePubSubType, hadal_msgs::msg::DropWeightState>(
      dds::actuator_state_topic(vehicle, "drop_weights"),
      [callback = std::move(callback)](const hadal_msgs::msg::DropWeightState& m) { callback(from_msg(m)); });
}

void Client::on_thruster_state(const std::string& vehicle, std::function<void(const ThrusterStates&)> callback) {
  impl_->subscribe<hadal_msgs::msg::ThrusterStatePubSubType, hadal_msgs::msg::ThrusterState>(
      dds::actuator_state_topic(vehicle, "thrusters"),
      [callback = std::move(callback)](const hadal_msgs::msg::ThrusterState& m) { callback(from_msg(m)); });
}

void Client::on_fluid_pressure(const std::string& vehicle, const std::string& sensor,
                               std::function<void(const FluidPressure&)> callback) {
  impl_->subscribe<sensor_msgs::msg::FluidPressurePubSubType, sensor_msgs::msg::FluidPressure>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const sensor_msgs::msg::FluidPressure& m) { callback(from_msg(m)); });
}

void Client::on_imu(const std::string& vehicle, const std::string& sensor, std::function<void(const Imu&)> callback) {
  impl_->subscribe<sensor_msgs::msg::ImuPubSubType, sensor_msgs::msg::Imu>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const sensor_msgs::msg::Imu& m) { callback(from_msg(m)); });
}

void Client::on_magnetic_field(const std::string& vehicle, const std::string& sensor,
                               std::function<void(const MagneticField&)> callback) {
  impl_->subscribe<sensor_msgs::msg::MagneticFieldPubSubType, sensor_msgs::msg::MagneticField>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const sensor_msgs::msg::MagneticField& m) { callback(from_msg(m)); });
}

void Client::on_wrench(const std::string& vehicle, const std::string& sensor,
                       std::function<void(const Wrench&)> callback) {
  impl_->subscribe<geometry_msgs::msg::WrenchStampedPubSubType, geometry_msgs::msg::WrenchStamped>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const geometry_msgs::msg::WrenchStamped& m) { callback(from_msg(m)); });
}

void Client::on_nav_sat_fix(const std::string& vehicle, const std::string& sensor,
                            std::function<void(const NavSatFix&)> callback) {
  impl_->subscribe<sensor_msgs::msg::NavSatFixPubSubType, sensor_msgs::msg::NavSatFix>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const sensor_msgs::msg::NavSatFix& m) { callback(from_msg(m)); });
}

void Client::on_dvl(const std::string& vehicle, const std::string& sensor, std::function<void(const Dvl&)> callback) {
  impl_->subscribe<marine_acoustic_msgs::msg::DvlPubSubType, marine_acoustic_msgs::msg::Dvl>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const marine_acoustic_msgs::msg::Dvl& m) { callback(from_msg(m)); });
}

void Client::on_usbl_fixes(const std::string& vehicle, const std::string& sensor,
                           std::function<void(const UsblFixes&)> callback) {
  impl_->subscribe<hadal_msgs::msg::UsblFixesPubSubType, hadal_msgs::msg::UsblFixes>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const hadal_msgs::msg::UsblFixes& m) { callback(from_msg(m)); });
}

void Client::on_lbl_ranges(const std::string& vehicle, const std::string& sensor,
                           std::function<void(const LblRanges&)> callback) {
  impl_->subscribe<hadal_msgs::msg::LblRangesPubSubType, hadal_msgs::msg::LblRanges>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const hadal_msgs::msg::LblRanges& m) { callback(from_msg(m)); });
}

void Client::on_range(const std::string& vehicle, const std::string& sensor,
                      std::function<void(const Range&)> callback) {
  impl_->subscribe<sensor_msgs::msg::RangePubSubType, sensor_msgs::msg::Range>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const sensor_msgs::msg::Range& m) { callback(from_msg(m)); });
}

float Image::depth_m(std::uint32_t u, std::uint32_t v) const {
  if (encoding != "32FC1") throw std::logic_error("Image::depth_m: encoding is '" + encoding + "', not 32FC1");
  if (u >= width || v >= height) throw std::out_of_range("Image::depth_m: pixel outside the image");
  float z = 0.0f;
  std::memcpy(&z, data.data() + static_cast<std::size_t>(v) * step + u * sizeof(float), sizeof(float));
  return z;
}

double SonarImageData::sample(std::size_t i) const {
  if (is_bigendian) throw std::logic_error("SonarImageData::sample: a big-endian image");
  if (i >= size()) throw std::out_of_range("SonarImageData::sample: index past the end");
  if (dtype == kUint8) return data[i];
  if (dtype != kFloat32) {
    throw std::logic_error("SonarImageData::sample: dtype " + std::to_string(dtype) + " (only uint8 and float32)");
  }
  float v = 0.0f;
  std::memcpy(&v, data.data() + 4 * i, sizeof v);
  return v;
}

double ProjectedSonarImage::beam_azimuth(std::size_t k) const {
  const std::array<double, 3>& d = beam_directions.at(k);
  return std::atan2(-d[1], d[2]);
}

double ProjectedSonarImage::sample(std::size_t bin, std::size_t beam) const {
  if (beam >= image.beam_count) throw std::out_of_range("ProjectedSonarImage::sample: beam past the last");
  return image.sample(bin * image.beam_count + beam);
}

double RawSonarImage::sample_range_m(std::size_t i) const {
  return (static_cast<double>(sample0) + static_cast<double>(i)) * ping_info.sound_speed_m_per_s / (2.0 * sample_rate_hz);
}

double SonarDetections::range_m(std::size_t k) const {
  if (flags.at(k) != kDetectOk) return std::numeric_limits<double>::quiet_NaN();
  return 0.5 * ping_info.sound_speed_m_per_s * two_way_travel_times_s.at(k);
}

void Client::on_sonar_image(const std::string& vehicle, const std::string& sensor,
                            std::function<void(const ProjectedSonarImage&)> callback) {
  using Msg = marine_acoustic_msgs::msg::ProjectedSonarImage;
  impl_->subscribe<marine_acoustic_msgs::msg::ProjectedSonarImagePubSubType, Msg>(
      dds::sensor_topic(vehicle, sensor), [callback = std::move(callback)](const Msg& m) { callback(from_msg(m)); });
}

void Client::on_sonar_detections(const std::string& vehicle, const std::string& sensor,
                                 std::function<void(const SonarDetections&)> callback) {
  using Msg = marine_acoustic_msgs::msg::SonarDetections;
  impl_->subscribe<marine_acoustic_msgs::msg::SonarDetectionsPubSubType, Msg>(
      dds::sensor_topic(vehicle, sensor), [callback = std::move(callback)](const Msg& m) { callback(from_msg(m)); });
}

void Client::on_raw_sonar_image(const std::string& vehicle, const std::string& sensor, const std::string& channel,
                                std::function<void(const RawSonarImage&)> callback) {
  using Msg = marine_acoustic_msgs::msg::RawSonarImage;
  impl_->subscribe<marine_acoustic_msgs::msg::RawSonarImagePubSubType, Msg>(
      dds::sensor_topic(vehicle, sensor) + "/" + channel,
      [callback = std::move(callback)](const Msg& m) { callback(from_msg(m)); });
}

void Client::on_image(const std::string& vehicle, const std::string& camera, std::function<void(const Image&)> callback) {
  impl_->subscribe<sensor_msgs::msg::ImagePubSubType, sensor_msgs::msg::Image>(
      dds::sensor_topic(vehicle, camera) + "/image_raw",
      [callback = std::move(callback)](const sensor_msgs::msg::Image& m) { callback(from_msg(m)); });
}

void Client::on_depth_image(const std::string& vehicle, const std::string& camera,
                            std::function<void(const Image&)> callback) {
  impl_->subscribe<sensor_msgs::msg::ImagePubSubType, sensor_msgs::msg::Image>(
      dds::sensor_topic(vehicle, camera) + "/depth",
      [callback = std::move(callback)](const sensor_msgs::msg::Image& m) { callback(from_msg(m)); });
}

void Client::on_camera_info(const std::string& vehicle, const std::string& camera,
                            std::function<void(const CameraInfo&)> callback) {
  impl_->subscribe<sensor_msgs::msg::CameraInfoPubSubType, sensor_msgs::msg::CameraInfo>(
      dds::sensor_topic(vehicle, camera) + "/camera_info",
      [callback = std::move(callback)](const sensor_msgs::msg::CameraInfo& m) { callback(from_msg(m)); });
}

void Client::on_cable_force(const std::string& cable, const std::string& end,
                            std::function<void(const Wrench&)> callback) {
  if (end != "from" && end != "to") {
    throw std::invalid_argument("on_cable_force: end must be 'from' or 'to' (got '" + end + "')");
  }
  impl_->subscribe<geometry_msgs::msg::WrenchStampedPubSubType, geometry_msgs::msg::WrenchStamped>(
      dds::cable_tension_topic(cable, end),
      [callback = std::move(callback)](const geometry_msgs::msg::WrenchStamped& m) { callback(from_msg(m)); });
}

void Client::on_cable_shape(const std::string& cable, std::function<void(const CableShape&)> callback) {
  impl_->subscribe<nav_msgs::msg::PathPubSubType, nav_msgs::msg::Path>(
      dds::cable_shape_topic(cable),
      [callback = std::move(callback)](const nav_msgs::msg::Path& m) { callback(from_msg(m)); });
}

void Client::on_winch_state(const std::string& cable, std::function<void(const WinchState&)> callback) {
  impl_->subscribe<hadal_msgs::msg::WinchStatePubSubType, hadal_msgs::msg::WinchState>(
      dds::winch_state_topic(cable),
      [callback = std::move(callback)](const hadal_msgs::msg::WinchState& m) { callback(from_msg(m)); });
}

void Client::on_sea_state(const std::string& vehicle, std::function<void(const SeaState&)> callback) {
  impl_->subscribe<hadal_msgs::msg::SeaStatePubSubType, hadal_msgs::msg::SeaState>(
      dds::sea_state_topic(vehicle),
      [callback = std::move(callback)](const hadal_msgs::msg::SeaState& m) { callback(from_msg(m)); });
}

void Client::command_winch(const std::string& cable, double speed_mps, double target_length_m) {
  hadal_msgs::msg::WinchCommand msg;
  msg.speed_mps(speed_mps);
  msg.target_length_m(target_length_m);
  impl_->publish_and_attach<hadal_msgs::msg::WinchCommandPubSubType>(
      impl_->pending_winches, impl_->winch_writers, cable, dds::winch_command_topic(cable), msg, msg);
}

void Client::attach_winch(const std::string& cable, double speed_mps, double target_length_m) {
  hadal_msgs::msg::WinchCommand msg;
  msg.speed_mps(speed_mps);
  msg.target_length_m(target_length_m);
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->pending_winches[cable] = msg;
}

void Client::on_modem_packets(const std::string& vehicle, const std::string& modem,
                              std::function<void(const AcousticPackets&)> callback) {
  impl_->subscribe<hadal_msgs::msg::AcousticPacketsPubSubType, hadal_msgs::msg::AcousticPackets>(
      dds::sensor_topic(vehicle, modem) + "/rx",
      [callback = std::move(callback)](const hadal_msgs::msg::AcousticPackets& m) { callback(from_msg(m)); });
}

void Client::send_packet(const std::string& vehicle, const std::string& modem, const std::vector<std::uint8_t>& payload,
                         const std::string& destination) {
  hadal_msgs::msg::AcousticPacket msg;
  msg.destination(destination);
  msg.payload(payload);
  const auto key = std::make_pair(vehicle, modem);
  fdds::DataWriter* writer = nullptr;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    auto found = impl_->packet_writers.find(key);
    if (found != impl_->packet_writers.end()) writer = found->second;
  }
  if (writer == nullptr) {
    writer = impl_->registry->writer<hadal_msgs::msg::AcousticPacketPubSubType>(dds::modem_tx_topic(vehicle, modem),
                                                                              kHistoryDepth);
    wait_for_match(writer, 2.0);
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->packet_writers[key] = writer;
  }
  writer->write(&msg);
}

void Client::attach_packet(const std::string& vehicle, const std::string& modem, const std::vector<std::uint8_t>& payload,
                           const std::string& destination) {
  Impl::PendingPacket pending{vehicle, modem, {}};
  pending.packet.destination(destination);
  pending.packet.payload(payload);
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->pending_packets.push_back(std::move(pending));
}

void Client::on_laser_scan(const std::string& vehicle, const std::string& sensor,
                           std::function<void(const LaserScan&)> callback) {
  impl_->subscribe<sensor_msgs::msg::LaserScanPubSubType, sensor_msgs::msg::LaserScan>(
      dds::sensor_topic(vehicle, sensor),
      [callback = std::move(callback)](const sensor_msgs::msg::LaserScan& m) { callback(from_msg(m)); });
}

void Client::attach_commands(const std::string& vehicle, const std::vector<double>& commands) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->pending_commands[vehicle] = commands;
}

void Client::attach_joint_commands(const std::string& vehicle, const std::string& controller,
                                   const std::vector<double>& values) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->pending_joint_commands[std::make_pair(vehicle, controller)] = values;
}

void Client::set_commands(const std::string& vehicle, const std::vector<double>& commands) {
  impl_->publish_and_attach(impl_->pending_commands, impl_->setpoint_writers, vehicle,
                            dds::actuator_commands_topic(vehicle), commands);
}

void Client::set_joint_commands(const std::string& vehicle, const std::string& controller,
                                const std::vector<double>& values) {
  impl_->publish_and_attach(impl_->pending_joint_commands, impl_->joint_command_writers,
                            std::make_pair(vehicle, controller), dds::joint_commands_topic(vehicle, controller),
                            values);
}

void Client::set_joint_trajectory(const std::string& vehicle, const std::string& controller,
                                  const JointTrajectory& trajectory) {
  trajectory_msgs::msg::JointTrajectory msg;
  // A zero stamp: on receipt (ros2_control's convention).
  if (trajectory.start_time) msg.header().stamp(dds::to_time_msg(*trajectory.start_time));
  msg.joint_names(trajectory.joint_names);
  for (const JointTrajectoryPoint& point : trajectory.points) {
    trajectory_msgs::msg::JointTrajectoryPoint out;
    out.positions(point.positions);
    out.velocities(point.velocities);
    out.accelerations(point.accelerations);
    const builtin_interfaces::msg::Time t = dds::to_time_msg(point.time_from_start);
    out.time_from_start().sec(t.sec());
    out.time_from_start().nanosec(t.nanosec());
    msg.points().push_back(std::move(out));
  }
  impl_->publish_and_attach<trajectory_msgs::msg::JointTrajectoryPubSubType>(
      impl_->pending_joint_trajectories, impl_->joint_trajectory_writers, std::make_pair(vehicle, controller),
      dds::joint_trajectory_topic(vehicle, controller), msg, msg);
}

std::uint64_t Client::Impl::submit(hadal_msgs::msg::StepRequest& request, double timeout_s) {
  Impl& d = *this;
  if (!wait_for_match(d.step_writer, timeout_s)) {
    throw ServerNotFound("no lockstep server on this domain (rt/hadal/step_request has no reader)");
  }
  std::uint64_t id = 0;
  {
    std::lock_guard<std::mutex> lock(d.mutex);
    id = ++d.next_request_id;
    request.request_id(id);
    for (const auto& [vehicle, setpoints] : d.pending_commands) {
      request.vehicle_names().push_back(vehicle);
      request.setpoint_counts().push_back(static_cast<std::uint32_t>(setpoints.size()));
      request.setpoints().insert(request.setpoints().end(), setpoints.begin(), setpoints.end());
    }
    d.pending_commands.clear();
    for (const auto& [key, values] : d.pending_joint_commands) {
      request.joint_command_vehicles().push_back(key.first);
      request.joint_command_controllers().push_back(key.second);
      request.joint_command_counts().push_back(static_cast<std::uint32_t>(values.size()));
      request.joint_commands().insert(request.joint_commands().end(), values.begin(), values.end());
    }
    d.pending_joint_commands.clear();
    for (auto& [key, trajectory] : d.pending_joint_trajectories) {
      request.joint_trajectory_vehicles().push_back(key.first);
      request.joint_trajectory_controllers().push_back(key.second);
      request.joint_trajectories().push_back(std::move(trajectory));
    }
    d.pending_joint_trajectories.clear();
    for (PendingPacket& pending : d.pending_packets) {
      request.packet_vehicles().push_back(pending.vehicle);
      request.packet_modems().push_back(pending.modem);
      request.packets().push_back(std::move(pending.packet));
    }
    d.pending_packets.clear();
    for (const auto& [cable, command] : d.pending_winches) {
      request.winch_cables().push_back(cable);
      request.winch_commands().push_back(command);
    }
    d.pending_winches.clear();
    d.replies.emplace(id, std::nullopt);
  }
  d.step_writer->write(&request);
  return id;
}

double Client::Impl::await(std::uint64_t id, double timeout_s) {
  Impl& d = *this;
  std::unique_lock<std::mutex> lock(d.mutex);
  auto found = d.replies.find(id);
  if (found == d.replies.end()) {
    throw ClientError("no request " + std::to_string(id) + " of this client is waiting for its reply");
  }
  // In slices, so that a server gone silent (no status heartbeat: killed, crashed, link down) ends the wait
  // long before timeout_s. A server never heard from is only waited for.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                              std::chrono::duration<double>(std::min(timeout_s, 1e9)));
  while (!found->second.has_value()) {
    const bool heard = d.status.has_value();
    if (heard && !d.alive()) {
      const double silence = d.silence_s();
      d.replies.erase(found);
      throw ServerLost("the server went silent: no status for " + std::to_string(silence) +
                       " s (heartbeat timeout " + std::to_string(d.heartbeat_timeout_s()) + " s); request " +
                       std::to_string(id) + " is lost");
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) {
      d.replies.erase(found);  // a reply that comes later is dropped
      throw Timeout("no step reply from the server within " + std::to_string(timeout_s) + " s");
    }
    d.changed.wait_until(lock, std::min(deadline, now + std::chrono::nanoseconds(std::chrono::milliseconds(100))));
  }
  const hadal_msgs::msg::StepReply reply = *found->second;
  d.replies.erase(found);
  d.replied = true;
  d.reply_states.clear();
  for (std::size_t i = 0; i < reply.vehicle_names().size() && 7 * i + 6 < reply.poses().size() &&
                          6 * i + 5 < reply.twists().size();
       ++i) {
    Odometry& o = d.reply_states[reply.vehicle_names()[i]];
    o.stamp = dds::from_time_msg(reply.sim_time());  // as odometry stamps it
    o.child_frame_id = dds::base_frame_id(reply.vehicle_names()[i]);
    std::copy_n(reply.poses().begin() + 7 * i, 3, o.p_WB.begin());
    std::copy_n(reply.poses().begin() + 7 * i + 3, 4, o.q_WB.begin());
    std::copy_n(reply.twists().begin() + 6 * i, 3, o.v_WB_B.begin());
    std::copy_n(reply.twists().begin() + 6 * i + 3, 3, o.w_WB_B.begin());
  }
  if (!reply.accepted()) {
    if (!reply.unknown_vehicle().empty()) {
      throw UnknownVehicle(reply.unknown_vehicle(), "step request refused: " + reply.error());
    }
    throw CommandRejected(reply.error());
  }
  return reply.sim_time_s();
}

namespace {

hadal_msgs::msg::StepRequest step_request(std::uint32_t steps) {
  hadal_msgs::msg::StepRequest request;
  request.steps(steps);
  return request;
}

hadal_msgs::msg::StepRequest reset_request(const ResetOptions& options, std::uint32_t steps) {
  hadal_msgs::msg::StepRequest request = step_request(steps);
  request.reset(true);
  request.reset_seed_given(options.seed.has_value());
  request.reset_seed(options.seed.value_or(0));
  for (const auto& [vehicle, pose] : options.poses) {
    request.reset_vehicle_names().push_back(vehicle);
    request.reset_poses().insert(request.reset_poses().end(), pose.p_WB.begin(), pose.p_WB.end());
    request.reset_poses().insert(request.reset_poses().end(), pose.q_WB.begin(), pose.q_WB.end());
  }
  return request;
}

}  // namespace

double Client::step(std::uint32_t steps, double timeout_s) {
  return wait_reply(send_step(steps, timeout_s), timeout_s);
}

double Client::reset(const ResetOptions& options, std::uint32_t steps, double timeout_s) {
  return wait_reply(send_reset(options, steps, timeout_s), timeout_s);
}

std::uint64_t Client::send_step(std::uint32_t steps, double timeout_s) {
  hadal_msgs::msg::StepRequest request = step_request(steps);
  return impl_->submit(request, timeout_s);
}

std::uint64_t Client::send_reset(const ResetOptions& options, std::uint32_t steps, double timeout_s) {
  hadal_msgs::msg::StepRequest request = reset_request(options, steps);
  return impl_->submit(request, timeout_s);
}

double Client::wait_reply(std::uint64_t request_id, double timeout_s) { return impl_->await(request_id, timeout_s); }

Odometry Client::reply_odometry(const std::string& vehicle) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  if (!impl_->replied) throw ClientError("reply_odometry: no step reply received yet");
  const auto found = impl_->reply_states.find(vehicle);
  if (found == impl_->reply_states.end()) {
    throw UnknownVehicle(vehicle, "reply_odometry: the last step reply has no vehicle '" + vehicle + "'");
  }
  return found->second;
}

namespace {

// CDR bytes (with their encapsulation header, as on the wire and in a rosbag2 bag) into the client's value.
template <class PubSub, class Msg>
DecodedMessage decode_as(const std::string& type, const std::vector<std::uint8_t>& cdr) {
  PubSub pub_sub;
  Msg msg;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(cdr.size()));
  if (!cdr.empty()) std::memcpy(payload.data, cdr.data(), cdr.size());
  payload.length = static_cast<std::uint32_t>(cdr.size());
  bool ok = false;
  try {
    ok = cdr.size() >= 4 && pub_sub.deserialize(&payload, &msg);
  } catch (const std::exception&) {  // fastcdr's exceptions for bytes that run out
    ok = false;
  }
  if (!ok) {
    throw std::runtime_error("the " + std::to_string(cdr.size()) + " bytes do not decode as " + type);
  }
  return DecodedMessage{from_msg(msg)};
}

using Decoder = DecodedMessage (*)(const std::string&, const std::vector<std::uint8_t>&);

const std::map<std::string, Decoder>& decoders() {
  static const std::map<std::string, Decoder> table = {
      {"rosgraph_msgs/msg/Clock", &decode_as<rosgraph_msgs::msg::ClockPubSubType, rosgraph_msgs::msg::Clock>},
      {"nav_msgs/msg/Odometry", &decode_as<nav_msgs::msg::OdometryPubSubType, nav_msgs::msg::Odometry>},
      {"hadal_msgs/msg/SimStatus", &decode_as<hadal_msgs::msg::SimStatusPubSubType, hadal_msgs::msg::SimStatus>},
      {"hadal_msgs/msg/ThrusterState",
       &decode_as<hadal_msgs::msg::ThrusterStatePubSubType, hadal_msgs::msg::ThrusterState>},
      {"hadal_msgs/msg/TrackState", &decode_as<hadal_msgs::msg::TrackStatePubSubType, hadal_msgs::msg::TrackState>},
      {"hadal_msgs/msg/FinState", &decode_as<hadal_msgs::msg::FinStatePubSubType, hadal_msgs::msg::FinState>},
      {"hadal_msgs/msg/BuoyancyEngineState",
       &decode_as<hadal_msgs::msg::BuoyancyEngineStatePubSubType, hadal_msgs::msg::BuoyancyEngineState>},
      {"hadal_msgs/msg/DropWeightState",
       &decode_as<hadal_msgs::msg::DropWeightStatePubSubType, hadal_msgs::msg::DropWeightState>},
      {"sensor_msgs/msg/JointState", &decode_as<sensor_msgs::msg::JointStatePubSubType, sensor_msgs::msg::JointState>},
      {"sensor_msgs/msg/FluidPressure",
       &decode_as<sensor_msgs::msg::FluidPressurePubSubType, sensor_msgs::msg::FluidPressure>},
      {"sensor_msgs/msg/Imu", &decode_as<sensor_msgs::msg::ImuPubSubType, sensor_msgs::msg::Imu>},
      {"sensor_msgs/msg/MagneticField",
       &decode_as<sensor_msgs::msg::MagneticFieldPubSubType, sensor_msgs::msg::MagneticField>},
      {"geometry_msgs/msg/WrenchStamped",
       &decode_as<geometry_msgs::msg::WrenchStampedPubSubType, geometry_msgs::msg::WrenchStamped>},
      {"sensor_msgs/msg/NavSatFix", &decode_as<sensor_msgs::msg::NavSatFixPubSubType, sensor_msgs::msg::NavSatFix>},
      {"marine_acoustic_msgs/msg/Dvl", &decode_as<marine_acoustic_msgs::msg::DvlPubSubType, marine_acoustic_msgs::msg::Dvl>},
      {"sensor_msgs/msg/Range", &decode_as<sensor_msgs::msg::RangePubSubType, sensor_msgs::msg::Range>},
      {"hadal_msgs/msg/UsblFixes", &decode_as<hadal_msgs::msg::UsblFixesPubSubType, hadal_msgs::msg::UsblFixes>},
      {"hadal_msgs/msg/LblRanges", &decode_as<hadal_msgs::msg::LblRangesPubSubType, hadal_msgs::msg::LblRanges>},
      {"nav_msgs/msg/Path", &decode_as<nav_msgs::msg::PathPubSubType, nav_msgs::msg::Path>},
      {"hadal_msgs/msg/AcousticPackets",
       &decode_as<hadal_msgs::msg::AcousticPacketsPubSubType, hadal_msgs::msg::AcousticPackets>},
      {"hadal_msgs/msg/WinchState", &decode_as<hadal_msgs::msg::WinchStatePubSubType, hadal_msgs::msg::WinchState>},
      {"hadal_msgs/msg/SeaState", &decode_as<hadal_msgs::msg::SeaStatePubSubType, hadal_msgs::msg::SeaState>},
      {"sensor_msgs/msg/LaserScan", &decode_as<sensor_msgs::msg::LaserScanPubSubType, sensor_msgs::msg::LaserScan>},
      {"sensor_msgs/msg/CameraInfo", &decode_as<sensor_msgs::msg::CameraInfoPubSubType, sensor_msgs::msg::CameraInfo>},
      {"marine_acoustic_msgs/msg/SonarDetections",
       &decode_as<marine_acoustic_msgs::msg::SonarDetectionsPubSubType, marine_acoustic_msgs::msg::SonarDetections>},
  };
  return table;
}

}  // namespace

std::vector<std::string> decodable_message_types() {
  std::vector<std::string> out;
  for (const auto& [type, decoder] : decoders()) out.push_back(type);
  return out;
}

DecodedMessage decode_message(const std::string& type, const std::vector<std::uint8_t>& cdr) {
  const auto found = decoders().find(type);
  if (found == decoders().end()) {
    std::string known;
    for (const std::string& name : decodable_message_types()) known += (known.empty() ? "" : ", ") + name;
    throw std::invalid_argument("no decoder for message type '" + type + "' (decoded: " + known + ")");
  }
  return found->second(type, cdr);
}

}  // namespace hadal
