// libhadal_client: a thin C++ client of hadald over DDS.
//
// Subscribe to odometry, clock, status, thruster state and sensors (pressure, IMU, magnetometer, GNSS,
// DVL, range finder, profiler scans) with callbacks; command thrusters; step a lockstep server. The public API has no
// DDS types in it: samples arrive as the plain structs below (SI units, frames as in the topic table of
// docs/topics.md). Callbacks run on DDS threads: keep them short and synchronise what they touch.
//
//   hadal::Client client(hadal::ClientOptions{0, "my_controller"});  // domain 0 ({}: $ROS_DOMAIN_ID, else 0)
//   if (!client.wait_for_server(10.0)) ...;
//   client.on_odometry("auv", [](const hadal::Odometry& o) { ... });
//   client.set_commands("auv", {0.5, 0.0, 0.0});
//   double t = client.step(100);  // lockstep servers only
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace hadal {

// nav_msgs/Odometry of rt/<vehicle>/odometry: pose of the body frame B in the world frame W (ENU),
// twist of B expressed in B.
struct Odometry {
  double stamp = 0.0;  // sim time [s]
  std::string frame_id;        // world frame
  std::string child_frame_id;  // <vehicle>/base_link
  std::array<double, 3> p_WB{};          // position [m]
  std::array<double, 4> q_WB{0, 0, 0, 1};  // orientation quaternion x, y, z, w
  std::array<double, 3> v_WB_B{};        // linear velocity of B in W, expressed in B [m/s]
  std::array<double, 3> w_WB_B{};        // angular velocity of B in W, expressed in B [rad/s]
};

enum class ServerMode : std::uint8_t { kRealtime = 0, kFast = 1, kLockstep = 2 };

// hadal_msgs/SimStatus of rt/hadal/status.
struct SimStatus {
  double sim_time = 0.0;          // [s]
  double wall_time = 0.0;         // since the server started [s]
  double real_time_factor = 0.0;
  std::uint64_t step_count = 0;
  double step_size = 0.0;         // [s]
  ServerMode mode = ServerMode::kRealtime;
  std::vector<std::string> vehicle_names;
  std::vector<std::uint32_t> vehicle_faults;  // bits: 1 command timeout, 2 non-finite state reset
  std::uint64_t rejected_commands = 0;
  std::string last_error;
  std::uint64_t dropped_captures = 0;  // camera frames / ray-cast samples late in real time, dropped
};

// hadal_msgs/ThrusterState of rt/<vehicle>/thrusters/state.
struct ThrusterStates {
  double stamp = 0.0;  // sim time [s]
  std::vector<std::string> names;
  std::vector<double> setpoint;     // [-1, 1]
  std::vector<double> rotor_speed;  // [rev/s]
  std::vector<double> thrust;       // [N]
  std::vector<double> torque;       // [N m]
  std::uint8_t command_source = 0;  // 0 none, 1 scenario schedule, 2 client
};

// hadal_msgs/TrackState of rt/<vehicle>/tracks/state (vehicles with tracks only).
struct TrackStates {
  double stamp = 0.0;  // sim time [s]
  std::vector<std::string> names;
  std::vector<double> setpoint;        // [-1, 1]
  std::vector<double> belt_speed;      // [m/s]
  std::vector<double> sprocket_speed;  // [rad/s]
  std::vector<double> motor_torque;    // at the sprocket [N m]
  std::vector<double> current;         // [A]
  std::vector<double> power;           // [W]
  std::vector<double> load;            // the soil's shear on the belt [N]
  std::uint8_t command_source = 0;     // 0 none, 1 scenario schedule, 2 client
};

// hadal_msgs/FinState of rt/<vehicle>/fins/state (vehicles with fins only).
struct FinStates {
  double stamp = 0.0;  // sim time [s]
  std::vector<std::string> names;
  std::vector<double> setpoint;      // [-1, 1]
  std::vector<double> angle;         // deflection about the hinge axis [rad]
  std::vector<double> attack_angle;  // the water's angle of attack [rad]
  std::vector<double> lift;          // [N], signed as the lift coefficient
  std::vector<double> drag;          // [N]
  std::uint8_t command_source = 0;   // 0 none, 1 scenario schedule, 2 client
};

// hadal_msgs/BuoyancyEngineState of rt/<vehicle>/buoyancy_engines/state (vehicles with one only).
struct BuoyancyEngineStates {
  double stamp = 0.0;  // sim time [s]
  std::vector<std::string> names;
  std::vector<double> setpoint;       // [-1, 1]
  std::vector<double> volume_change;  // displaced volume beyond neutral [m^3]
  std::vector<double> volume_rate;    // [m^3/s]
  std::vector<double> force;          // buoyancy of the volume change, up [N]
  std::vector<double> power;          // pump power [W]
  std::vector<double> energy;         // pump energy since the start [J]
  std::uint8_t command_source = 0;    // 0 none, 1 scenario schedule, 2 client
};

// hadal_msgs/DropWeightState of rt/<vehicle>/drop_weights/state (vehicles with one only).
struct DropWeightStates {
  static constexpr std::uint8_t kAttached = 0, kReleasedOnCommand = 1, kReleasedAtAltitude = 2, kReleasedAtTime = 3;
  double stamp = 0.0;  // sim time [s]
  std::vector<std::string> names;
  std::vector<bool> attached;
  std::vector<std::uint8_t> reason;   // kAttached, kReleasedOn...
  std::vector<double> release_time;   // [s]; NaN while attached
  std::vector<double> force;          // vertical force while attached [N] (negative: down)
  std::uint8_t command_source = 0;    // 0 none, 1 scenario schedule, 2 client
};

// sensor_msgs/JointState of rt/<vehicle>/joint_states (articulated vehicles only): each moving joint,
// named as the scenario names them (links[].joint.name, else the link's), in the server's state order.
struct JointStates {
  double stamp = 0.0;  // sim time [s]
  std::string frame_id;  // <vehicle>/base_link
  std::vector<std::string> names;
  std::vector<double> position;  // [rad or m]
  std::vector<double> velocity;  // [rad/s or m/s]
  std::vector<double> effort;    // the effort each joint's motor holds [N m or N]
};

// A position group's trajectory (trajectory_msgs/JointTrajectory, as ros2_control's
// joint_trajectory_controller takes it): waypoints at times after its start. Between waypoints the server
// moves each joint on a line (positions alone), a cubic (with velocities) or a quintic (with
// accelerations too), from where the joints are when it starts; then it holds the last waypoint.
struct JointTrajectoryPoint {
  double time_from_start = 0.0;       // [s], increasing from point to point
  std::vector<double> positions;      // one per joint, in joint_names' order [rad or m]
  std::vector<double> velocities;     // empty, or one per joint [rad/s or m/s]
  std::vector<double> accelerations;  // empty, or (with velocities) one per joint [rad/s^2 or m/s^2]
};
struct JointTrajectory {
  std::vector<std::string> joint_names;  // the group's joints, each once, in any order
  std::vector<JointTrajectoryPoint> points;
  // The sim time [s] from which time_from_start counts; none: when the server applies it (the next step).
  std::optional<double> start_time;
};

// sensor_msgs/FluidPressure of a pressure sensor, rt/<vehicle>/<sensor>: absolute pressure with the
// sensor's noise. Depth below the surface follows as d = (p - p_atm) / (rho g) for the water's mean
// density above the sensor (p_atm = 101325 Pa and rho = 1025 kg/m^3 unless the scenario says otherwise).
struct FluidPressure {
  double stamp = 0.0;     // sim time of the sample [s]
  std::string frame_id;   // the sensor's frame
  double pressure = 0.0;  // absolute [Pa]
  double variance = 0.0;  // [Pa^2]
};

// sensor_msgs/Imu of an IMU, rt/<vehicle>/<sensor>: angular rate and specific force (acceleration
// minus gravity: +9.81 m/s^2 up at rest) in the sensor frame, with the sensor's noise.
struct Imu {
  double stamp = 0.0;                          // sim time of the sample [s]
  std::string frame_id;                        // the sensor's frame
  std::array<double, 3> angular_velocity{};    // [rad/s]
  std::array<double, 3> linear_acceleration{};  // specific force [m/s^2]
};

// sensor_msgs/MagneticField of a magnetometer, rt/<vehicle>/<sensor>: the magnetic flux density at
// the sensor (Earth's field from the World Magnetic Model plus the scenario's dipoles, soft iron and
// noise) expressed in the sensor frame S.
// geometry_msgs/WrenchStamped of a force_torque sensor, rt/<vehicle>/<sensor>: the wrench across its link's
// joint in the sensor frame, about its origin (by default what the link and its load put on the parent).
struct Wrench {
  double stamp = 0.0;                // sim time of the sample [s]
  std::string frame_id;              // the sensor's frame
  std::array<double, 3> force{};     // [N]
  std::array<double, 3> torque{};    // [N m]
};

// nav_msgs/Path of a cable, rt/hadal/cables/<name>/shape: its nodes in W, from its `from` end to its `to` end.
struct CableShape {
  double stamp = 0.0;                          // sim time [s]
  std::string frame_id;                        // the world frame
  std::vector<std::array<double, 3>> points;   // [m]
};

// hadal_msgs/WinchState of a cable's winch, rt/hadal/cables/<name>/winch/state, at the cable's rate_hz.
struct WinchState {
  double stamp = 0.0;                // sim time [s]
  std::string frame_id;              // the world frame
  double length = 0.0;               // unstretched cable in the water [m]
  double speed = 0.0;                // line speed, + paying out [m/s]
  double command_speed = 0.0;        // what it was last told [m/s]
  double target_length = 0.0;        // [m]; 0: none
  double drum_length = 0.0;          // in the water and on the drum together [m]
  double min_length = 0.0;           // hauling in stops here [m]
  double tension = 0.0;              // the cable's pull on the winch [N]
  bool at_limit = false;             // stopped at min_length or the drum's end while told to go on
};

// hadal_msgs/SeaState: the sea at a vehicle, rt/<vehicle>/sea_state, at its odometry_rate_hz when the scenario has
// waves (world.waves). W is the world frame (ENU).
struct SeaState {
  double stamp = 0.0;                          // sim time [s]
  std::string frame_id;                        // the world frame
  double surface_z = 0.0;                      // the instantaneous surface's z over the vehicle's B origin [m]
  std::array<double, 2> surface_slope{};       // d eta / dx, d eta / dy there
  double depth = 0.0;                          // of B's origin below the surface [m] (< 0: above it)
  std::array<double, 3> orbital_velocity{};    // the waves' water velocity at B's origin, W [m/s]; 0 in the air
  double significant_height = 0.0;             // Hs [m]
  double peak_period = 0.0;                    // Tp [s] (listed waves: the longest period)
  double mean_direction = 0.0;                 // the waves travel toward, from W's x toward y [rad]
  double build_up = 0.0;                       // the sea's build-up factor in [0, 1]
};

struct MagneticField {
  double stamp = 0.0;                               // sim time of the sample [s]
  std::string frame_id;                             // the sensor's frame
  std::array<double, 3> magnetic_field{};           // B in S [T]
  std::array<double, 9> magnetic_field_covariance{};  // 3x3 row-major [T^2]; all 0: unknown
};

// sensor_msgs/NavSatFix of a GNSS receiver, rt/<vehicle>/<sensor>. Without a fix (status kStatusNoFix:
// hadald's GPS has none while its antenna is under water) latitude, longitude and altitude are NaN.
struct NavSatFix {
  // NavSatStatus.status
  static constexpr std::int8_t kStatusNoFix = -1;
  static constexpr std::int8_t kStatusFix = 0;
  static constexpr std::int8_t kStatusSbasFix = 1;
  static constexpr std::int8_t kStatusGbasFix = 2;
  // NavSatStatus.service (bits)
  static constexpr std::uint16_t kServiceGps = 1;
  static constexpr std::uint16_t kServiceGlonass = 2;
  static constexpr std::uint16_t kServiceCompass = 4;
  static constexpr std::uint16_t kServiceGalileo = 8;
  // position_covariance_type
  static constexpr std::uint8_t kCovarianceTypeUnknown = 0;
  static constexpr std::uint8_t kCovarianceTypeApproximated = 1;
  static constexpr std::uint8_t kCovarianceTypeDiagonalKnown = 2;
  static constexpr std::uint8_t kCovarianceTypeKnown = 3;

  double stamp = 0.0;                  // sim time of the sample [s]
  std::string frame_id;                // the antenna's frame
  std::int8_t status = kStatusNoFix;
  std::uint16_t service = 0;
  double latitude = 0.0;               // WGS84 [deg], + north
  double longitude = 0.0;              // WGS84 [deg], + east
  double altitude = 0.0;               // above the WGS84 ellipsoid [m]
  std::array<double, 9> position_covariance{};  // 3x3 row-major, east/north/up [m^2]
  std::uint8_t position_covariance_type = kCovarianceTypeUnknown;

  bool has_fix() const { return status >= kStatusFix; }
};

// marine_acoustic_msgs/Dvl of a Doppler velocity log, rt/<vehicle>/<sensor>: one ping. Frame S: the
// DVL's, z along its axis, x vehicle forward. Field names as the message's, except `covar` spelled out
// and `range` as `ranges`.
struct Dvl {
  // velocity_mode
  static constexpr std::uint8_t kVelocityModeNone = 0;  // no velocity this ping
  static constexpr std::uint8_t kVelocityModeBottomTrack = 1;
  static constexpr std::uint8_t kVelocityModeWaterTrack = 2;
  // dvl_type
  static constexpr std::uint8_t kDvlTypePiston = 0;
  static constexpr std::uint8_t kDvlTypePhasedArray = 1;

  double stamp = 0.0;     // sim time the velocity is valid at [s]
  std::string frame_id;   // the DVL's frame
  std::uint8_t velocity_mode = kVelocityModeNone;
  std::uint8_t dvl_type = kDvlTypePiston;
  std::array<double, 3> velocity{};             // relative to the bottom or water layer, in S [m/s]
  std::array<double, 9> velocity_covariance{};  // 3x3 row-major [m^2/s^2]; -1: unknown
  double altitude = 0.0;     // mean vertical range of the good beams [m]
  double course_gnd = 0.0;   // atan2(velocity y, velocity x) [rad]
  double speed_gnd = 0.0;    // hypot(velocity x, velocity y) [m/s]
  std::uint8_t num_good_beams = 0;
  double sound_speed = 0.0;  // the DVL assumed [m/s]
  bool beam_ranges_valid = false;
  bool beam_velocities_valid = false;
  std::array<std::array<double, 3>, 4> beam_unit_vec{};  // beam directions in S (unit vectors)
  std::array<double, 4> ranges{};                  // slant range along each beam [m]
  std::array<double, 4> range_covariance{};        // [m^2]
  std::array<double, 4> beam_quality{};            // per-beam quality figure (unitless)
  std::array<double, 4> beam_velocity{};           // along-beam velocity [m/s]
  std::array<double, 4> beam_velocity_covariance{};  // [m^2/s^2]
};

// sensor_msgs/Range of a single-beam range finder (e.g. an altimeter), rt/<vehicle>/<sensor>: the
// distance along the sensor's x axis. Values outside [min_range, max_range] are not measurements
// (ROS REP 117: +inf no return within max_range, -inf closer than min_range).
struct Range {
  // radiation_type
  static constexpr std::uint8_t kUltrasound = 0;
  static constexpr std::uint8_t kInfrared = 1;

  double stamp = 0.0;            // sim time of the sample [s]
  std::string frame_id;          // the sensor's frame
  std::uint8_t radiation_type = kUltrasound;
  double field_of_view = 0.0;    // full cone angle [rad]
  double min_range = 0.0;        // [m]
  double max_range = 0.0;        // [m]
  double range = 0.0;            // [m]
};

// hadal_msgs/UsblFixes of a USBL transceiver, rt/<vehicle>/<sensor>: the fixes of the transponders whose
// replies arrived within one physics step (usually one), each stamped at its reply's reception.
struct UsblFix {
  double stamp = 0.0;               // reception of the reply [s]
  double interrogation_stamp = 0.0; // emission of the interrogation [s]
  std::string target;               // the transponder's vehicle
  std::uint64_t interrogation = 0;  // the interrogation's index
  double travel_time = 0.0;         // two-way, turnaround removed [s]
  double range = 0.0;               // slant range [m]
  double bearing = 0.0;             // atan2(y_S, x_S) [rad]
  double elevation = 0.0;           // asin(z_S / range), negative below [rad]
  std::array<double, 3> position{};        // the transponder in the transceiver's frame S [m]
  std::array<double, 9> position_covariance{};  // in S, row-major [m^2]
  std::array<double, 3> position_world{};  // the same in W (ENU) [m]
  double latitude = 0.0;            // WGS84 [deg]
  double longitude = 0.0;           // WGS84 [deg]
  double altitude = 0.0;            // above the WGS84 ellipsoid [m]
  double snr_db = 0.0;              // the reply's SNR at the transceiver [dB]
};
struct UsblFixes {
  double stamp = 0.0;               // the last fix's [s]
  std::string frame_id;             // the transceiver's frame S
  std::vector<UsblFix> fixes;
};

// hadal_msgs/AcousticPackets of an acoustic modem, rt/<vehicle>/<modem>/rx: the packets it decoded within one
// physics step (usually one), each stamped at the end of its reception.
struct AcousticPacket {
  double transmit_stamp = 0.0;      // start of its transmission [s]
  double stamp = 0.0;               // end of its reception [s]
  std::string source;               // "<vehicle>/<modem>" of the sender
  std::string destination;          // as sent: "" every modem, "<vehicle>" or "<vehicle>/<modem>"
  std::uint64_t sequence_number = 0;  // the sender's packet index
  std::vector<std::uint8_t> payload;
  double travel_time = 0.0;         // from the start of transmission to the start of reception [s]
  double snr_db = 0.0;              // signal to noise and interference over the packet [dB]
};
struct AcousticPackets {
  double stamp = 0.0;               // the last packet's [s]
  std::string frame_id;             // the modem's
  std::vector<AcousticPacket> packets;
};

// hadal_msgs/LblRanges of an LBL transceiver, rt/<vehicle>/<sensor>: the ranges to the beacons whose replies
// arrived within one physics step, each stamped at its reply's reception.
struct LblRange {
  double stamp = 0.0;               // reception of the reply [s]
  double interrogation_stamp = 0.0; // emission of the interrogation [s]
  std::string beacon;               // the beacon's name
  std::uint64_t interrogation = 0;  // the interrogation's index
  double travel_time = 0.0;         // two-way, turnaround removed [s]
  double range = 0.0;               // [m]
  double range_variance = 0.0;      // [m^2]
  std::array<double, 3> beacon_position{};  // in W (ENU) [m]
  double snr_db = 0.0;              // the reply's SNR at the transceiver [dB]
};
struct LblRanges {
  double stamp = 0.0;               // the last range's [s]
  std::string frame_id;             // the transceiver's frame
  std::vector<LblRange> ranges;
};

// sensor_msgs/LaserScan of a fan of range beams (a profiler), rt/<vehicle>/<sensor>: one range per beam,
// beam k at angle_min + k angle_increment about the sensor frame's z axis from its x axis. Values
// outside [range_min, range_max] are not measurements (REP 117: +inf no return, -inf too close). The
// stamp is the sim time of the scan's snapshot; the sample arrives its latency later.
struct LaserScan {
  double stamp = 0.0;             // sim time of the scan [s]
  std::string frame_id;           // the sensor's frame
  double angle_min = 0.0;         // first beam [rad]
  double angle_max = 0.0;         // last beam [rad]
  double angle_increment = 0.0;   // between beams [rad]
  double time_increment = 0.0;    // between beams' measurements [s]
  double scan_time = 0.0;         // between scans [s]
  double range_min = 0.0;         // [m]
  double range_max = 0.0;         // [m]
  std::vector<float> ranges;      // one per beam [m]
  std::vector<float> intensities;  // device-specific; may be empty
};

// marine_acoustic_msgs/PingInfo of a sonar ping: centre frequency, the sound speed at the sonar, and per beam
// its -3 dB widths (tx: across the fan, rx: in the fan).
struct PingInfo {
  double frequency_hz = 0.0;
  double sound_speed_m_per_s = 0.0;
  std::vector<float> tx_beamwidths_rad;
  std::vector<float> rx_beamwidths_rad;
};

// marine_acoustic_msgs/SonarImageData: beam_count beams of samples, little-endian, dtype kUint8 (the level
// mapped onto a display window) or kFloat32 (intensity after TVG [uPa^2]).
struct SonarImageData {
  static constexpr std::uint32_t kUint8 = 0;
  static constexpr std::uint32_t kFloat32 = 8;
  bool is_bigendian = false;
  std::uint32_t dtype = kUint8;
  std::uint32_t beam_count = 0;
  std::vector<std::uint8_t> data;

  std::size_t size() const { return dtype == kFloat32 ? data.size() / 4 : data.size(); }
  // Sample i as a number; throws std::logic_error for another dtype or a big-endian image, std::out_of_range
  // past the end.
  double sample(std::size_t i) const;
};

// marine_acoustic_msgs/ProjectedSonarImage of a forward-looking sonar, rt/<vehicle>/<sensor>: beam k's
// direction (0, -sin a, cos a) in the sonar frame (z forward, x up: a > 0 to port), range bin centres, samples
// range-major (sample(bin, beam) = image.sample(bin * beams + beam)).
struct ProjectedSonarImage {
  double stamp = 0.0;  // sim time of the ping [s]
  std::string frame_id;
  PingInfo ping_info;
  std::vector<std::array<double, 3>> beam_directions;
  std::vector<float> ranges;  // [m]
  SonarImageData image;

  // Beam k's azimuth atan2(-y, z) [rad], positive to port.
  double beam_azimuth(std::size_t k) const;
  double sample(std::size_t bin, std::size_t beam) const;
};

// marine_acoustic_msgs/RawSonarImage of one side-scan channel, rt/<vehicle>/<sensor>/port or .../starboard:
// samples_per_beam samples, sample i from range (sample0 + i) c / (2 sample_rate) [m].
struct RawSonarImage {
  double stamp = 0.0;  // [s]
  std::string frame_id;
  PingInfo ping_info;
  double sample_rate_hz = 0.0;
  std::uint32_t samples_per_beam = 0;
  std::uint32_t sample0 = 0;
  std::vector<float> tx_delays_s;
  std::vector<float> tx_angles_rad;
  std::vector<float> rx_angles_rad;  // + to starboard
  SonarImageData image;

  // The range at which sample i starts [m].
  double sample_range_m(std::size_t i) const;
};

// marine_acoustic_msgs/SonarDetections of a multibeam, rt/<vehicle>/<sensor>: per beam a flag (0 good, 1 no
// detection), the two-way travel time, intensity and steering angles.
struct SonarDetections {
  static constexpr std::uint8_t kDetectOk = 0;
  double stamp = 0.0;  // [s]
  std::string frame_id;
  PingInfo ping_info;
  std::vector<std::uint8_t> flags;
  std::vector<float> two_way_travel_times_s;
  std::vector<float> tx_delays_s;
  std::vector<float> intensities;
  std::vector<float> tx_angles_rad;  // along track, + forward
  std::vector<float> rx_angles_rad;  // across track, + to starboard

  // Beam k's slant range c t / 2 [m] (straight rays, c the ping's sound speed); NaN without a detection.
  double range_m(std::size_t k) const;
};

// sensor_msgs/Image of a camera: rt/<vehicle>/<camera>/image_raw (encoding "rgb8": 3 bytes per pixel
// R, G, B, or "mono8") or rt/<vehicle>/<camera>/depth ("32FC1": one little-endian float per pixel,
// metres along the optical axis, NaN where nothing is hit). Row-major, `step` bytes per row. frame_id
// is the camera's optical frame (z forward, x right, y down); the stamp the sim time of the snapshot
// the frame was rendered from.
struct Image {
  double stamp = 0.0;  // [s]
  std::string frame_id;
  std::uint32_t height = 0;  // rows [px]
  std::uint32_t width = 0;   // columns [px]
  std::string encoding;
  bool is_bigendian = false;
  std::uint32_t step = 0;  // bytes per row
  std::vector<std::uint8_t> data;

  // The depth at pixel (u, v) of a 32FC1 image [m] (NaN: no hit); throws std::logic_error for another
  // encoding and std::out_of_range outside the image.
  float depth_m(std::uint32_t u, std::uint32_t v) const;
};

// sensor_msgs/CameraInfo of a camera, rt/<vehicle>/<camera>/camera_info: its calibration exactly as
// configured. distortion_model "plumb_bob" (d = k1, k2, p1, p2, k3) or "equidistant" (d = k1..k4); k the
// 3x3 intrinsics [fx 0 cx; 0 fy cy; 0 0 1], r the rectification (identity), p the 3x4 projection, all
// row-major.
struct CameraInfo {
  double stamp = 0.0;  // [s]
  std::string frame_id;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::string distortion_model;
  std::vector<double> d;
  std::array<double, 9> k{};
  std::array<double, 9> r{};
  std::array<double, 12> p{};
};

// A sensor of the server's scenario: its vehicle, its name and its YAML type ("imu", "camera", "fls", ...).
struct SceneSensor {
  std::string vehicle;
  std::string name;
  std::string type;
};

struct ClientOptions {
  // 0..232, as hadald --domain-id; unset: $ROS_DOMAIN_ID, else 0 (the rule of every Hadal tool and of ROS 2).
  std::optional<int> domain_id;
  std::string name = "hadal_client";
  // Heartbeat timeout [s]: the server counts as gone (server_alive() false, ServerLost from a pending
  // step()) after this long without a status sample, or three of its status periods if those are longer
  // (hadald publishes rt/hadal/status at world.status_rate_hz, 10 Hz by default, in every mode, between
  // the steps of a lockstep request too). 10 s: longer than one lockstep step ever takes (it may wait for
  // a large camera frame's rendering), short beside a training run's patience.
  double server_timeout_s = 10.0;
  // DDS Security: a YAML file whose `security:` block names this client's certificate, key and the domain's
  // signed documents (paths relative to the file), the form `hadald --security FILE` takes;
  // tools/make-security-demo.sh writes one per identity (docs/dds.md, "DDS Security"). Empty: no security, and
  // then no secure server is visible at all. A file that is wrong throws std::runtime_error from the
  // constructor, `file:line:col: error: ...`; so do files Fast DDS refuses.
  std::string security_file{};
};

// A recorded message (a rosbag2 bag's, or any CDR bytes with their encapsulation header as on the wire) decoded
// into the value the client's own reader gives: double for a Clock (sim time [s]), Odometry, SimStatus, and so
// on. decode_message(type, cdr): type as a bag's topics table names it ("nav_msgs/msg/Odometry");
// std::invalid_argument for a type not among decodable_message_types() (images and sonar images are not:
// read them live), std::runtime_error for bytes that do not decode as the type.
using DecodedMessage = std::variant<double, Odometry, SimStatus, ThrusterStates, TrackStates, FinStates,
                                    BuoyancyEngineStates, DropWeightStates, JointStates, FluidPressure, Imu,
                                    MagneticField, Wrench, NavSatFix, Dvl, Range, LaserScan, CameraInfo,
                                    SonarDetections, UsblFixes, LblRanges, AcousticPackets, CableShape,
                                    WinchState, SeaState>;
DecodedMessage decode_message(const std::string& type, const std::vector<std::uint8_t>& cdr);
std::vector<std::string> decodable_message_types();

// The DDS domain a client with ClientOptions::domain_id = `domain_id` joins: it, or $ROS_DOMAIN_ID, or 0.
// std::invalid_argument outside 0..232 (or for a ROS_DOMAIN_ID that is no domain id).
int resolve_domain_id(std::optional<int> domain_id);

// Errors of the client. Every one is a ClientError; the subclasses say what went wrong.
class ClientError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
// No server answers on this domain (no lockstep server's reader for step()/reset()).
class ServerNotFound : public ClientError {
 public:
  using ClientError::ClientError;
};
// The server went silent (no status heartbeat within the heartbeat timeout, ClientOptions::server_timeout_s)
// while a request waited for its reply: it stopped, crashed or the link is down. The request is lost; once
// a server publishes again (wait_for_server()), requests work again with the same client.
class ServerLost : public ClientError {
 public:
  using ClientError::ClientError;
};
// The server did not reply in time.
class Timeout : public ClientError {
 public:
  using ClientError::ClientError;
};
// A vehicle the server does not have (the server's refusal of a step or reset request).
class UnknownVehicle : public ClientError {
 public:
  UnknownVehicle(const std::string& vehicle, const std::string& what) : ClientError(what), vehicle_(vehicle) {}
  const std::string& vehicle() const { return vehicle_; }

 private:
  std::string vehicle_;
};
// A sensor a vehicle does not have, or has as another type (Python's wait_imu on a DVL): raised by the
// Python client from the server's scene (Client::scene_sensors).
class UnknownSensor : public ClientError {
 public:
  UnknownSensor(const std::string& vehicle, const std::string& sensor, const std::string& what)
      : ClientError(what), vehicle_(vehicle), sensor_(sensor) {}
  const std::string& vehicle() const { return vehicle_; }
  const std::string& sensor() const { return sensor_; }

 private:
  std::string vehicle_, sensor_;
};
// The server refused a request (a wrong setpoint count, a NaN, a value out of range, ...); reason() is
// the server's own words.
class CommandRejected : public ClientError {
 public:
  explicit CommandRejected(const std::string& reason)
      : ClientError("step request refused: " + reason), reason_(reason) {}
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

// A pose of the body frame B in the world W (ENU).
struct Pose {
  std::array<double, 3> p_WB{};            // position [m]
  std::array<double, 4> q_WB{0, 0, 0, 1};  // orientation quaternion x, y, z, w (unit)
};

// What a reset starts from (Client::reset).
struct ResetOptions {
  std::optional<std::uint64_t> seed;  // seed of the sensors' noise streams; the scenario's world.seed if empty
  std::vector<std::pair<std::string, Pose>> poses;  // vehicles placed elsewhere than their scenario pose, at rest
};

class Client {
 public:
  explicit Client(const ClientOptions& options = {});
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Waits until the server is alive (server_alive(): so discovery is done, and after a server restart, the
  // new one is up). False on timeout.
  bool wait_for_server(double timeout_s);
  // True while status samples keep coming: the last arrived within the heartbeat timeout
  // (ClientOptions::server_timeout_s). False before the first and after the server went silent.
  bool server_alive() const;
  // Wall seconds since the last status sample arrived; +infinity before the first.
  double seconds_since_status() const;
  // Waits until every subscription made so far (on_odometry, on_clock, ...) is matched with a server
  // writer, so no sample published from now on is missed. False on timeout.
  bool wait_for_subscriptions(double timeout_s);
  // The most recent status, if any arrived.
  std::optional<SimStatus> latest_status() const;
  // The server's sensors as its scene lists them (rt/hadal/scene, which each client is sent as it joins):
  // nullopt until the scene has come.
  std::optional<std::vector<SceneSensor>> scene_sensors() const;

  // Subscriptions: the callback runs on a DDS thread for every sample. Subscribing to a sensor's topic
  // with the wrong message type (e.g. on_imu on a magnetometer already subscribed with
  // on_magnetic_field in this client) throws std::invalid_argument naming both types.
  void on_clock(std::function<void(double sim_time_s)> callback);
  void on_status(std::function<void(const SimStatus&)> callback);
  void on_odometry(const std::string& vehicle, std::function<void(const Odometry&)> callback);
  void on_thruster_state(const std::string& vehicle, std::function<void(const ThrusterStates&)> callback);
  // rt/<vehicle>/tracks/state (a vehicle with tracks: its belt speeds, motor torques and currents).
  void on_track_state(const std::string& vehicle, std::function<void(const TrackStates&)> callback);
  // rt/<vehicle>/fins/state, buoyancy_engines/state, drop_weights/state (vehicles with those actuators).
  void on_fin_state(const std::string& vehicle, std::function<void(const FinStates&)> callback);
  void on_buoyancy_engine_state(const std::string& vehicle, std::function<void(const BuoyancyEngineStates&)> callback);
  void on_drop_weight_state(const std::string& vehicle, std::function<void(const DropWeightStates&)> callback);
  // rt/<vehicle>/joint_states of an articulated vehicle, at its odometry rate.
  void on_joint_state(const std::string& vehicle, std::function<void(const JointStates&)> callback);
  void on_fluid_pressure(const std::string& vehicle, const std::string& sensor,
                         std::function<void(const FluidPressure&)> callback);
  void on_imu(const std::string& vehicle, const std::string& sensor, std::function<void(const Imu&)> callback);
  void on_magnetic_field(const std::string& vehicle, const std::string& sensor,
                         std::function<void(const MagneticField&)> callback);
  void on_wrench(const std::string& vehicle, const std::string& sensor, std::function<void(const Wrench&)> callback);
  void on_nav_sat_fix(const std::string& vehicle, const std::string& sensor,
                      std::function<void(const NavSatFix&)> callback);
  void on_dvl(const std::string& vehicle, const std::string& sensor, std::function<void(const Dvl&)> callback);
  void on_range(const std::string& vehicle, const std::string& sensor, std::function<void(const Range&)> callback);
  void on_usbl_fixes(const std::string& vehicle, const std::string& sensor,
                     std::function<void(const UsblFixes&)> callback);
  void on_lbl_ranges(const std::string& vehicle, const std::string& sensor,
                     std::function<void(const LblRanges&)> callback);
  // A cable's (the scenario's `cables`): the force it puts on what holds its `end` ("from" or "to"; in W, the
  // world frame) and its shape, at the cable's rate_hz.
  void on_cable_force(const std::string& cable, const std::string& end, std::function<void(const Wrench&)> callback);
  void on_cable_shape(const std::string& cable, std::function<void(const CableShape&)> callback);
  // A cable's winch (a `winch:` at one of its ends), at the cable's rate_hz.
  void on_winch_state(const std::string& cable, std::function<void(const WinchState&)> callback);
  // The sea at a vehicle (rt/<vehicle>/sea_state), at its odometry rate, when the scenario has waves.
  void on_sea_state(const std::string& vehicle, std::function<void(const SeaState&)> callback);
  // An acoustic modem's decoded packets (rt/<vehicle>/<modem>/rx).
  void on_modem_packets(const std::string& vehicle, const std::string& modem,
                        std::function<void(const AcousticPackets&)> callback);
  void on_laser_scan(const std::string& vehicle, const std::string& sensor,
                     std::function<void(const LaserScan&)> callback);
  // A camera's colour (or mono) images, depth images and calibration (its three topics).
  void on_image(const std::string& vehicle, const std::string& camera, std::function<void(const Image&)> callback);
  void on_depth_image(const std::string& vehicle, const std::string& camera,
                      std::function<void(const Image&)> callback);
  void on_camera_info(const std::string& vehicle, const std::string& camera,
                      std::function<void(const CameraInfo&)> callback);
  // Sonars: a forward-looking sonar's images, a multibeam's detections, and one side-scan channel
  // (`channel` "port" or "starboard": rt/<vehicle>/<sensor>/<channel>).
  void on_sonar_image(const std::string& vehicle, const std::string& sensor,
                      std::function<void(const ProjectedSonarImage&)> callback);
  void on_sonar_detections(const std::string& vehicle, const std::string& sensor,
                           std::function<void(const SonarDetections&)> callback);
  void on_raw_sonar_image(const std::string& vehicle, const std::string& sensor, const std::string& channel,
                          std::function<void(const RawSonarImage&)> callback);

  // Publishes the vehicle's control vector (one entry per actuator: thrusters, tracks, fins, buoyancy
  // engines, drop weights, each kind in scenario order; normalised [-1, 1], a drop weight 0 or 1) on
  // rt/<vehicle>/actuators/commands (std_msgs/Float64MultiArray, as a ros2_control forward command
  // controller's), waiting up to 2 s for the server's reader on first use. The commands are also attached
  // to the next step() request, so in lockstep they take effect exactly before that request's first step.
  // The server validates them: a rejected command shows up in SimStatus::rejected_commands / last_error.
  void set_commands(const std::string& vehicle, const std::vector<double>& commands);
  // Lockstep only: the control vector for the next step() or reset() request, attached to it and not
  // published on the commands topic (one DDS sample less per control period; what the Python
  // environments use). Validated by the server with the request (CommandRejected, UnknownVehicle).
  void attach_commands(const std::string& vehicle, const std::vector<double>& commands);
  // An articulated vehicle's joint controller command (its scenario's `joint_controllers`): one value per
  // joint of the group, in its order (a position [rad or m], rate or effort; a gripper's: [position] or
  // [position, max_effort], every finger at its multiplier times the position), published on
  // rt/<vehicle>/<controller>/commands (std_msgs/Float64MultiArray, as ros2_control's forward command
  // controllers take it) and attached to the next step() request, like set_commands. The server refuses a
  // wrong length, NaN, a position outside the joint's limits or an unknown controller (last_error; in
  // lockstep, CommandRejected from step()).
  void set_joint_commands(const std::string& vehicle, const std::string& controller,
                          const std::vector<double>& values);
  // Lockstep only: a joint controller's command for the next step() or reset() request, attached to it and
  // not published (as attach_commands for the control vector; what the Python environments use).
  void attach_joint_commands(const std::string& vehicle, const std::string& controller,
                             const std::vector<double>& values);
  // A trajectory for a position group (JointTrajectory above), published on
  // rt/<vehicle>/<controller>/joint_trajectory (trajectory_msgs/JointTrajectory) and attached to the next
  // step() request, like set_joint_commands; it replaces the group's command or trajectory when it starts.
  // The server refuses joint names that are not the group's, a waypoint outside a joint's limits, times that
  // do not increase, NaN (last_error; in lockstep, CommandRejected from step()).
  void set_joint_trajectory(const std::string& vehicle, const std::string& controller,
                            const JointTrajectory& trajectory);
  // Gives the vehicle's acoustic modem `modem` a packet to send to `destination` ("" every modem, a vehicle's
  // modems, or "<vehicle>/<modem>"): published on rt/<vehicle>/<modem>/tx (hadal_msgs/AcousticPacket), waiting up
  // to 2 s for the server's reader on first use. The server queues it and sends it through the water; it refuses
  // an empty payload or one longer than the modem's max_payload_bytes, an unknown destination, or a send when the
  // modem's queue is full (SimStatus::rejected_commands / last_error). Every call is one packet.
  void send_packet(const std::string& vehicle, const std::string& modem, const std::vector<std::uint8_t>& payload,
                   const std::string& destination = "");
  // Lockstep only: the packet is attached to the next step() or reset() request instead of published, so it is
  // queued exactly before that request's first step (deterministic runs); refused packets make step() throw
  // CommandRejected (checked before anything is applied). Packets attached to one request go in call order.
  void attach_packet(const std::string& vehicle, const std::string& modem, const std::vector<std::uint8_t>& payload,
                     const std::string& destination = "");
  // Commands a cable's winch: run at speed_mps (+ pays out, - hauls in) until told otherwise or a limit (its
  // min_length, the drum's end); with target_length_m > 0, run at |speed_mps| toward that length in the water and
  // stop there. Published on rt/hadal/cables/<cable>/winch/command (hadal_msgs/WinchCommand) and attached to the
  // next step() request, like set_commands. The server refuses a cable without a winch, a speed beyond its
  // max_speed, a target beyond its drum_length or below its min_length, NaN (last_error; in lockstep,
  // CommandRejected from step()).
  void command_winch(const std::string& cable, double speed_mps, double target_length_m = 0.0);
  // Lockstep only: the winch command for the next step() or reset() request, attached and not published.
  void attach_winch(const std::string& cable, double speed_mps, double target_length_m = 0.0);
  // The names before the control vector drove every actuator kind: refused at compile time, naming the
  // new ones.
  template <class... Args>
  void set_thrusters(Args&&...) {
    static_assert(sizeof...(Args) < 0, "Client::set_thrusters was renamed set_commands (it commands every actuator)");
  }
  template <class... Args>
  void attach_setpoints(Args&&...) {
    static_assert(sizeof...(Args) < 0, "Client::attach_setpoints was renamed attach_commands");
  }

  // Lockstep: advances the server by `steps` physics steps and returns the sim time reached [s].
  // Throws ServerNotFound without a lockstep server, Timeout without a reply within timeout_s, ServerLost
  // when the server's status heartbeat stops while it waits (long before timeout_s),
  // UnknownVehicle for commands of a vehicle the server does not have, CommandRejected when the server
  // refuses the request (e.g. a wrong number of commands), with its reason.
  double step(std::uint32_t steps, double timeout_s = 30.0);
  // Lockstep: starts the run over from the scenario's initial state at sim time 0 (every vehicle at its
  // scenario pose or the given one, at rest; actuators at rest; no client command; sensor noise seeded
  // from options.seed), then applies commands set since the last request, then runs `steps` steps.
  // Returns the sim time reached [s]. The server publishes the initial state (odometry at t = 0) before
  // it replies. Throws as step().
  double reset(const ResetOptions& options = {}, std::uint32_t steps = 0, double timeout_s = 30.0);

  // Lockstep without waiting: send_step() and send_reset() send the request step() and reset() would send
  // (with the commands attached so far) and return its id at once; wait_reply(id) then returns what
  // step() or reset() would have, and throws as they do. One thread can so keep several servers (one
  // client each) stepping at the same time: send to each, then wait for each (hadal.env.VectorEnv).
  // The send throws ServerNotFound as step(); each id can be waited for once (else ClientError).
  std::uint64_t send_step(std::uint32_t steps, double timeout_s = 30.0);
  std::uint64_t send_reset(const ResetOptions& options = {}, std::uint32_t steps = 0, double timeout_s = 30.0);
  double wait_reply(std::uint64_t request_id, double timeout_s = 30.0);

  // Lockstep: the vehicle's ground truth at the sim time of the last reply waited for (step(), reset(),
  // wait_reply()), as its odometry at that instant carries it (same numbers; frame_id left empty, the
  // scenario's world.frame_id). Every reply carries every vehicle's, so a lockstep client needs no
  // odometry subscription. Throws ClientError before the first reply, UnknownVehicle for a vehicle the
  // reply does not have.
  Odometry reply_odometry(const std::string& vehicle) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hadal
