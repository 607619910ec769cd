#include "hadal/core/model.h"

#include "hadal/physics/actuator_kinds.h"
#include "hadal/sensors/sensor_kinds.h"

#include <sched.h>

#include <algorithm>
#include <cmath>
#include <thread>

namespace hadal {

int WorldSpec::effective_threads() const {
  if (threads > 0) return threads;
  cpu_set_t allowed;  // the CPUs this process may run on (hadald --cpus, taskset, a container's cpuset)
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof(allowed), &allowed) == 0) return std::max(1, CPU_COUNT(&allowed));
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

int VehicleSpec::link_index(const std::string& link_name) const {
  for (std::size_t i = 0; i < links.size(); ++i) {
    if (links[i].name == link_name) return static_cast<int>(i);
  }
  return -1;
}

std::string_view SensorSpec::type() const {
  return std::visit([](const auto& spec) { return sensors::KindOf<std::decay_t<decltype(spec)>>::kType; }, kind);
}

bool SensorSpec::captured() const {
  return std::visit([](const auto& spec) { return sensors::KindOf<std::decay_t<decltype(spec)>>::kCaptures; }, kind);
}

std::uint64_t SensorSpec::latency_steps(double physics_rate_hz) const {
  return static_cast<std::uint64_t>(std::ceil(latency_s * physics_rate_hz - 1e-6));
}

std::string_view ActuatorSpec::type() const {
  return std::visit([](const auto& spec) { return std::decay_t<decltype(spec)>::Kind::kType; }, kind);
}

std::size_t ActuatorSpec::num_controls() const {
  return std::visit([](const auto& spec) { return std::decay_t<decltype(spec)>::Kind::kControls; }, kind);
}

std::size_t VehicleSpec::num_controls() const {
  std::size_t n = 0;
  for (const ActuatorSpec& actuator : actuators) n += actuator.num_controls();
  return n;
}

int Model::vehicle_index(const std::string& name) const {
  for (std::size_t i = 0; i < vehicles.size(); ++i) {
    if (vehicles[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int Model::cable_index(const std::string& name) const {
  for (std::size_t c = 0; c < cables.size(); ++c) {
    if (cables[c].name == name) return static_cast<int>(c);
  }
  return -1;
}

namespace {
struct VehicleTypeName {
  VehicleType type;
  const char* name;
};
constexpr VehicleTypeName kVehicleTypeNames[] = {
    {VehicleType::kAuv, "auv"},         {VehicleType::kRov, "rov"},
    {VehicleType::kLander, "lander"},   {VehicleType::kSurfaceVessel, "surface_vessel"},
    {VehicleType::kGlider, "glider"},   {VehicleType::kCrawler, "crawler"},
    {VehicleType::kObject, "object"},
};
}  // namespace

const char* to_string(VehicleType type) {
  for (const auto& entry : kVehicleTypeNames) {
    if (entry.type == type) return entry.name;
  }
  return "unknown";
}

std::optional<VehicleType> vehicle_type_from_string(const std::string& text) {
  for (const auto& entry : kVehicleTypeNames) {
    if (text == entry.name) return entry.type;
  }
  return std::nullopt;
}

}  // namespace hadal
