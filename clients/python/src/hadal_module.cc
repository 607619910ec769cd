// Python bindings of libhadal_client (module hadal._hadal; the public package is `hadal`).
//
// Python sees a polling API rather than callbacks: the binding subscribes on first use and keeps the
// latest sample per topic, so no Python code ever runs on a DDS thread (no GIL hand-offs, no
// deadlock at shutdown). Blocking calls release the GIL. Vectors come back as numpy arrays.
#include "hadal_client/client.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <type_traits>

namespace py = pybind11;

namespace {

template <std::size_t N>
py::array_t<double> to_numpy(const std::array<double, N>& values) {
  py::array_t<double> out(N);
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

// A row-major 3x3 matrix (a ROS covariance) as a (3, 3) array.
py::array_t<double> to_numpy_3x3(const std::array<double, 9>& values) {
  py::array_t<double> out({3, 3});
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

// Rows of vectors as an (R, C) array.
template <std::size_t R, std::size_t C>
py::array_t<double> to_numpy(const std::array<std::array<double, C>, R>& rows) {
  py::array_t<double> out({R, C});
  double* data = out.mutable_data();
  for (const auto& row : rows) data = std::copy(row.begin(), row.end(), data);
  return out;
}

template <class T>
py::array_t<T> to_numpy(const std::vector<T>& values) {
  py::array_t<T> out(values.size());
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

// A sample's stamp, whether kept by value or (images) by shared pointer.
template <class Sample>
double stamp_of(const Sample& s) {
  return s.stamp;
}
template <class Sample>
double stamp_of(const std::shared_ptr<const Sample>& s) {
  return s->stamp;
}

// An image's pixels as a numpy array viewing the image's bytes (no copy; the array keeps `owner`, the
// Python Image, alive): (H, W, 3) uint8 for rgb8, (H, W) uint8 for mono8, (H, W) float32 for 32FC1.
py::array image_array(const hadal::Image& image, py::handle owner) {
  const auto h = static_cast<py::ssize_t>(image.height), w = static_cast<py::ssize_t>(image.width);
  const auto step = static_cast<py::ssize_t>(image.step);
  void* data = const_cast<std::uint8_t*>(image.data.data());
  if (image.encoding == "rgb8") {
    return py::array(py::dtype::of<std::uint8_t>(), {h, w, py::ssize_t{3}}, {step, py::ssize_t{3}, py::ssize_t{1}},
                     data, owner);
  }
  if (image.encoding == "mono8") {
    return py::array(py::dtype::of<std::uint8_t>(), {h, w}, {step, py::ssize_t{1}}, data, owner);
  }
  if (image.encoding == "32FC1" && !image.is_bigendian) {
    return py::array(py::dtype::of<float>(), {h, w}, {step, py::ssize_t{4}}, data, owner);
  }
  throw std::invalid_argument("Image.array: unsupported encoding '" + image.encoding + "'");
}

// A sonar image's samples as an (rows, beam_count) array: uint8 or float32 (little-endian), a copy.
py::array sonar_array(const hadal::SonarImageData& image) {
  if (image.beam_count == 0) throw std::invalid_argument("sonar image without beams");
  const bool f32 = image.dtype == hadal::SonarImageData::kFloat32;
  if ((!f32 && image.dtype != hadal::SonarImageData::kUint8) || image.is_bigendian) {
    throw std::invalid_argument("sonar image: dtype " + std::to_string(image.dtype) +
                                " (only little-endian uint8 and float32)");
  }
  const auto cols = static_cast<py::ssize_t>(image.beam_count);
  const auto rows = static_cast<py::ssize_t>(image.size()) / cols;
  py::array out = f32 ? py::array(py::dtype::of<float>(), {rows, cols}) : py::array(py::dtype::of<std::uint8_t>(), {rows, cols});
  std::memcpy(out.mutable_data(), image.data.data(), static_cast<std::size_t>(rows * cols) * (f32 ? 4u : 1u));
  return out;
}

// Latest sample per key, with a wait for a sample at or after a sim time.
template <class Sample>
class Latest {
 public:
  void put(const std::string& key, const Sample& s) {
    std::lock_guard<std::mutex> lock(mutex_);
    samples_[key] = s;
    changed_.notify_all();
  }
  std::optional<Sample> get(const std::string& key) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = samples_.find(key);
    if (found == samples_.end()) return std::nullopt;
    return found->second;
  }
  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    samples_.clear();
  }
  std::optional<Sample> wait(const std::string& key, double min_stamp, double timeout_s) const {
    std::unique_lock<std::mutex> lock(mutex_);
    const bool ok = changed_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] {
      auto found = samples_.find(key);
      return found != samples_.end() && stamp_of(found->second) >= min_stamp - 1e-9;
    });
    if (!ok) return std::nullopt;
    return samples_.at(key);
  }

 private:
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::map<std::string, Sample> samples_;
};

using ImagePtr = std::shared_ptr<const hadal::Image>;
using SonarImagePtr = std::shared_ptr<const hadal::ProjectedSonarImage>;  // large too: kept, not copied

class PyClient {
 public:
  PyClient(std::optional<int> domain_id, const std::string& name, double server_timeout_s,
           const std::optional<std::filesystem::path>& security_file)
      : client_(std::make_shared<hadal::Client>(hadal::ClientOptions{
            domain_id, name, server_timeout_s, security_file ? security_file->string() : std::string()})) {}

  // Leaves the DDS domain (its participant and shared-memory segments go) once no call on another thread
  // still uses it; later calls raise.
  void close() {
    std::shared_ptr<hadal::Client> client;
    {
      std::lock_guard<std::mutex> lock(client_mutex_);
      client = std::move(client_);
    }
  }
  bool closed() const {
    std::lock_guard<std::mutex> lock(client_mutex_);
    return !client_;
  }

  bool wait_for_server(double timeout_s) { return client()->wait_for_server(timeout_s); }
  bool server_alive() const { return client()->server_alive(); }
  double seconds_since_status() const { return client()->seconds_since_status(); }
  bool wait_for_subscriptions(double timeout_s) { return client()->wait_for_subscriptions(timeout_s); }
  std::optional<hadal::SimStatus> status() const { return client()->latest_status(); }

  // A vehicle the server does not have raises UnknownVehicle at once, naming those it has (from its
  // status; before the first status nothing is known, and a wait that ends empty checks again).
  void check_vehicle(const std::string& vehicle) const {
    const std::optional<hadal::SimStatus> status = client()->latest_status();
    if (!status) return;
    const std::vector<std::string>& names = status->vehicle_names;
    if (std::find(names.begin(), names.end(), vehicle) != names.end()) return;
    std::string known;
    for (const std::string& name : names) known += (known.empty() ? "'" : ", '") + name + "'";
    throw hadal::UnknownVehicle(vehicle, "no vehicle '" + vehicle + "' on this server (vehicles: " +
                                             (known.empty() ? std::string("none") : known) + ")");
  }
  // A sensor the vehicle does not have, or has as another type than the wait's `kind` ("imu", "image", ...)
  // reads, raises UnknownSensor at once naming the vehicle's sensors and their types (from the server's scene;
  // before the scene has come nothing is known). `sensor` may be "<sensor>/<channel>" (a side-scan's).
  void check_sensor(const std::string& vehicle, const std::string& sensor, const std::string& kind) const {
    check_vehicle(vehicle);
    const std::optional<std::vector<hadal::SceneSensor>> sensors = client()->scene_sensors();
    if (!sensors) return;
    const std::string name = sensor.substr(0, sensor.find('/'));
    const std::string type = sensor_type_of(kind);
    const hadal::SceneSensor* found = nullptr;
    std::string known;
    for (const hadal::SceneSensor& s : *sensors) {
      if (s.vehicle != vehicle) continue;
      known += (known.empty() ? "'" : ", '") + s.name + "' (" + s.type + ")";
      if (s.name == name) found = &s;
    }
    if (found != nullptr && (type.empty() || found->type == type)) return;
    const std::string listed = " (its sensors: " + (known.empty() ? std::string("none") : known) + ")";
    if (found == nullptr) {
      throw hadal::UnknownSensor(vehicle, name, "no sensor '" + name + "' on vehicle '" + vehicle + "'" + listed);
    }
    throw hadal::UnknownSensor(vehicle, name, "sensor '" + name + "' of vehicle '" + vehicle + "' is of type " +
                                                  found->type + ", not " + type + listed);
  }
  // The sensor type (YAML `type:`) whose samples a wait of `kind` reads ("" when any may).
  static std::string sensor_type_of(const std::string& kind) {
    static const std::map<std::string, std::string> types = {
        {"imu", "imu"},           {"pressure", "pressure"},        {"magnetic_field", "magnetometer"},
        {"nav_sat_fix", "gps"},   {"dvl", "dvl"},                  {"range", "altimeter"},
        {"laser_scan", "profiler"}, {"image", "camera"},           {"depth", "camera"},
        {"camera_info", "camera"}, {"sonar_image", "fls"},         {"sonar_detections", "multibeam"},
        {"raw_sonar_image", "sidescan"}, {"wrench", "force_torque"}, {"usbl_fixes", "usbl"},   {"lbl_ranges", "lbl"},
        {"modem_packets", "modem"}};
    const auto it = types.find(kind);
    return it == types.end() ? std::string() : it->second;
  }
  // Returns `sample`; when it is empty, first checks the vehicle (the status may have come meanwhile).
  template <class Sample>
  std::optional<Sample> checked(std::optional<Sample> sample, const std::string& vehicle) const {
    if (!sample) check_vehicle(vehicle);
    return sample;
  }

