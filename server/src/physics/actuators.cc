#include "hadal/physics/actuators.h"

#include "hadal/physics/control_vector.h"

#include <type_traits>

namespace hadal::physics {

namespace {

template <class Spec>
using Kind = typename Spec::Kind;

// Whether kind K drives a surface (K::kDrivesSurface, physics/track.h).
template <class K, class = void>
struct DrivesSurface : std::false_type {};
template <class K>
struct DrivesSurface<K, std::void_t<decltype(K::kDrivesSurface)>> : std::bool_constant<K::kDrivesSurface> {};

// Whether a spec of kind K reads the seabed (K::needs_seabed(spec), physics/drop_weight.h).
template <class K, class = void>
struct HasNeedsSeabed : std::false_type {};
template <class K>
struct HasNeedsSeabed<K, std::void_t<decltype(K::needs_seabed(std::declval<const typename K::Spec&>()))>>
    : std::true_type {};

}  // namespace

bool VehicleActuators::needs_seabed(const VehicleSpec& vehicle) {
  bool needs = false;
  for (const ActuatorSpec& actuator : vehicle.actuators) {
    std::visit(
        [&](const auto& spec) {
          using K = Kind<std::decay_t<decltype(spec)>>;
          if constexpr (HasNeedsSeabed<K>::value) needs |= K::needs_seabed(spec);
        },
        actuator.kind);
  }
  return needs;
}

VehicleActuators::VehicleActuators(const VehicleSpec& vehicle, const WorldSpec& world, const Ocean* ocean)
    : vehicle_(vehicle), ocean_(ocean), surface_z_(world.water.surface_z) {
  for (const ActuatorSpec& actuator : vehicle.actuators) {
    const auto link = static_cast<std::size_t>(actuator.link_index);
    const ActuatorSetup setup{vehicle.links[link].X_BL, world.water.density, world.step_size(), link};
    std::visit([&](const auto& spec) { runtimes_.emplace_back(Kind<std::decay_t<decltype(spec)>>::prepare(spec, setup)); },
               actuator.kind);
    std::visit([&](const auto& spec) { drives_surfaces_ |= DrivesSurface<Kind<std::decay_t<decltype(spec)>>>::value; },
               actuator.kind);
    first_control_.push_back(num_controls_);
    num_controls_ += actuator.num_controls();
  }
}

std::vector<ActuatorKindState> VehicleActuators::initial_states(const VehicleSpec& vehicle) {
  std::vector<ActuatorKindState> states;
  for (const ActuatorSpec& actuator : vehicle.actuators) {
    std::visit([&](const auto& spec) { states.emplace_back(typename Kind<std::decay_t<decltype(spec)>>::State{}); },
               actuator.kind);
  }
  return states;
}

std::string VehicleActuators::check(const std::vector<double>& controls) const {
  if (controls.size() != num_controls_) {
    std::string reason = "expected " + std::to_string(num_controls_) + (num_controls_ == 1 ? " setpoint" : " setpoints");
    if (!vehicle_.actuators.empty()) {
      reason += " (";
      for (std::size_t k = 0; k < vehicle_.actuators.size(); ++k) reason += (k > 0 ? ", " : "") + vehicle_.actuators[k].name;
      reason += ")";
    }
    return reason + ", got " + std::to_string(controls.size());
  }
  return check_actuator_controls(vehicle_.actuators, controls);
}

void VehicleActuators::command(std::vector<ActuatorKindState>& states, const std::vector<double>& controls) const {
  std::vector<double> padded;
  const std::vector<double>* held = &controls;
  if (controls.size() < num_controls_) {
    padded = controls;
    padded.resize(num_controls_, 0.0);
    held = &padded;
  }
  for (std::size_t k = 0; k < states.size(); ++k) {
    std::visit([&](auto& state) { std::decay_t<decltype(state)>::Kind::command(state, &(*held)[first_control_[k]]); },
               states[k]);
  }
}

void VehicleActuators::actuate(std::vector<ActuatorKindState>& states) const {
  for (std::size_t k = 0; k < states.size(); ++k) {
    std::visit(
        [&](auto& state) {
          using K = typename std::decay_t<decltype(state)>::Kind;
          K::actuate(std::get<typename K::Runtime>(runtimes_[k]), state);
        },
        states[k]);
  }
}

void VehicleActuators::stop(std::vector<ActuatorKindState>& states) {
  for (ActuatorKindState& state : states) {
    std::visit([](auto& s) { std::decay_t<decltype(s)>::Kind::stop(s); }, state);
  }
}

bool VehicleActuators::is_finite(const std::vector<ActuatorKindState>& states) {
  for (const ActuatorKindState& state : states) {
    if (!std::visit([](const auto& s) { return std::decay_t<decltype(s)>::Kind::is_finite(s); }, state)) return false;
  }
  return true;
}

void VehicleActuators::add_wrenches(const ForceInput& in, StepWrench& out) const {
  const ActuatorForceInput input{in.body.X_WB, in.p_WBcm, surface_z_,     in.time,
                                 in.body.v_WB, in.body.w_WB, ocean_, in.seabed_z_below};
  for (std::size_t k = 0; k < in.actuators.size(); ++k) {
    std::visit(
        [&](auto& state) {
          using K = typename std::decay_t<decltype(state)>::Kind;
          K::add_wrench(std::get<typename K::Runtime>(runtimes_[k]), state, input, out);
        },
        in.actuators[k]);
  }
}

void VehicleActuators::belt_velocities(const std::vector<ActuatorKindState>& states,
                                       std::vector<Eigen::Vector3d>& belts) const {
  belts.assign(vehicle_.links.size(), Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < states.size(); ++k) {
    std::visit(
        [&](const auto& state) {
          using K = typename std::decay_t<decltype(state)>::Kind;
          if constexpr (DrivesSurface<K>::value) {
            const auto& runtime = std::get<typename K::Runtime>(runtimes_[k]);
            belts[K::belt_link(runtime)] += K::belt_velocity_B(runtime, state);
          }
        },
        states[k]);
  }
}

void VehicleActuators::take_belt_forces(std::vector<ActuatorKindState>& states,
                                        const std::vector<Eigen::Vector3d>& link_forces_W,
                                        const Eigen::Matrix3d& R_WB) const {
  for (std::size_t k = 0; k < states.size(); ++k) {
    std::visit(
        [&](auto& state) {
          using K = typename std::decay_t<decltype(state)>::Kind;
          if constexpr (DrivesSurface<K>::value) {
            const auto& runtime = std::get<typename K::Runtime>(runtimes_[k]);
            const std::size_t link = K::belt_link(runtime);
            const Eigen::Vector3d force_W = link < link_forces_W.size() ? link_forces_W[link] : Eigen::Vector3d::Zero();
            K::take_belt_force(runtime, state, R_WB.transpose() * force_W);
          }
        },
        states[k]);
  }
}

}  // namespace hadal::physics
