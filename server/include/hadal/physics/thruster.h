// Propeller thruster (actuator kind "thruster", YAML list `thrusters`): first-order rotor dynamics and
// open-water thrust/torque (Fossen, "Handbook of Marine Craft Hydrodynamics and Motion Control", 2011,
// sec. 9.4; no advance-ratio dependence). Its control is one normalised setpoint in [-1, 1].
//
//   rotor   n_cmd = setpoint * n_max                                   [rev/s]
//           n_{k+1} = n_k + (n_cmd - n_k) (1 - exp(-dt / tau))         (exact discretisation of
//           dn/dt = (n_cmd - n) / tau for a command held over the step; tau = 0: n_{k+1} = n_cmd)
//   thrust  T = K_T rho D^4 n|n|                 [N],   f_W   = T axis_W  applied at p_WT
//   torque  Q = -handedness K_Q rho D^5 n|n|    [N m], tau_W = Q axis_W  (propeller reaction on B)
//
// with axis_W = R_WB R_BL axis_L and p_WT = X_WB X_BL p_LT. A propeller above the water surface
// (p_WT.z > surface_z) is in air: T = Q = 0 while the rotor keeps spinning.
// YAML keys: ThrusterActuator::keys() (server/src/physics/thruster.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/config/key_table_fwd.h"
#include "hadal/physics/actuator_kind.h"
#include "hadal/physics/thruster_spec.h"

namespace hadal::physics {

class Thruster;

struct ThrusterActuator {
  static constexpr std::string_view kType = "thruster";
  static constexpr std::string_view kListKey = "thrusters";
  static constexpr std::size_t kControls = 1;  // the normalised setpoint

  using Spec = ThrusterSpec;
  struct State {
    using Kind = ThrusterActuator;
    double setpoint = 0.0;           // normalised command in [-1, 1] currently applied
    double rotor_speed_rev_s = 0.0;  // n [rev/s]
    double thrust_N = 0.0;           // along the thruster axis
    double torque_Nm = 0.0;          // reaction torque about the thruster axis
  };
  using Runtime = Thruster;

  // Its YAML keys besides name and link, declared once (configs/REFERENCE.md shows them).
  static const config::KeyTable<Spec>& keys();
  static Runtime prepare(const Spec& spec, const ActuatorSetup& setup);
  // "" when controls[0] is finite and in [-1, 1], else why not ("setpoint[first] is NaN", ...).
  static std::string check(const Spec& spec, const double* controls, std::size_t first);
  // Holds controls[0] as the setpoint (a last-line guard clamps it to [-1, 1], NaN to 0).
  static void command(State& state, const double* controls);
  static void actuate(const Runtime& runtime, State& state);
  static void add_wrench(const Runtime& runtime, State& state, const ActuatorForceInput& in, StepWrench& out);
  static void stop(State& state);
  static bool is_finite(const State& state) { return std::isfinite(state.rotor_speed_rev_s); }
};

// Thrust and reaction torque of one thruster in the current pose.
struct ThrusterWrench {
  double thrust = 0.0;                              // T along the axis [N]
  double torque = 0.0;                              // Q about the axis [N m]
  Eigen::Vector3d p_WT = Eigen::Vector3d::Zero();   // point of application, in W [m]
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();    // force on B at p_WT, in W [N]
  Eigen::Vector3d tau_W = Eigen::Vector3d::Zero();  // pure moment on B, in W [N m]
};

// The constants of one thruster derived from its spec, its link's pose and the world.
class Thruster {
 public:
  // X_BL: pose in B of the link the thruster is mounted on; dt: the fixed physics step [s].
  Thruster(const ThrusterActuator::Spec& spec, const Eigen::Isometry3d& X_BL, double water_density, double dt);

  double commanded_rotor_speed(double setpoint) const { return setpoint * max_rotor_speed_rev_s_; }

  // Rotor speed after one step of dt with `setpoint` held, starting from n [rev/s].
  double next_rotor_speed(double n, double setpoint) const {
    return n + (commanded_rotor_speed(setpoint) - n) * response_per_step_;
  }

  double thrust_in_water(double n) const { return thrust_gain_ * n * std::abs(n); }
  double torque_in_water(double n) const { return torque_gain_ * n * std::abs(n); }

  // Thrust and torque at rotor speed n [rev/s] with the vehicle at X_WB; zero in air (p_WT.z > surface_z).
  ThrusterWrench wrench(double n, const Eigen::Isometry3d& X_WB, double surface_z) const;

  const Eigen::Vector3d& p_BT() const { return p_BT_; }
  const Eigen::Vector3d& axis_B() const { return axis_B_; }

 private:
  Eigen::Vector3d p_BT_;
  Eigen::Vector3d axis_B_;        // unit
  double max_rotor_speed_rev_s_;
  double response_per_step_;      // 1 - exp(-dt / tau), 1 for tau = 0
  double thrust_gain_;            // K_T rho D^4 [kg m]
  double torque_gain_;            // -handedness K_Q rho D^5 [kg m^2]
};

}  // namespace hadal::physics