  void subscribe(const std::string& vehicle) {
    check_vehicle(vehicle);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!subscribed_.emplace(vehicle, true).second) return;
    client()->on_odometry(vehicle, [this, vehicle](const hadal::Odometry& o) { odometry_.put(vehicle, o); });
    client()->on_thruster_state(vehicle,
                              [this, vehicle](const hadal::ThrusterStates& t) { thrusters_.put(vehicle, t); });
  }
  std::optional<hadal::Odometry> odometry(const std::string& vehicle) {
    subscribe(vehicle);
    return odometry_.get(vehicle);
  }
  std::optional<hadal::Odometry> wait_odometry(const std::string& vehicle, double min_stamp, double timeout_s) {
    subscribe(vehicle);
    return checked(odometry_.wait(vehicle, min_stamp, timeout_s), vehicle);
  }
  std::optional<hadal::ThrusterStates> thruster_state(const std::string& vehicle) {
    subscribe(vehicle);
    return thrusters_.get(vehicle);
  }
  std::optional<hadal::ThrusterStates> wait_thruster_state(const std::string& vehicle, double min_stamp,
                                                           double timeout_s) {
    subscribe(vehicle);
    return checked(thrusters_.wait(vehicle, min_stamp, timeout_s), vehicle);
  }
  // rt/<vehicle>/<kind>/state of the actuator kinds besides thrusters, subscribed on first use (only
  // vehicles with such actuators publish them).
  std::optional<hadal::TrackStates> wait_track_state(const std::string& vehicle, double min_stamp, double timeout_s) {
    return wait_actuator_state("tracks", &hadal::Client::on_track_state, tracks_, vehicle, min_stamp, timeout_s);
  }
  std::optional<hadal::FinStates> wait_fin_state(const std::string& vehicle, double min_stamp, double timeout_s) {
    return wait_actuator_state("fins", &hadal::Client::on_fin_state, fins_, vehicle, min_stamp, timeout_s);
  }
  std::optional<hadal::BuoyancyEngineStates> wait_buoyancy_engine_state(const std::string& vehicle, double min_stamp,
                                                                        double timeout_s) {
    return wait_actuator_state("buoyancy_engines", &hadal::Client::on_buoyancy_engine_state, buoyancy_engines_,
                               vehicle, min_stamp, timeout_s);
  }
  std::optional<hadal::DropWeightStates> wait_drop_weight_state(const std::string& vehicle, double min_stamp,
                                                                double timeout_s) {
    return wait_actuator_state("drop_weights", &hadal::Client::on_drop_weight_state, drop_weights_, vehicle,
                               min_stamp, timeout_s);
  }
  std::optional<hadal::JointStates> wait_joint_state(const std::string& vehicle, double min_stamp, double timeout_s) {
    return wait_actuator_state("joint_states", &hadal::Client::on_joint_state, joint_states_, vehicle, min_stamp,
                               timeout_s);
  }
  // Sensors, keyed "<vehicle>/<sensor>", subscribed on first use.
  std::optional<hadal::Imu> wait_imu(const std::string& vehicle, const std::string& sensor, double min_stamp,
                                     double timeout_s) {
    return wait_sensor("imu", &hadal::Client::on_imu, imu_, vehicle, sensor, min_stamp, timeout_s);
  }
  std::optional<hadal::FluidPressure> wait_fluid_pressure(const std::string& vehicle, const std::string& sensor,
                                                          double min_stamp, double timeout_s) {
    return wait_sensor("pressure", &hadal::Client::on_fluid_pressure, pressure_, vehicle, sensor, min_stamp,
                       timeout_s);
  }
  std::optional<hadal::MagneticField> wait_magnetic_field(const std::string& vehicle, const std::string& sensor,
                                                          double min_stamp, double timeout_s) {
    return wait_sensor("magnetic_field", &hadal::Client::on_magnetic_field, magnetic_field_, vehicle, sensor,
                       min_stamp, timeout_s);
  }
  std::optional<hadal::Wrench> wait_wrench(const std::string& vehicle, const std::string& sensor, double min_stamp,
                                           double timeout_s) {
    return wait_sensor("wrench", &hadal::Client::on_wrench, wrench_, vehicle, sensor, min_stamp, timeout_s);
  }
  std::optional<hadal::NavSatFix> wait_nav_sat_fix(const std::string& vehicle, const std::string& sensor,
                                                   double min_stamp, double timeout_s) {
    return wait_sensor("nav_sat_fix", &hadal::Client::on_nav_sat_fix, nav_sat_fix_, vehicle, sensor, min_stamp,
                       timeout_s);
  }
  std::optional<hadal::Dvl> wait_dvl(const std::string& vehicle, const std::string& sensor, double min_stamp,
                                     double timeout_s) {
    return wait_sensor("dvl", &hadal::Client::on_dvl, dvl_, vehicle, sensor, min_stamp, timeout_s);
  }
  std::optional<hadal::Range> wait_range(const std::string& vehicle, const std::string& sensor, double min_stamp,
                                         double timeout_s) {
    return wait_sensor("range", &hadal::Client::on_range, range_, vehicle, sensor, min_stamp, timeout_s);
  }
  std::optional<hadal::UsblFixes> wait_usbl_fixes(const std::string& vehicle, const std::string& sensor,
                                                  double min_stamp, double timeout_s) {
    return wait_sensor("usbl_fixes", &hadal::Client::on_usbl_fixes, usbl_fixes_, vehicle, sensor, min_stamp,
                       timeout_s);
  }
  std::optional<hadal::LblRanges> wait_lbl_ranges(const std::string& vehicle, const std::string& sensor,
                                                  double min_stamp, double timeout_s) {
    return wait_sensor("lbl_ranges", &hadal::Client::on_lbl_ranges, lbl_ranges_, vehicle, sensor, min_stamp,
                       timeout_s);
  }
  std::optional<hadal::LaserScan> wait_laser_scan(const std::string& vehicle, const std::string& sensor,
                                                  double min_stamp, double timeout_s) {
    return wait_sensor("laser_scan", &hadal::Client::on_laser_scan, laser_scan_, vehicle, sensor, min_stamp,
                       timeout_s);
  }
  // A camera's topics; images are kept by shared pointer so that Python can view them without a copy.
  std::optional<ImagePtr> wait_image(const std::string& vehicle, const std::string& camera, double min_stamp,
                                     double timeout_s) {
    return wait_sensor<hadal::Image, ImagePtr>("image", &hadal::Client::on_image, image_, vehicle, camera, min_stamp,
                                               timeout_s);
  }
  std::optional<ImagePtr> wait_depth_image(const std::string& vehicle, const std::string& camera, double min_stamp,
                                           double timeout_s) {
    return wait_sensor<hadal::Image, ImagePtr>("depth", &hadal::Client::on_depth_image, depth_, vehicle, camera,
                                               min_stamp, timeout_s);
  }
  std::optional<hadal::CameraInfo> wait_camera_info(const std::string& vehicle, const std::string& camera,
                                                    double min_stamp, double timeout_s) {
    return wait_sensor("camera_info", &hadal::Client::on_camera_info, camera_info_, vehicle, camera, min_stamp,
                       timeout_s);
  }
  // Sonars.
  std::optional<SonarImagePtr> wait_sonar_image(const std::string& vehicle, const std::string& sensor, double min_stamp,
                                                double timeout_s) {
    return wait_sensor<hadal::ProjectedSonarImage, SonarImagePtr>("sonar_image", &hadal::Client::on_sonar_image,
                                                                  sonar_image_, vehicle, sensor, min_stamp, timeout_s);
  }
  std::optional<hadal::SonarDetections> wait_sonar_detections(const std::string& vehicle, const std::string& sensor,
                                                              double min_stamp, double timeout_s) {
    return wait_sensor("sonar_detections", &hadal::Client::on_sonar_detections, sonar_detections_, vehicle, sensor,
                       min_stamp, timeout_s);
  }
  std::optional<hadal::RawSonarImage> wait_raw_sonar_image(const std::string& vehicle, const std::string& sensor,
                                                           const std::string& channel, double min_stamp,
                                                           double timeout_s) {
    if (channel != "port" && channel != "starboard") {
      throw std::invalid_argument("wait_raw_sonar_image: channel must be 'port' or 'starboard' (got '" + channel + "')");
    }
    return wait_subscribed<hadal::RawSonarImage>(
        "raw_sonar_image",
        [sensor, channel](hadal::Client& c, std::function<void(const hadal::RawSonarImage&)> callback,
                          const std::string& v, const std::string& /*key*/) {
          c.on_raw_sonar_image(v, sensor, channel, std::move(callback));
        },
        raw_sonar_image_, vehicle, sensor + "/" + channel, min_stamp, timeout_s);
  }
  void set_commands(const std::string& vehicle, const std::vector<double>& commands, bool publish) {
    if (publish) {
      client()->set_commands(vehicle, commands);
    } else {
      client()->attach_commands(vehicle, commands);
    }
  }
  // A cable's end force ("from", "to") or shape: not a vehicle's sensor, so checked by the server's answer only.
  std::optional<hadal::Wrench> wait_cable_force(const std::string& cable, const std::string& end, double min_stamp,
                                                double timeout_s) {
    if (end != "from" && end != "to") {
      throw std::invalid_argument("wait_cable_force: end must be 'from' or 'to' (got '" + end + "')");
    }
    const std::string key = cable + "/" + end;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (subscribed_.emplace("cable_force:" + key, true).second) {
        client()->on_cable_force(cable, end, [this, key](const hadal::Wrench& m) { cable_forces_.put(key, m); });
      }
    }
    return cable_forces_.wait(key, min_stamp, timeout_s);
  }
  std::optional<hadal::CableShape> wait_cable_shape(const std::string& cable, double min_stamp, double timeout_s) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (subscribed_.emplace("cable_shape:" + cable, true).second) {
        client()->on_cable_shape(cable, [this, cable](const hadal::CableShape& m) { cable_shapes_.put(cable, m); });
      }
    }
    return cable_shapes_.wait(cable, min_stamp, timeout_s);
  }
  std::optional<hadal::SeaState> wait_sea_state(const std::string& vehicle, double min_stamp, double timeout_s) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (subscribed_.emplace("sea_state:" + vehicle, true).second) {
        client()->on_sea_state(vehicle, [this, vehicle](const hadal::SeaState& m) { sea_states_.put(vehicle, m); });
      }
    }
    return sea_states_.wait(vehicle, min_stamp, timeout_s);
  }
  std::optional<hadal::WinchState> wait_winch_state(const std::string& cable, double min_stamp, double timeout_s) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (subscribed_.emplace("winch_state:" + cable, true).second) {
        client()->on_winch_state(cable, [this, cable](const hadal::WinchState& m) { winch_states_.put(cable, m); });
      }
    }
    return winch_states_.wait(cable, min_stamp, timeout_s);
  }
  void command_winch(const std::string& cable, double speed_mps, double target_length_m, bool publish) {
    if (publish) {
      client()->command_winch(cable, speed_mps, target_length_m);
    } else {
      client()->attach_winch(cable, speed_mps, target_length_m);
    }
  }
  // An acoustic modem's packets: every packet it decodes from the first call on is kept (not only the latest)
  // until a call takes it.
  std::vector<hadal::AcousticPacket> receive_packets(const std::string& vehicle, const std::string& modem,
                                                     double timeout_s) {
    check_sensor(vehicle, modem, "modem_packets");
    const std::string key = vehicle + "/" + modem;
    bool subscribe = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      subscribe = modem_subscribed_.insert(key).second;
    }
    if (subscribe) {
      client()->on_modem_packets(vehicle, modem, [this, key](const hadal::AcousticPackets& packets) {
        {
          std::lock_guard<std::mutex> lock(packets_mutex_);
          auto& queue = packets_[key];
          queue.insert(queue.end(), packets.packets.begin(), packets.packets.end());
        }
        packets_arrived_.notify_all();
      });
    }
    std::unique_lock<std::mutex> lock(packets_mutex_);
    packets_arrived_.wait_for(lock, std::chrono::duration<double>(std::max(timeout_s, 0.0)),
                              [&] { return !packets_[key].empty(); });
    std::vector<hadal::AcousticPacket> out;
    out.swap(packets_[key]);
    return out;
  }
  void send_packet(const std::string& vehicle, const std::string& modem, const std::vector<std::uint8_t>& payload,
                   const std::string& destination, bool publish) {
    if (publish) {
      client()->send_packet(vehicle, modem, payload, destination);
    } else {
      client()->attach_packet(vehicle, modem, payload, destination);
    }
  }
  void set_joint_commands(const std::string& vehicle, const std::string& controller,
                          const std::vector<double>& values, bool publish) {
    if (publish) {
      client()->set_joint_commands(vehicle, controller, values);
    } else {
      client()->attach_joint_commands(vehicle, controller, values);
    }
  }
  // Arrays to a JointTrajectory with the GIL held (shapes checked here, the rest by the server), then sent
  // without it.
  void set_joint_trajectory(const std::string& vehicle, const std::string& controller,
                            const std::vector<std::string>& joint_names,
                            const py::array_t<double, py::array::c_style | py::array::forcecast>& times,
                            const py::array_t<double, py::array::c_style | py::array::forcecast>& positions,
                            const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>&
                                velocities,
                            const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>&
                                accelerations,
                            std::optional<double> start_time) {
    const auto n = static_cast<py::ssize_t>(joint_names.size());
    if (times.ndim() != 1) throw py::value_error("times: a 1-D array of seconds, one per waypoint");
    const py::ssize_t points = times.shape(0);
    const auto rows = [&](const char* what, const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
      if (a.ndim() != 2 || a.shape(0) != points || a.shape(1) != n) {
        throw py::value_error(std::string(what) + ": shape (" + std::to_string(points) + ", " + std::to_string(n) +
                              ") expected (one row per waypoint, one column per joint name)");
      }
      std::vector<std::vector<double>> out(static_cast<std::size_t>(points));
      for (py::ssize_t k = 0; k < points; ++k) out[static_cast<std::size_t>(k)].assign(a.data(k, 0), a.data(k, 0) + n);
      return out;
    };
    const auto p = rows("positions", positions);
    const auto v = velocities ? rows("velocities", *velocities) : std::vector<std::vector<double>>{};
    const auto a = accelerations ? rows("accelerations", *accelerations) : std::vector<std::vector<double>>{};
    hadal::JointTrajectory trajectory;
    trajectory.joint_names = joint_names;
    trajectory.start_time = start_time;
    for (py::ssize_t k = 0; k < points; ++k) {
      const auto i = static_cast<std::size_t>(k);
      trajectory.points.push_back({*times.data(k), p[i], v.empty() ? std::vector<double>{} : v[i],
                                   a.empty() ? std::vector<double>{} : a[i]});
    }
    py::gil_scoped_release unlocked;
    client()->set_joint_trajectory(vehicle, controller, trajectory);
  }
  double step(std::uint32_t steps, double timeout_s) { return client()->step(steps, timeout_s); }
  // The samples kept so far are forgotten first: after the reset sim time starts again at 0, and a kept
  // sample of the run before would satisfy any min_stamp.
  double reset(std::optional<std::uint64_t> seed, const std::map<std::string, std::vector<double>>& poses,
               std::uint32_t steps, double timeout_s) {
    return wait_reply(send_reset(seed, poses, steps, timeout_s), timeout_s);
  }
  std::uint64_t send_step(std::uint32_t steps, double timeout_s) { return client()->send_step(steps, timeout_s); }
  std::uint64_t send_reset(std::optional<std::uint64_t> seed, const std::map<std::string, std::vector<double>>& poses,
                           std::uint32_t steps, double timeout_s) {
    const hadal::ResetOptions options = reset_options(seed, poses);
    forget_samples();
    return client()->send_reset(options, steps, timeout_s);
  }
  double wait_reply(std::uint64_t request_id, double timeout_s) { return client()->wait_reply(request_id, timeout_s); }
  hadal::Odometry reply_odometry(const std::string& vehicle) const { return client()->reply_odometry(vehicle); }

 private:
  static hadal::ResetOptions reset_options(std::optional<std::uint64_t> seed,
                                           const std::map<std::string, std::vector<double>>& poses) {
    hadal::ResetOptions options;
    options.seed = seed;
    for (const auto& [vehicle, pose] : poses) {
      if (pose.size() != 3 && pose.size() != 7) {
        throw std::invalid_argument("reset: the pose of '" + vehicle + "' has " + std::to_string(pose.size()) +
                                    " numbers; give x, y, z [m] or x, y, z, qx, qy, qz, qw");
      }
      hadal::Pose p;
      std::copy(pose.begin(), pose.begin() + 3, p.p_WB.begin());
      if (pose.size() == 7) std::copy(pose.begin() + 3, pose.end(), p.q_WB.begin());
      options.poses.emplace_back(vehicle, p);
    }
    return options;
  }

  // The client for one call: a reference kept until the end of the caller's full expression, so that a
  // close() on another thread (the GIL is released around every call) cannot destroy it mid-call.
  std::shared_ptr<hadal::Client> client() const {
    std::lock_guard<std::mutex> lock(client_mutex_);
    if (!client_) throw hadal::ClientError("the client is closed");
    return client_;
  }

  void forget_samples() {
    odometry_.clear();
    thrusters_.clear();
    tracks_.clear();
    fins_.clear();
    buoyancy_engines_.clear();
    drop_weights_.clear();
    imu_.clear();
    pressure_.clear();
    magnetic_field_.clear();
    wrench_.clear();
    nav_sat_fix_.clear();
    dvl_.clear();
    range_.clear();
    laser_scan_.clear();
    image_.clear();
    depth_.clear();
    camera_info_.clear();
    sonar_image_.clear();
    sonar_detections_.clear();
    raw_sonar_image_.clear();
    joint_states_.clear();
  }

  template <class Sample>
  using Subscription = void (hadal::Client::*)(const std::string&, const std::string&,
                                               std::function<void(const Sample&)>);

  template <class State>
  using VehicleSubscription = void (hadal::Client::*)(const std::string&, std::function<void(const State&)>);

  // Subscribes `latest` to rt/<vehicle>/<kind>/state on first use, then waits for a sample.
  template <class State>
  std::optional<State> wait_actuator_state(const std::string& kind, VehicleSubscription<State> subscribe,
                                           Latest<State>& latest, const std::string& vehicle, double min_stamp,
                                           double timeout_s) {
    check_vehicle(vehicle);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (subscribed_.emplace(kind + ":" + vehicle, true).second) {
        ((*client()).*subscribe)(vehicle, [&latest, vehicle](const State& m) { latest.put(vehicle, m); });
      }
    }
    return checked(latest.wait(vehicle, min_stamp, timeout_s), vehicle);
  }

  // Subscribes `latest` to rt/<vehicle>/<sensor> on first use, then waits for a sample. Samples are kept
  // as Stored: by value, or (images) by shared pointer, so that Python can view them without a copy.
  template <class Sample, class Stored = Sample>
  std::optional<Stored> wait_sensor(const std::string& kind, Subscription<Sample> subscribe, Latest<Stored>& latest,
                                    const std::string& vehicle, const std::string& sensor, double min_stamp,
                                    double timeout_s) {
    return wait_subscribed<Sample, Stored>(
        kind,
        [subscribe](hadal::Client& c, std::function<void(const Sample&)> callback, const std::string& v,
                    const std::string& s) { (c.*subscribe)(v, s, std::move(callback)); },
        latest, vehicle, sensor, min_stamp, timeout_s);
  }

  // wait_sensor with any subscription: subscribe(client, callback, vehicle, sensor) (a side-scan channel's
  // sensor is "<sensor>/<channel>").
  template <class Sample, class Stored = Sample>
  std::optional<Stored> wait_subscribed(
      const std::string& kind,
      const std::function<void(hadal::Client&, std::function<void(const Sample&)>, const std::string&, const std::string&)>&
          subscribe,
      Latest<Stored>& latest, const std::string& vehicle, const std::string& sensor, double min_stamp,
      double timeout_s) {
    check_sensor(vehicle, sensor, kind);
    const std::string key = vehicle + "/" + sensor;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (subscribed_.emplace(kind + ":" + key, true).second) {
        subscribe(*client(), [&latest, key](const Sample& m) {
          if constexpr (std::is_same_v<Stored, Sample>) {
            latest.put(key, m);
          } else {
            latest.put(key, std::make_shared<const Sample>(m));
          }
        }, vehicle, sensor);
      }
    }
    std::optional<Stored> sample = latest.wait(key, min_stamp, timeout_s);
    if (!sample) check_sensor(vehicle, sensor, kind);  // the scene may have come meanwhile
    return sample;
  }

  // The client is declared last so that it is destroyed first: its DDS callbacks write into the members
  // above, which must outlive them.
  mutable std::mutex mutex_;
  std::map<std::string, bool> subscribed_;
  Latest<hadal::Odometry> odometry_;
  Latest<hadal::ThrusterStates> thrusters_;
  Latest<hadal::TrackStates> tracks_;
  Latest<hadal::FinStates> fins_;
  Latest<hadal::BuoyancyEngineStates> buoyancy_engines_;
  Latest<hadal::DropWeightStates> drop_weights_;
  Latest<hadal::JointStates> joint_states_;
  Latest<hadal::Imu> imu_;
  Latest<hadal::FluidPressure> pressure_;
  Latest<hadal::MagneticField> magnetic_field_;
  Latest<hadal::Wrench> wrench_;
  Latest<hadal::NavSatFix> nav_sat_fix_;
  Latest<hadal::Dvl> dvl_;
  Latest<hadal::Range> range_;
  Latest<hadal::UsblFixes> usbl_fixes_;
  Latest<hadal::LblRanges> lbl_ranges_;
  Latest<hadal::Wrench> cable_forces_;      // by "<cable>/<end>"
  Latest<hadal::CableShape> cable_shapes_;  // by cable
  Latest<hadal::WinchState> winch_states_;  // by cable
  Latest<hadal::SeaState> sea_states_;      // by vehicle
  std::set<std::string> modem_subscribed_;  // "<vehicle>/<modem>" (under mutex_)
  std::mutex packets_mutex_;
  std::condition_variable packets_arrived_;
  std::map<std::string, std::vector<hadal::AcousticPacket>> packets_;  // decoded, not yet taken
  Latest<hadal::LaserScan> laser_scan_;
  Latest<ImagePtr> image_;
  Latest<ImagePtr> depth_;
  Latest<hadal::CameraInfo> camera_info_;
  Latest<SonarImagePtr> sonar_image_;
  Latest<hadal::SonarDetections> sonar_detections_;
  Latest<hadal::RawSonarImage> raw_sonar_image_;
  mutable std::mutex client_mutex_;  // guards client_ alone (mutex_ is held around calls on it)
  std::shared_ptr<hadal::Client> client_;
};

}  // namespace

PYBIND11_MODULE(_hadal, m) {
  m.doc() = "Python client of the Hadal deep-sea simulator (hadald) over DDS";
  m.def("current_cpu", [] { return sched_getcpu(); },
        "The CPU the calling thread runs on now (sched_getcpu(3)), -1 if unknown; hadal.env.VectorEnv sends the "
        "server pinned there its request last");
  m.def(
      "decode_message",
      [](const std::string& type, const py::bytes& cdr) {
        const std::string text(cdr);
        const std::vector<std::uint8_t> bytes(text.begin(), text.end());
        try {
          return hadal::decode_message(type, bytes);
        } catch (const std::invalid_argument&) {
          throw;
        } catch (const std::runtime_error& e) {
          throw py::value_error(e.what());
        }
      },
      py::arg("type"), py::arg("cdr"),
      "A recorded message (CDR bytes with their encapsulation header, as a rosbag2 bag keeps them) of ROS 2 type "
      "`type` ('nav_msgs/msg/Odometry') as the client's own readers give it (Odometry, Imu, ...; a float for a "
      "Clock). ValueError for a type not in decodable_message_types() or bytes that do not decode");
  m.def("decodable_message_types", &hadal::decodable_message_types,
        "The ROS 2 type names decode_message reads (images and sonar images are not among them)");
  m.def("default_domain_id", [] { return hadal::resolve_domain_id(std::nullopt); },
        "The DDS domain when none is given, the rule of hadald, its tools, hadal.Client and ROS 2: $ROS_DOMAIN_ID, "
        "else 0 (ValueError for a ROS_DOMAIN_ID that is no id in 0..232)");
  // The client's errors as hadal.errors' classes (Python classes, so that Timeout is also a TimeoutError).
  py::register_exception_translator([](std::exception_ptr error) {
    const auto raise = [](const char* name, const hadal::ClientError& e, const char* attribute = nullptr,
                          const std::string& value = {}) {
      py::object type = py::module_::import("hadal.errors").attr(name);
      py::object exception = attribute ? type(e.what(), value) : type(e.what());
      PyErr_SetObject(type.ptr(), exception.ptr());
    };
    try {
      if (error) std::rethrow_exception(error);
    } catch (const hadal::CommandRejected& e) {
      raise("CommandRejected", e, "reason", e.reason());
    } catch (const hadal::UnknownVehicle& e) {
      raise("UnknownVehicle", e, "vehicle", e.vehicle());
    } catch (const hadal::UnknownSensor& e) {
      py::object type = py::module_::import("hadal.errors").attr("UnknownSensor");
      py::object exception = type(e.what(), e.vehicle(), e.sensor());
      PyErr_SetObject(type.ptr(), exception.ptr());
    } catch (const hadal::ServerLost& e) {
      raise("ServerLost", e);
    } catch (const hadal::Timeout& e) {
      raise("Timeout", e);
    } catch (const hadal::ServerNotFound& e) {
      raise("ServerNotFound", e);
    } catch (const hadal::ClientError& e) {
      raise("ClientError", e);
    }
  });

  py::enum_<hadal::ServerMode>(m, "ServerMode")
      .value("REALTIME", hadal::ServerMode::kRealtime)
      .value("FAST", hadal::ServerMode::kFast)
      .value("LOCKSTEP", hadal::ServerMode::kLockstep);

  py::class_<hadal::Odometry>(m, "Odometry",
                              "Ground-truth odometry: pose of body frame B in world W (ENU), twist in B")
      .def_readonly("stamp", &hadal::Odometry::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::Odometry::frame_id)
      .def_readonly("child_frame_id", &hadal::Odometry::child_frame_id)
      .def_property_readonly("p_WB", [](const hadal::Odometry& o) { return to_numpy(o.p_WB); }, "position [m]")
      .def_property_readonly("q_WB", [](const hadal::Odometry& o) { return to_numpy(o.q_WB); },
                             "orientation quaternion (x, y, z, w)")
      .def_property_readonly("v_WB_B", [](const hadal::Odometry& o) { return to_numpy(o.v_WB_B); },
                             "linear velocity expressed in B [m/s]")
      .def_property_readonly("w_WB_B", [](const hadal::Odometry& o) { return to_numpy(o.w_WB_B); },
                             "angular velocity expressed in B [rad/s]")
      .def("__repr__", [](const hadal::Odometry& o) {
        return "Odometry(stamp=" + std::to_string(o.stamp) + ", p_WB=[" + std::to_string(o.p_WB[0]) + ", " +
               std::to_string(o.p_WB[1]) + ", " + std::to_string(o.p_WB[2]) + "])";
      });

  py::class_<hadal::ThrusterStates>(m, "ThrusterStates")
      .def_readonly("stamp", &hadal::ThrusterStates::stamp, "sim time [s]")
      .def_readonly("names", &hadal::ThrusterStates::names)
      .def_property_readonly("setpoint", [](const hadal::ThrusterStates& t) { return to_numpy(t.setpoint); })
      .def_property_readonly("rotor_speed", [](const hadal::ThrusterStates& t) { return to_numpy(t.rotor_speed); },
                             "[rev/s]")
      .def_property_readonly("thrust", [](const hadal::ThrusterStates& t) { return to_numpy(t.thrust); }, "[N]")
      .def_property_readonly("torque", [](const hadal::ThrusterStates& t) { return to_numpy(t.torque); }, "[N m]")
      .def_readonly("command_source", &hadal::ThrusterStates::command_source,
                    "0 none, 1 scenario schedule, 2 client");

  py::class_<hadal::TrackStates>(m, "TrackStates", "hadal_msgs/TrackState: a crawler's tracks, in scenario order")
      .def_readonly("stamp", &hadal::TrackStates::stamp, "sim time [s]")
      .def_readonly("names", &hadal::TrackStates::names)
      .def_property_readonly("setpoint", [](const hadal::TrackStates& t) { return to_numpy(t.setpoint); })
      .def_property_readonly("belt_speed", [](const hadal::TrackStates& t) { return to_numpy(t.belt_speed); }, "[m/s]")
      .def_property_readonly("sprocket_speed", [](const hadal::TrackStates& t) { return to_numpy(t.sprocket_speed); },
                             "[rad/s]")
      .def_property_readonly("motor_torque", [](const hadal::TrackStates& t) { return to_numpy(t.motor_torque); },
                             "at the sprocket [N m]")
      .def_property_readonly("current", [](const hadal::TrackStates& t) { return to_numpy(t.current); }, "[A]")
      .def_property_readonly("power", [](const hadal::TrackStates& t) { return to_numpy(t.power); }, "[W]")
      .def_property_readonly("load", [](const hadal::TrackStates& t) { return to_numpy(t.load); },
                             "the soil's shear on the belt [N]")
      .def_readonly("command_source", &hadal::TrackStates::command_source, "0 none, 1 scenario schedule, 2 client");
  py::class_<hadal::FinStates>(m, "FinStates", "hadal_msgs/FinState: a vehicle's fins, in scenario order")
      .def_readonly("stamp", &hadal::FinStates::stamp, "sim time [s]")
      .def_readonly("names", &hadal::FinStates::names)
      .def_property_readonly("setpoint", [](const hadal::FinStates& f) { return to_numpy(f.setpoint); })
      .def_property_readonly("angle", [](const hadal::FinStates& f) { return to_numpy(f.angle); },
                             "deflection about the hinge axis [rad]")
      .def_property_readonly("attack_angle", [](const hadal::FinStates& f) { return to_numpy(f.attack_angle); },
                             "the water's angle of attack [rad]")
      .def_property_readonly("lift", [](const hadal::FinStates& f) { return to_numpy(f.lift); }, "[N]")
      .def_property_readonly("drag", [](const hadal::FinStates& f) { return to_numpy(f.drag); }, "[N]")
      .def_readonly("command_source", &hadal::FinStates::command_source, "0 none, 1 scenario schedule, 2 client");
  py::class_<hadal::BuoyancyEngineStates>(m, "BuoyancyEngineStates",
                                          "hadal_msgs/BuoyancyEngineState: a glider's buoyancy engines")
      .def_readonly("stamp", &hadal::BuoyancyEngineStates::stamp, "sim time [s]")
      .def_readonly("names", &hadal::BuoyancyEngineStates::names)
      .def_property_readonly("setpoint", [](const hadal::BuoyancyEngineStates& b) { return to_numpy(b.setpoint); })
      .def_property_readonly("volume_change",
                             [](const hadal::BuoyancyEngineStates& b) { return to_numpy(b.volume_change); },
                             "displaced volume beyond neutral [m^3]")
      .def_property_readonly("volume_rate", [](const hadal::BuoyancyEngineStates& b) { return to_numpy(b.volume_rate); },
                             "[m^3/s]")
      .def_property_readonly("force", [](const hadal::BuoyancyEngineStates& b) { return to_numpy(b.force); },
                             "buoyancy of the volume change, up [N]")
      .def_property_readonly("power", [](const hadal::BuoyancyEngineStates& b) { return to_numpy(b.power); }, "[W]")
      .def_property_readonly("energy", [](const hadal::BuoyancyEngineStates& b) { return to_numpy(b.energy); },
                             "pump energy since the start [J]")
      .def_readonly("command_source", &hadal::BuoyancyEngineStates::command_source,
                    "0 none, 1 scenario schedule, 2 client");
  py::class_<hadal::DropWeightStates>(m, "DropWeightStates", "hadal_msgs/DropWeightState: a vehicle's drop weights")
      .def_readonly("stamp", &hadal::DropWeightStates::stamp, "sim time [s]")
      .def_readonly("names", &hadal::DropWeightStates::names)
      .def_property_readonly("attached",
                             [](const hadal::DropWeightStates& d) {
                               py::array_t<bool> out(d.attached.size());
                               std::copy(d.attached.begin(), d.attached.end(), out.mutable_data());
                               return out;
                             })
      .def_property_readonly("reason", [](const hadal::DropWeightStates& d) { return to_numpy(d.reason); },
                             "0 attached, 1 released on command, 2 at altitude, 3 at time")
      .def_property_readonly("release_time", [](const hadal::DropWeightStates& d) { return to_numpy(d.release_time); },
                             "sim time of the release [s]; NaN while attached")
      .def_property_readonly("force", [](const hadal::DropWeightStates& d) { return to_numpy(d.force); },
                             "vertical force while attached [N]")
      .def_readonly("command_source", &hadal::DropWeightStates::command_source,
                    "0 none, 1 scenario schedule, 2 client");

  py::class_<hadal::JointStates>(m, "JointStates",
                                 "sensor_msgs/JointState: an articulated vehicle's joints by name (links[].joint.name)")
      .def_readonly("stamp", &hadal::JointStates::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::JointStates::frame_id)
      .def_readonly("names", &hadal::JointStates::names)
      .def_property_readonly("position", [](const hadal::JointStates& j) { return to_numpy(j.position); },
                             "[rad or m]")
      .def_property_readonly("velocity", [](const hadal::JointStates& j) { return to_numpy(j.velocity); },
                             "[rad/s or m/s]")
      .def_property_readonly("effort", [](const hadal::JointStates& j) { return to_numpy(j.effort); },
                             "the effort each joint's motor holds [N m or N]");

  py::class_<hadal::Imu>(m, "Imu", "sensor_msgs/Imu sample: rate and specific force in the sensor frame")
      .def_readonly("stamp", &hadal::Imu::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::Imu::frame_id)
      .def_property_readonly("angular_velocity", [](const hadal::Imu& i) { return to_numpy(i.angular_velocity); },
                             "[rad/s]")
      .def_property_readonly("linear_acceleration",
                             [](const hadal::Imu& i) { return to_numpy(i.linear_acceleration); },
                             "specific force [m/s^2] (+g up at rest)");
  py::class_<hadal::FluidPressure>(m, "FluidPressure", "sensor_msgs/FluidPressure sample")
      .def_readonly("stamp", &hadal::FluidPressure::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::FluidPressure::frame_id)
      .def_readonly("pressure", &hadal::FluidPressure::pressure, "absolute [Pa]")
      .def_readonly("variance", &hadal::FluidPressure::variance, "[Pa^2]");

  py::class_<hadal::Wrench>(m, "Wrench",
                            "geometry_msgs/WrenchStamped sample of a force_torque sensor: the wrench across its "
                            "link's joint in the sensor frame, about its origin")
      .def_readonly("stamp", &hadal::Wrench::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::Wrench::frame_id)
      .def_property_readonly("force", [](const hadal::Wrench& w) { return to_numpy(w.force); }, "[N], shape (3,)")
      .def_property_readonly("torque", [](const hadal::Wrench& w) { return to_numpy(w.torque); },
                             "[N m] about the sensor's origin, shape (3,)");
  py::class_<hadal::MagneticField>(m, "MagneticField",
                                   "sensor_msgs/MagneticField sample: flux density in the sensor frame")
      .def_readonly("stamp", &hadal::MagneticField::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::MagneticField::frame_id)
      .def_property_readonly("magnetic_field",
                             [](const hadal::MagneticField& f) { return to_numpy(f.magnetic_field); },
                             "(3,) flux density in the sensor frame [T]")
      .def_property_readonly("magnetic_field_covariance",
                             [](const hadal::MagneticField& f) { return to_numpy_3x3(f.magnetic_field_covariance); },
                             "(3, 3) covariance [T^2]; all 0: unknown");

  py::class_<hadal::NavSatFix> nav_sat_fix(
      m, "NavSatFix", "sensor_msgs/NavSatFix sample; latitude, longitude, altitude are NaN without a fix");
  nav_sat_fix.attr("STATUS_NO_FIX") = hadal::NavSatFix::kStatusNoFix;
  nav_sat_fix.attr("STATUS_FIX") = hadal::NavSatFix::kStatusFix;
  nav_sat_fix.attr("STATUS_SBAS_FIX") = hadal::NavSatFix::kStatusSbasFix;
  nav_sat_fix.attr("STATUS_GBAS_FIX") = hadal::NavSatFix::kStatusGbasFix;
  nav_sat_fix.attr("SERVICE_GPS") = hadal::NavSatFix::kServiceGps;
  nav_sat_fix.attr("SERVICE_GLONASS") = hadal::NavSatFix::kServiceGlonass;
  nav_sat_fix.attr("SERVICE_COMPASS") = hadal::NavSatFix::kServiceCompass;
  nav_sat_fix.attr("SERVICE_GALILEO") = hadal::NavSatFix::kServiceGalileo;
  nav_sat_fix.attr("COVARIANCE_TYPE_UNKNOWN") = hadal::NavSatFix::kCovarianceTypeUnknown;
  nav_sat_fix.attr("COVARIANCE_TYPE_APPROXIMATED") = hadal::NavSatFix::kCovarianceTypeApproximated;
  nav_sat_fix.attr("COVARIANCE_TYPE_DIAGONAL_KNOWN") = hadal::NavSatFix::kCovarianceTypeDiagonalKnown;
  nav_sat_fix.attr("COVARIANCE_TYPE_KNOWN") = hadal::NavSatFix::kCovarianceTypeKnown;
  nav_sat_fix.def_readonly("stamp", &hadal::NavSatFix::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::NavSatFix::frame_id)
      .def_readonly("status", &hadal::NavSatFix::status, "-1 no fix, 0 fix, 1 SBAS fix, 2 GBAS fix")
      .def_readonly("service", &hadal::NavSatFix::service, "bits: 1 GPS, 2 GLONASS, 4 COMPASS, 8 GALILEO")
      .def_readonly("latitude", &hadal::NavSatFix::latitude, "WGS84 [deg], + north")
      .def_readonly("longitude", &hadal::NavSatFix::longitude, "WGS84 [deg], + east")
      .def_readonly("altitude", &hadal::NavSatFix::altitude, "above the WGS84 ellipsoid [m]")
      .def_property_readonly("position_covariance",
                             [](const hadal::NavSatFix& f) { return to_numpy_3x3(f.position_covariance); },
                             "(3, 3) covariance, east/north/up [m^2]")
      .def_readonly("position_covariance_type", &hadal::NavSatFix::position_covariance_type,
                    "0 unknown, 1 approximated, 2 diagonal known, 3 known")
      .def("has_fix", &hadal::NavSatFix::has_fix, "True when status >= STATUS_FIX");

  py::class_<hadal::Dvl> dvl(m, "Dvl",
                             "marine_acoustic_msgs/Dvl ping; frame: the DVL's (z along its axis, x forward)");
  dvl.attr("VELOCITY_MODE_NONE") = hadal::Dvl::kVelocityModeNone;
  dvl.attr("VELOCITY_MODE_BOTTOM_TRACK") = hadal::Dvl::kVelocityModeBottomTrack;
  dvl.attr("VELOCITY_MODE_WATER_TRACK") = hadal::Dvl::kVelocityModeWaterTrack;
  dvl.attr("DVL_TYPE_PISTON") = hadal::Dvl::kDvlTypePiston;
  dvl.attr("DVL_TYPE_PHASED_ARRAY") = hadal::Dvl::kDvlTypePhasedArray;
  dvl.def_readonly("stamp", &hadal::Dvl::stamp, "sim time the velocity is valid at [s]")
      .def_readonly("frame_id", &hadal::Dvl::frame_id)
      .def_readonly("velocity_mode", &hadal::Dvl::velocity_mode, "0 none, 1 bottom track, 2 water track")
      .def_readonly("dvl_type", &hadal::Dvl::dvl_type, "0 piston, 1 phased array")
      .def_property_readonly("velocity", [](const hadal::Dvl& d) { return to_numpy(d.velocity); },
                             "(3,) velocity in the DVL frame [m/s]")
      .def_property_readonly("velocity_covariance",
                             [](const hadal::Dvl& d) { return to_numpy_3x3(d.velocity_covariance); },
                             "(3, 3) covariance [m^2/s^2]; -1: unknown")
      .def_readonly("altitude", &hadal::Dvl::altitude, "mean vertical range of the good beams [m]")
      .def_readonly("course_gnd", &hadal::Dvl::course_gnd, "atan2(velocity y, velocity x) [rad]")
      .def_readonly("speed_gnd", &hadal::Dvl::speed_gnd, "hypot(velocity x, velocity y) [m/s]")
      .def_readonly("num_good_beams", &hadal::Dvl::num_good_beams)
      .def_readonly("sound_speed", &hadal::Dvl::sound_speed, "sound speed the DVL assumed [m/s]")
      .def_readonly("beam_ranges_valid", &hadal::Dvl::beam_ranges_valid)
      .def_readonly("beam_velocities_valid", &hadal::Dvl::beam_velocities_valid)
      .def_property_readonly("beam_unit_vec", [](const hadal::Dvl& d) { return to_numpy(d.beam_unit_vec); },
                             "(4, 3) beam directions in the DVL frame, one unit vector per row")
      .def_property_readonly("ranges", [](const hadal::Dvl& d) { return to_numpy(d.ranges); },
                             "(4,) slant range along each beam [m] (the message's `range`)")
      .def_property_readonly("range_covariance", [](const hadal::Dvl& d) { return to_numpy(d.range_covariance); },
                             "(4,) [m^2]")
      .def_property_readonly("beam_quality", [](const hadal::Dvl& d) { return to_numpy(d.beam_quality); },
                             "(4,) per-beam quality figure")
      .def_property_readonly("beam_velocity", [](const hadal::Dvl& d) { return to_numpy(d.beam_velocity); },
                             "(4,) along-beam velocity [m/s]")
      .def_property_readonly("beam_velocity_covariance",
                             [](const hadal::Dvl& d) { return to_numpy(d.beam_velocity_covariance); },
                             "(4,) [m^2/s^2]");

  py::class_<hadal::Range> range(m, "Range",
                                 "sensor_msgs/Range sample (altimeter, range finder) along the sensor's x axis; "
                                 "values outside [min_range, max_range] are not measurements");
  range.attr("ULTRASOUND") = hadal::Range::kUltrasound;
  range.attr("INFRARED") = hadal::Range::kInfrared;
  range.def_readonly("stamp", &hadal::Range::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::Range::frame_id)
      .def_readonly("radiation_type", &hadal::Range::radiation_type, "0 ultrasound, 1 infrared")
      .def_readonly("field_of_view", &hadal::Range::field_of_view, "full cone angle [rad]")
      .def_readonly("min_range", &hadal::Range::min_range, "[m]")
      .def_readonly("max_range", &hadal::Range::max_range, "[m]")
      .def_readonly("range", &hadal::Range::range, "[m]");

  py::class_<hadal::UsblFix>(m, "UsblFix",
                             "One USBL fix: a transponder's reply fixed in the transceiver's frame S and geo-referenced")
      .def_readonly("stamp", &hadal::UsblFix::stamp, "reception of the reply, sim time [s]")
      .def_readonly("interrogation_stamp", &hadal::UsblFix::interrogation_stamp, "emission of the interrogation [s]")
      .def_readonly("target", &hadal::UsblFix::target, "the transponder's vehicle")
      .def_readonly("interrogation", &hadal::UsblFix::interrogation, "the interrogation's index")
      .def_readonly("travel_time", &hadal::UsblFix::travel_time, "two-way, turnaround removed [s]")
      .def_readonly("range", &hadal::UsblFix::range, "slant range [m]")
      .def_readonly("bearing", &hadal::UsblFix::bearing, "atan2(y_S, x_S) [rad]")
      .def_readonly("elevation", &hadal::UsblFix::elevation, "asin(z_S / range), negative below [rad]")
      .def_readonly("position", &hadal::UsblFix::position, "the transponder in S [m]")
      .def_readonly("position_covariance", &hadal::UsblFix::position_covariance, "in S, row-major [m^2]")
      .def_readonly("position_world", &hadal::UsblFix::position_world, "the transponder in W (ENU) [m]")
      .def_readonly("latitude", &hadal::UsblFix::latitude, "WGS84 [deg]")
      .def_readonly("longitude", &hadal::UsblFix::longitude, "WGS84 [deg]")
      .def_readonly("altitude", &hadal::UsblFix::altitude, "above the WGS84 ellipsoid [m]")
      .def_readonly("snr_db", &hadal::UsblFix::snr_db, "the reply's SNR at the transceiver [dB]");
  py::class_<hadal::CableShape>(m, "CableShape", "nav_msgs/Path of a cable: its nodes in W")
      .def_readonly("stamp", &hadal::CableShape::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::CableShape::frame_id, "the world frame")
      .def_property_readonly(
          "points",
          [](const hadal::CableShape& s) {
            py::array_t<double> out({static_cast<py::ssize_t>(s.points.size()), static_cast<py::ssize_t>(3)});
            auto view = out.mutable_unchecked<2>();
            for (std::size_t i = 0; i < s.points.size(); ++i) {
              for (int k = 0; k < 3; ++k) view(static_cast<py::ssize_t>(i), k) = s.points[i][static_cast<std::size_t>(k)];
            }
            return out;
          },
          "(N + 1, 3) array of the nodes from the `from` end [m]");
  py::class_<hadal::SeaState>(m, "SeaState", "hadal_msgs/SeaState: the sea at a vehicle (world.waves)")
      .def_readonly("stamp", &hadal::SeaState::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::SeaState::frame_id, "the world frame")
      .def_readonly("surface_z", &hadal::SeaState::surface_z,
                    "the instantaneous surface's z over the vehicle's B origin, W [m]")
      .def_readonly("surface_slope", &hadal::SeaState::surface_slope, "(d eta / dx, d eta / dy) there")
      .def_readonly("depth", &hadal::SeaState::depth, "of B's origin below the surface [m] (< 0: above it)")
      .def_readonly("orbital_velocity", &hadal::SeaState::orbital_velocity,
                    "the waves' water velocity at B's origin, W [m/s]; 0 in the air")
      .def_readonly("significant_height", &hadal::SeaState::significant_height, "Hs [m]")
      .def_readonly("peak_period", &hadal::SeaState::peak_period, "Tp [s] (listed waves: the longest period)")
      .def_readonly("mean_direction", &hadal::SeaState::mean_direction,
                    "the waves travel toward, from W's x toward y [rad]")
      .def_readonly("build_up", &hadal::SeaState::build_up, "the sea's build-up factor in [0, 1]");
  py::class_<hadal::WinchState>(m, "WinchState", "hadal_msgs/WinchState of a cable's winch")
      .def_readonly("stamp", &hadal::WinchState::stamp, "sim time [s]")
      .def_readonly("frame_id", &hadal::WinchState::frame_id, "the world frame")
      .def_readonly("length", &hadal::WinchState::length, "unstretched cable in the water [m]")
      .def_readonly("speed", &hadal::WinchState::speed, "line speed, + paying out [m/s]")
      .def_readonly("command_speed", &hadal::WinchState::command_speed, "what it was last told [m/s]")
      .def_readonly("target_length", &hadal::WinchState::target_length, "[m]; 0: none")
      .def_readonly("drum_length", &hadal::WinchState::drum_length, "in the water and on the drum together [m]")
      .def_readonly("min_length", &hadal::WinchState::min_length, "hauling in stops here [m]")
      .def_readonly("tension", &hadal::WinchState::tension, "the cable's pull on the winch [N]")
      .def_readonly("at_limit", &hadal::WinchState::at_limit,
                    "stopped at min_length or the drum's end while told to go on");
  py::class_<hadal::AcousticPacket>(m, "AcousticPacket", "A packet an acoustic modem decoded")
      .def_readonly("transmit_stamp", &hadal::AcousticPacket::transmit_stamp, "start of its transmission, sim time [s]")
      .def_readonly("stamp", &hadal::AcousticPacket::stamp, "end of its reception, sim time [s]")
      .def_readonly("source", &hadal::AcousticPacket::source, "'<vehicle>/<modem>' of the sender")
      .def_readonly("destination", &hadal::AcousticPacket::destination,
                    "as sent: '' every modem, '<vehicle>' or '<vehicle>/<modem>'")
      .def_readonly("sequence_number", &hadal::AcousticPacket::sequence_number, "the sender's packet index")
      .def_property_readonly(
          "payload",
          [](const hadal::AcousticPacket& p) {
            return py::bytes(reinterpret_cast<const char*>(p.payload.data()), p.payload.size());
          },
          "the bytes sent")
      .def_readonly("travel_time", &hadal::AcousticPacket::travel_time,
                    "from the start of transmission to the start of reception [s]")
      .def_readonly("snr_db", &hadal::AcousticPacket::snr_db, "signal to noise and interference over the packet [dB]")
      .def("__repr__", [](const hadal::AcousticPacket& p) {
        return "<AcousticPacket " + p.source + " -> '" + p.destination + "' #" + std::to_string(p.sequence_number) +
               ", " + std::to_string(p.payload.size()) + " bytes, t = " + std::to_string(p.stamp) + " s>";
      });
  py::class_<hadal::AcousticPackets>(m, "AcousticPackets",
                                     "hadal_msgs/AcousticPackets: the packets a modem decoded within one physics step")
      .def_readonly("stamp", &hadal::AcousticPackets::stamp, "the last packet's [s]")
      .def_readonly("frame_id", &hadal::AcousticPackets::frame_id, "the modem's frame")
      .def_readonly("packets", &hadal::AcousticPackets::packets, "list of AcousticPacket");
  py::class_<hadal::UsblFixes>(m, "UsblFixes",
                               "hadal_msgs/UsblFixes: the USBL fixes whose replies arrived within one physics step")
      .def_readonly("stamp", &hadal::UsblFixes::stamp, "the last fix's [s]")
      .def_readonly("frame_id", &hadal::UsblFixes::frame_id, "the transceiver's frame")
      .def_readonly("fixes", &hadal::UsblFixes::fixes, "list of UsblFix");

  py::class_<hadal::LblRange>(m, "LblRange", "One LBL range: a beacon's reply")
      .def_readonly("stamp", &hadal::LblRange::stamp, "reception of the reply, sim time [s]")
      .def_readonly("interrogation_stamp", &hadal::LblRange::interrogation_stamp, "emission of the interrogation [s]")
      .def_readonly("beacon", &hadal::LblRange::beacon, "the beacon's name")
      .def_readonly("interrogation", &hadal::LblRange::interrogation, "the interrogation's index")
      .def_readonly("travel_time", &hadal::LblRange::travel_time, "two-way, turnaround removed [s]")
      .def_readonly("range", &hadal::LblRange::range, "[m]")
      .def_readonly("range_variance", &hadal::LblRange::range_variance, "[m^2]")
      .def_readonly("beacon_position", &hadal::LblRange::beacon_position, "in W (ENU) [m]")
      .def_readonly("snr_db", &hadal::LblRange::snr_db, "the reply's SNR at the transceiver [dB]");
  py::class_<hadal::LblRanges>(m, "LblRanges",
                               "hadal_msgs/LblRanges: the LBL ranges whose replies arrived within one physics step")
      .def_readonly("stamp", &hadal::LblRanges::stamp, "the last range's [s]")
      .def_readonly("frame_id", &hadal::LblRanges::frame_id, "the transceiver's frame")
      .def_readonly("ranges", &hadal::LblRanges::ranges, "list of LblRange");

  py::class_<hadal::LaserScan>(m, "LaserScan",
                               "sensor_msgs/LaserScan of a fan of range beams (a profiler): beam k at "
                               "angle_min + k angle_increment about the sensor frame's z axis; values outside "
                               "[range_min, range_max] are not measurements (+inf no return, -inf too close)")
      .def_readonly("stamp", &hadal::LaserScan::stamp, "sim time of the scan's snapshot [s]")
      .def_readonly("frame_id", &hadal::LaserScan::frame_id)
      .def_readonly("angle_min", &hadal::LaserScan::angle_min, "first beam [rad]")
      .def_readonly("angle_max", &hadal::LaserScan::angle_max, "last beam [rad]")
      .def_readonly("angle_increment", &hadal::LaserScan::angle_increment, "between beams [rad]")
      .def_readonly("time_increment", &hadal::LaserScan::time_increment, "between beams' measurements [s]")
      .def_readonly("scan_time", &hadal::LaserScan::scan_time, "between scans [s]")
      .def_readonly("range_min", &hadal::LaserScan::range_min, "[m]")
      .def_readonly("range_max", &hadal::LaserScan::range_max, "[m]")
      .def_property_readonly("ranges", [](const hadal::LaserScan& l) { return to_numpy(l.ranges); },
                             "(beams,) float32 ranges [m]")
      .def_property_readonly("intensities", [](const hadal::LaserScan& l) { return to_numpy(l.intensities); },
                             "(beams,) or (0,) float32");

  py::class_<hadal::SimStatus>(m, "SimStatus")
      .def_readonly("sim_time", &hadal::SimStatus::sim_time)
      .def_readonly("wall_time", &hadal::SimStatus::wall_time)
      .def_readonly("real_time_factor", &hadal::SimStatus::real_time_factor)
      .def_readonly("step_count", &hadal::SimStatus::step_count)
      .def_readonly("step_size", &hadal::SimStatus::step_size)
      .def_readonly("mode", &hadal::SimStatus::mode)
      .def_readonly("vehicle_names", &hadal::SimStatus::vehicle_names)
      .def_readonly("vehicle_faults", &hadal::SimStatus::vehicle_faults)
      .def_readonly("rejected_commands", &hadal::SimStatus::rejected_commands)
      .def_readonly("last_error", &hadal::SimStatus::last_error)
      .def_readonly("dropped_captures", &hadal::SimStatus::dropped_captures);

  py::class_<hadal::Image, std::shared_ptr<hadal::Image>>(
      m, "Image",
      "sensor_msgs/Image of a camera: image_raw (rgb8 or mono8) or depth (32FC1, metres along the optical axis, "
      "NaN where nothing is hit); `array` views the pixels without a copy")
      .def_readonly("stamp", &hadal::Image::stamp, "sim time of the frame's snapshot [s]")
      .def_readonly("frame_id", &hadal::Image::frame_id, "the camera's optical frame (z forward, x right, y down)")
      .def_readonly("height", &hadal::Image::height, "[px]")
      .def_readonly("width", &hadal::Image::width, "[px]")
      .def_readonly("encoding", &hadal::Image::encoding)
      .def_readonly("step", &hadal::Image::step, "bytes per row")
      .def_property_readonly(
          "array", [](py::object self) { return image_array(self.cast<const hadal::Image&>(), self); },
          "numpy view of the pixels: (H, W, 3) uint8 (rgb8), (H, W) uint8 (mono8), (H, W) float32 (32FC1)");
  py::class_<hadal::CameraInfo>(m, "CameraInfo",
                                "sensor_msgs/CameraInfo of a camera: its calibration as configured")
      .def_readonly("stamp", &hadal::CameraInfo::stamp, "[s]")
      .def_readonly("frame_id", &hadal::CameraInfo::frame_id)
      .def_readonly("height", &hadal::CameraInfo::height, "[px]")
      .def_readonly("width", &hadal::CameraInfo::width, "[px]")
      .def_readonly("distortion_model", &hadal::CameraInfo::distortion_model, "plumb_bob or equidistant")
      .def_property_readonly("d", [](const hadal::CameraInfo& c) { return to_numpy(c.d); },
                             "distortion: k1, k2, p1, p2, k3 (plumb_bob) or k1..k4 (equidistant)")
      .def_property_readonly("k", [](const hadal::CameraInfo& c) { return to_numpy_3x3(c.k); }, "(3, 3) intrinsics")
      .def_property_readonly("r", [](const hadal::CameraInfo& c) { return to_numpy_3x3(c.r); }, "(3, 3) rectification")
      .def_property_readonly(
          "p",
          [](const hadal::CameraInfo& c) {
            py::array_t<double> out({3, 4});
            std::copy(c.p.begin(), c.p.end(), out.mutable_data());
            return out;
          },
          "(3, 4) projection");

  py::class_<hadal::ProjectedSonarImage, std::shared_ptr<hadal::ProjectedSonarImage>>(
      m, "SonarImage",
      "marine_acoustic_msgs/ProjectedSonarImage of a forward-looking sonar: array[bin, beam] the samples (uint8: the "
      "level over the display window; float32: intensity after TVG [uPa^2]), beam k at azimuth beam_azimuths[k] "
      "(positive to port), range bin centres `ranges`")
      .def_readonly("stamp", &hadal::ProjectedSonarImage::stamp, "sim time of the ping [s]")
      .def_readonly("frame_id", &hadal::ProjectedSonarImage::frame_id)
      .def_property_readonly("frequency_hz", [](const hadal::ProjectedSonarImage& s) { return s.ping_info.frequency_hz; })
      .def_property_readonly("sound_speed", [](const hadal::ProjectedSonarImage& s) { return s.ping_info.sound_speed_m_per_s; },
                             "sound speed at the sonar [m/s]")
      .def_property_readonly("beam_widths", [](const hadal::ProjectedSonarImage& s) { return to_numpy(s.ping_info.rx_beamwidths_rad); },
                             "(beams,) -3 dB width in the fan [rad]")
      .def_property_readonly("vertical_apertures", [](const hadal::ProjectedSonarImage& s) { return to_numpy(s.ping_info.tx_beamwidths_rad); },
                             "(beams,) -3 dB width across the fan [rad]")
      .def_property_readonly(
          "beam_azimuths",
          [](const hadal::ProjectedSonarImage& s) {
            std::vector<double> a;
            for (std::size_t k = 0; k < s.beam_directions.size(); ++k) a.push_back(s.beam_azimuth(k));
            return to_numpy(a);
          },
          "(beams,) atan2(-y, z) of the beam directions [rad]")
      .def_property_readonly("ranges", [](const hadal::ProjectedSonarImage& s) { return to_numpy(s.ranges); },
                             "(bins,) range bin centres [m]")
      .def_property_readonly("array", [](const hadal::ProjectedSonarImage& s) { return sonar_array(s.image); },
                             "(bins, beams) samples, uint8 or float32");
  py::class_<hadal::SonarDetections>(
      m, "SonarDetections",
      "marine_acoustic_msgs/SonarDetections of a multibeam: per beam its slant range (NaN without a detection), "
      "two-way travel time, peak intensity and steering angles (rx + to starboard)")
      .def_readonly("stamp", &hadal::SonarDetections::stamp, "sim time of the ping [s]")
      .def_readonly("frame_id", &hadal::SonarDetections::frame_id)
      .def_property_readonly("frequency_hz", [](const hadal::SonarDetections& s) { return s.ping_info.frequency_hz; })
      .def_property_readonly("sound_speed", [](const hadal::SonarDetections& s) { return s.ping_info.sound_speed_m_per_s; },
                             "sound speed at the sonar [m/s]")
      .def_property_readonly(
          "ranges",
          [](const hadal::SonarDetections& s) {
            std::vector<double> r;
            for (std::size_t k = 0; k < s.flags.size(); ++k) r.push_back(s.range_m(k));
            return to_numpy(r);
          },
          "(beams,) slant range c t / 2 [m], NaN without a detection")
      .def_property_readonly("flags", [](const hadal::SonarDetections& s) { return to_numpy(s.flags); },
                             "(beams,) 0 detection, 1 none")
      .def_property_readonly("two_way_travel_times", [](const hadal::SonarDetections& s) { return to_numpy(s.two_way_travel_times_s); },
                             "(beams,) [s]")
      .def_property_readonly("intensities", [](const hadal::SonarDetections& s) { return to_numpy(s.intensities); },
                             "(beams,) echo peak after TVG [uPa^2]")
      .def_property_readonly("rx_angles", [](const hadal::SonarDetections& s) { return to_numpy(s.rx_angles_rad); },
                             "(beams,) across track, + to starboard [rad]")
      .def_property_readonly("tx_angles", [](const hadal::SonarDetections& s) { return to_numpy(s.tx_angles_rad); },
                             "(beams,) along track, + forward [rad]");
  py::class_<hadal::RawSonarImage>(
      m, "RawSonarImage",
      "marine_acoustic_msgs/RawSonarImage of one side-scan channel: samples[i] from range ranges[i] on")
      .def_readonly("stamp", &hadal::RawSonarImage::stamp, "sim time of the ping [s]")
      .def_readonly("frame_id", &hadal::RawSonarImage::frame_id)
      .def_property_readonly("frequency_hz", [](const hadal::RawSonarImage& s) { return s.ping_info.frequency_hz; })
      .def_property_readonly("sound_speed", [](const hadal::RawSonarImage& s) { return s.ping_info.sound_speed_m_per_s; },
                             "sound speed at the sonar [m/s]")
      .def_readonly("sample_rate", &hadal::RawSonarImage::sample_rate_hz, "[Hz]")
      .def_readonly("sample0", &hadal::RawSonarImage::sample0)
      .def_property_readonly("rx_angle", [](const hadal::RawSonarImage& s) { return s.rx_angles_rad.empty() ? 0.0 : s.rx_angles_rad[0]; },
                             "across-track steering, + to starboard [rad]")
      .def_property_readonly(
          "ranges",
          [](const hadal::RawSonarImage& s) {
            std::vector<double> r;
            for (std::size_t i = 0; i < s.samples_per_beam; ++i) r.push_back(s.sample_range_m(i));
            return to_numpy(r);
          },
          "(samples,) range at which each sample starts, (sample0 + i) c / (2 sample_rate) [m]")
      .def_property_readonly(
          "samples", [](const hadal::RawSonarImage& s) { return sonar_array(s.image).attr("reshape")(-1); },
          "(samples,) uint8 or float32");

  using release = py::call_guard<py::gil_scoped_release>;
  py::class_<PyClient>(m, "Client", R"doc(A client of a hadald on a DDS domain (domain_id; None: $ROS_DOMAIN_ID, else 0).

Subscribes on first use and keeps the latest sample of each topic: wait_odometry, wait_imu, ... return the
first sample at or after min_stamp (sim time [s]), or None on timeout; a vehicle the server's status does
not list raises UnknownVehicle at once, naming those it has, and a sensor the vehicle does not have (or has as
another type: wait_imu on a DVL) UnknownSensor, naming its sensors and their types (from the server's scene). Commands with set_commands; steps
and resets a lockstep server with step and reset. Use it as a context manager (or call close()) to leave
the DDS domain at a known point:

    with hadal.Server("default") as server, hadal.Client(server.domain_id) as client:
        client.wait_for_server()
        client.set_commands("auv", [0.5, 0.0, 0.0])
        odom = client.wait_odometry("auv", min_stamp=client.step(500))

A server that goes silent (no status heartbeat for server_timeout_s, or three of its status periods) is
gone: server_alive() turns False and a step() waiting for its reply raises ServerLost; wait_for_server()
then waits for it (or a restarted one) to come back, and the same client carries on.

security_file: DDS Security, a YAML file with a `security:` block naming this client's certificate and key
and the domain's signed documents, as hadald --security takes it (tools/make-security-demo.sh writes one
per identity). Without it a secure server is invisible.

Errors: hadal.ServerNotFound, hadal.ServerLost, hadal.Timeout, hadal.UnknownVehicle, hadal.CommandRejected
(all hadal.ClientError).)doc")
      .def(py::init<std::optional<int>, const std::string&, double, const std::optional<std::filesystem::path>&>(),
           py::arg("domain_id") = py::none(), py::arg("name") = "hadal_python", py::arg("server_timeout_s") = 10.0,
           py::arg("security_file") = py::none(), release())
      .def("close", &PyClient::close, release(), "Leave the DDS domain now; later calls raise ClientError")
      .def_property_readonly("closed", &PyClient::closed)
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PyClient& self, py::args) {
        py::gil_scoped_release unlocked;
        self.close();
        return false;
      })
      .def("wait_for_server", &PyClient::wait_for_server, py::arg("timeout_s") = 10.0, release(),
           "Wait until the server is alive (its status heartbeat arrives: the first time, or again after it went "
           "silent); False on timeout")
      .def("server_alive", &PyClient::server_alive, release(),
           "True while the server's status keeps arriving (the last within server_timeout_s)")
      .def("seconds_since_status", &PyClient::seconds_since_status, release(),
           "Wall seconds since the last status arrived (inf before the first)")
      .def("wait_for_subscriptions", &PyClient::wait_for_subscriptions, py::arg("timeout_s") = 10.0, release())
      .def("status", &PyClient::status, "Latest SimStatus, or None")
      .def("subscribe", &PyClient::subscribe, py::arg("vehicle"), release(),
           "Subscribe to a vehicle's odometry and thruster state (done on first use otherwise)")
      .def("odometry", &PyClient::odometry, py::arg("vehicle"), release(), "Latest Odometry, or None")
      .def("wait_odometry", &PyClient::wait_odometry, py::arg("vehicle"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(), "Odometry with stamp >= min_stamp, or None on timeout")
      .def("thruster_state", &PyClient::thruster_state, py::arg("vehicle"), release())
      .def("wait_thruster_state", &PyClient::wait_thruster_state, py::arg("vehicle"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release())
      .def("wait_track_state", &PyClient::wait_track_state, py::arg("vehicle"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(), "TrackStates with stamp >= min_stamp, or None on timeout")
      .def("wait_fin_state", &PyClient::wait_fin_state, py::arg("vehicle"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(), "FinStates with stamp >= min_stamp, or None on timeout")
      .def("wait_buoyancy_engine_state", &PyClient::wait_buoyancy_engine_state, py::arg("vehicle"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "BuoyancyEngineStates with stamp >= min_stamp, or None on timeout")
      .def("wait_drop_weight_state", &PyClient::wait_drop_weight_state, py::arg("vehicle"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(), "DropWeightStates with stamp >= min_stamp, or None on timeout")
      .def("wait_joint_state", &PyClient::wait_joint_state, py::arg("vehicle"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(), "JointStates with stamp >= min_stamp, or None on timeout")
      .def("wait_imu", &PyClient::wait_imu, py::arg("vehicle"), py::arg("sensor"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(), "Imu sample with stamp >= min_stamp, or None on timeout")
      .def("wait_fluid_pressure", &PyClient::wait_fluid_pressure, py::arg("vehicle"), py::arg("sensor"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "FluidPressure sample with stamp >= min_stamp, or None on timeout")
      .def("wait_wrench", &PyClient::wait_wrench, py::arg("vehicle"), py::arg("sensor"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(),
           "Wrench sample of rt/<vehicle>/<sensor> (a force_torque sensor) with stamp >= min_stamp, or None on "
           "timeout")
      .def("wait_magnetic_field", &PyClient::wait_magnetic_field, py::arg("vehicle"), py::arg("sensor"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "MagneticField sample of rt/<vehicle>/<sensor> with stamp >= min_stamp, or None on timeout")
      .def("wait_nav_sat_fix", &PyClient::wait_nav_sat_fix, py::arg("vehicle"), py::arg("sensor"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "NavSatFix sample of rt/<vehicle>/<sensor> with stamp >= min_stamp, or None on timeout")
      .def("wait_dvl", &PyClient::wait_dvl, py::arg("vehicle"), py::arg("sensor"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(),
           "Dvl sample of rt/<vehicle>/<sensor> with stamp >= min_stamp, or None on timeout")
      .def("wait_range", &PyClient::wait_range, py::arg("vehicle"), py::arg("sensor"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(),
           "Range sample of rt/<vehicle>/<sensor> with stamp >= min_stamp, or None on timeout")
      .def("wait_usbl_fixes", &PyClient::wait_usbl_fixes, py::arg("vehicle"), py::arg("sensor"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "UsblFixes sample of rt/<vehicle>/<sensor> (a USBL) with stamp >= min_stamp, or None on timeout")
      .def("wait_lbl_ranges", &PyClient::wait_lbl_ranges, py::arg("vehicle"), py::arg("sensor"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "LblRanges sample of rt/<vehicle>/<sensor> (an LBL) with stamp >= min_stamp, or None on timeout")
      .def("wait_laser_scan", &PyClient::wait_laser_scan, py::arg("vehicle"), py::arg("sensor"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "LaserScan of rt/<vehicle>/<sensor> (a profiler) with stamp >= min_stamp, or None on timeout")
      .def("wait_image", &PyClient::wait_image, py::arg("vehicle"), py::arg("camera"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(),
           "Image of rt/<vehicle>/<camera>/image_raw with stamp >= min_stamp, or None on timeout")
      .def("wait_depth_image", &PyClient::wait_depth_image, py::arg("vehicle"), py::arg("camera"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "Image (32FC1) of rt/<vehicle>/<camera>/depth with stamp >= min_stamp, or None on timeout")
      .def("wait_camera_info", &PyClient::wait_camera_info, py::arg("vehicle"), py::arg("camera"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "CameraInfo of rt/<vehicle>/<camera>/camera_info with stamp >= min_stamp, or None on timeout")
      .def("wait_sonar_image", &PyClient::wait_sonar_image, py::arg("vehicle"), py::arg("sensor"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "SonarImage of rt/<vehicle>/<sensor> (a forward-looking sonar) with stamp >= min_stamp, or None on timeout")
      .def("wait_sonar_detections", &PyClient::wait_sonar_detections, py::arg("vehicle"), py::arg("sensor"),
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "SonarDetections of rt/<vehicle>/<sensor> (a multibeam) with stamp >= min_stamp, or None on timeout")
      .def("wait_raw_sonar_image", &PyClient::wait_raw_sonar_image, py::arg("vehicle"), py::arg("sensor"),
           py::arg("channel") = "port", py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "RawSonarImage of rt/<vehicle>/<sensor>/<channel> (a side-scan's 'port' or 'starboard') with stamp >= "
           "min_stamp, or None on timeout")
      .def("wait_cable_force", &PyClient::wait_cable_force, py::arg("cable"), py::arg("end") = "from",
           py::arg("min_stamp") = 0.0, py::arg("timeout_s") = 10.0, release(),
           "Wrench of rt/hadal/cables/<cable>/<end> ('from' or 'to'): the force [N, W] the cable put on what holds "
           "that end over the last step, with stamp >= min_stamp, or None on timeout")
      .def("wait_cable_shape", &PyClient::wait_cable_shape, py::arg("cable"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(),
           "CableShape of rt/hadal/cables/<cable>/shape (.points: the nodes in W) with stamp >= min_stamp, or None "
           "on timeout")
      .def("wait_sea_state", &PyClient::wait_sea_state, py::arg("vehicle"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(),
           "SeaState of rt/<vehicle>/sea_state (a scenario with waves) with stamp >= min_stamp, or None on timeout")
      .def("wait_winch_state", &PyClient::wait_winch_state, py::arg("cable"), py::arg("min_stamp") = 0.0,
           py::arg("timeout_s") = 10.0, release(),
           "WinchState of rt/hadal/cables/<cable>/winch/state with stamp >= min_stamp, or None on timeout")
      .def("command_winch", &PyClient::command_winch, py::arg("cable"), py::arg("speed"),
           py::arg("target_length") = 0.0, py::arg("publish") = true, release(),
           "Commands the cable's winch: run at `speed` [m/s] (+ pays out, - hauls in) until told otherwise or a limit; "
           "with target_length > 0 [m], run at |speed| toward that length in the water and stop there. Published on "
           "rt/hadal/cables/<cable>/winch/command and attached to the next step()/reset(); publish=False: only "
           "attached (lockstep). The server refuses a cable without a winch, a speed beyond its max_speed, a target "
           "beyond its drum_length or below its min_length (CommandRejected in lockstep)")
      .def("receive_packets", &PyClient::receive_packets, py::arg("vehicle"), py::arg("modem"),
           py::arg("timeout_s") = 0.0, release(),
           "The packets the acoustic modem rt/<vehicle>/<modem> decoded (list of AcousticPacket, oldest first) since "
           "the last call: every one from the first call on, which subscribes. Waits up to timeout_s for one when "
           "none is there")
      .def(
          "send_packet",
          [](PyClient& self, const std::string& vehicle, const std::string& modem, const py::bytes& payload,
             const std::string& destination, bool publish) {
            const std::string data = payload;
            const std::vector<std::uint8_t> bytes(data.begin(), data.end());
            py::gil_scoped_release unlocked;
            self.send_packet(vehicle, modem, bytes, destination, publish);
          },
          py::arg("vehicle"), py::arg("modem"), py::arg("payload"), py::arg("destination") = "",
          py::arg("publish") = true,
          "Gives the acoustic modem a packet (bytes) to send to `destination` ('' every modem, a vehicle's modems, "
          "or '<vehicle>/<modem>'), published on rt/<vehicle>/<modem>/tx; publish=False: attached to the next "
          "step()/reset() instead (lockstep: queued exactly before its first step; a refusal raises "
          "CommandRejected there). The server refuses an empty or oversize payload, an unknown destination or a "
          "full queue")
      .def("set_joint_commands", &PyClient::set_joint_commands, py::arg("vehicle"), py::arg("controller"),
           py::arg("values"), py::arg("publish") = true, release(),
           "A joint controller's command (the scenario's joint_controllers): one value per joint of the group, in "
           "its order (a position [rad or m], rate or effort); a gripper's: [position] or [position, max_effort]. "
           "Published on rt/<vehicle>/<controller>/commands "
           "and attached to the next step()/reset(); publish=False: only attached (lockstep)")
      .def("set_joint_trajectory", &PyClient::set_joint_trajectory, py::arg("vehicle"), py::arg("controller"),
           py::arg("joint_names"), py::arg("times"), py::arg("positions"), py::arg("velocities") = std::nullopt,
           py::arg("accelerations") = std::nullopt, py::arg("start_time") = std::nullopt,
           "A trajectory for a position group (trajectory_msgs/JointTrajectory, as ros2_control's "
           "joint_trajectory_controller takes it): waypoints at `times` [s] after its start (start_time, a sim "
           "time [s]; None: when the server applies it), `positions` one row per waypoint and one column per "
           "name in joint_names (the group's joints in any order) [rad or m], optional `velocities` and "
           "`accelerations` of the same shape. Between waypoints each joint moves on a line, a cubic (with "
           "velocities) or a quintic (with accelerations), from where it is when the trajectory starts; then "
           "the last waypoint is held. Published on rt/<vehicle>/<controller>/joint_trajectory and attached to "
           "the next step()/reset(); the server refuses a bad one (CommandRejected in lockstep)")
      .def("set_commands", &PyClient::set_commands, py::arg("vehicle"), py::arg("commands"),
           py::arg("publish") = true, release(),
           "The vehicle's control vector: one entry per actuator (thrusters, tracks, fins, buoyancy engines, drop "
           "weights, each kind in scenario order), normalised [-1, 1] (a drop weight: 0 or 1). Published on "
           "rt/<vehicle>/actuators/commands and attached to the next step()/reset(); publish=False: only attached "
           "(lockstep; one DDS sample less per control period)")
      // The name before the control vector drove every actuator kind: refused, naming the new one.
      .def("set_thrusters",
           [](PyClient&, py::args, py::kwargs) -> void {
             throw py::attribute_error(
                 "Client.set_thrusters was renamed set_commands (the control vector commands every actuator: "
                 "thrusters, tracks, fins, buoyancy engines, drop weights)");
           })
      .def("step", &PyClient::step, py::arg("steps") = 1, py::arg("timeout_s") = 30.0, release(),
           "Lockstep: advance the server by `steps` physics steps (commands set since the last request are "
           "applied first); returns the sim time reached [s]. Raises ServerNotFound, Timeout, UnknownVehicle or "
           "CommandRejected (with the server's reason)")
      .def("reset", &PyClient::reset, py::arg("seed") = py::none(),
           py::arg("poses") = std::map<std::string, std::vector<double>>{}, py::arg("steps") = 0,
           py::arg("timeout_s") = 30.0, release(),
           "Lockstep: start the run over from the scenario's initial state at sim time 0, without restarting the "
           "server. seed: the sensors' noise seed (None: the scenario's); poses: {vehicle: (x, y, z) or (x, y, z, "
           "qx, qy, qz, qw)} in W [m] to start those vehicles elsewhere, at rest. Then applies pending setpoints "
           "and runs `steps` steps; returns the sim time reached [s]. Samples kept from before are forgotten; "
           "odometry at t = 0 is published before the reply. Raises as step()")
      .def("send_step", &PyClient::send_step, py::arg("steps") = 1, py::arg("timeout_s") = 30.0, release(),
           "Lockstep, without waiting: sends the request step() would and returns its id at once; wait_reply(id) "
           "returns what step() would have. Send to several servers, then wait for each: they step in parallel. "
           "Raises ServerNotFound as step()")
      .def("send_reset", &PyClient::send_reset, py::arg("seed") = py::none(),
           py::arg("poses") = std::map<std::string, std::vector<double>>{}, py::arg("steps") = 0,
           py::arg("timeout_s") = 30.0, release(), "reset() without waiting: its request id, for wait_reply()")
      .def("wait_reply", &PyClient::wait_reply, py::arg("request_id"), py::arg("timeout_s") = 30.0, release(),
           "Waits for the reply to a request sent with send_step()/send_reset(): the sim time reached [s]. Raises "
           "as step(); ClientError for an id that is not waiting (each is waited for once)")
      .def("reply_odometry", &PyClient::reply_odometry, py::arg("vehicle"), release(),
           "Lockstep: the vehicle's ground truth at the sim time of the last reply waited for (step, reset, "
           "wait_reply), the numbers its odometry carries at that instant (frame_id left empty). Every reply "
           "carries every vehicle's: no odometry subscription needed. Raises ClientError before the first reply, "
           "UnknownVehicle for a vehicle the reply does not have");
}
