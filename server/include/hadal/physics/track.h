// Driven track (actuator kind "track", YAML list `tracks`): a crawler's track or a driven wheel, whose
// belt surface moves over the body, driven through a sprocket by an electric motor with a speed loop.
// Its control is one normalised belt-speed setpoint in [-1, 1]. The track pushes on nothing itself: its
// belt velocity is handed to the soil contact (physics/terramechanics.h), which turns slip into traction
// on the link's faces, and the soil's shear on the link comes back as the belt's load.
//
//   belt speed     V [m/s] along the track's forward direction d (positive: driving forward, so the belt's
//                  ground run moves along -d over the body: belt velocity -V d, in B)
//   sprocket       omega = V / r
//   command        V_cmd = setpoint * omega_0 r
//   load           F = the soil's shear on the link along d in the last step [N] (traction when > 0)
//   motor torque   tau = J a_cmd / r + F r, a_cmd = (V_cmd - V) / tau_s      (the speed loop's demand)
//                  clamped to the motor's envelope: |tau| <= tau_stall (1 - |omega| / omega_0) while driving
//                  (tau and omega of one sign), |tau| <= tau_stall while braking
//   dynamics       J dV/dt = (tau - F r) r                                   (explicit Euler, one step)
//   current        I = tau / k_t;  mechanical power P = tau omega
// with J the drive train's inertia at the sprocket. A stalled track (F r above what the motor gives at
// that speed) slows down and slips less; a track in the air (F = 0) runs at V_cmd after ~3 tau_s.
// A wheel is the same with r its radius: its tread is the belt.
//
// YAML keys: TrackActuator::keys() (server/src/physics/track.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/config/key_table_fwd.h"
#include "hadal/physics/actuator_kind.h"
#include "hadal/physics/track_spec.h"

namespace hadal::physics {

struct TrackActuator;

// The constants of one track.
struct TrackDrive {
  std::size_t link = 0;                              // the link whose faces are its belt
  Eigen::Vector3d direction_B = Eigen::Vector3d::UnitX();  // d in B, unit
  double radius = 0.0;                               // r [m]
  double no_load_speed = 0.0;                        // omega_0 [rad/s]
  double stall_torque = 0.0;                         // [N m]
  double torque_constant = 1.0;                      // [N m/A]
  double inertia = 0.5;                              // J [kg m^2]
  double speed_time_constant = 0.2;                  // tau_s [s]
  double dt = 0.002;                                 // [s]
};

struct TrackActuator {
  static constexpr std::string_view kType = "track";
  static constexpr std::string_view kListKey = "tracks";
  static constexpr std::size_t kControls = 1;  // the normalised belt-speed setpoint
  static constexpr bool kDrivesSurface = true;  // hands a belt velocity to the soil (physics/actuators.h)

  using Spec = TrackSpec;
  struct State {
    using Kind = TrackActuator;
    double setpoint = 0.0;          // normalised command in [-1, 1] currently applied
    double belt_speed = 0.0;        // V [m/s]
    double sprocket_speed = 0.0;    // omega [rad/s]
    double motor_torque_Nm = 0.0;   // tau at the sprocket
    double current_A = 0.0;         // I
    double power_W = 0.0;           // tau omega
    double load_N = 0.0;            // F: the soil's shear on the belt along d in the last step
  };
  using Runtime = TrackDrive;

  // Its YAML keys besides name and link, declared once (configs/REFERENCE.md shows them).
  static const config::KeyTable<Spec>& keys();
  static Runtime prepare(const Spec& spec, const ActuatorSetup& setup);
  static std::string check(const Spec& spec, const double* controls, std::size_t first);
  static void command(State& state, const double* controls);
  static void actuate(const Runtime& runtime, State& state);
  // A track adds no wrench of its own (its traction is the soil's force on its link).
  static void add_wrench(const Runtime&, State&, const ActuatorForceInput&, StepWrench&) {}
  static void stop(State& state);
  static bool is_finite(const State& state) { return std::isfinite(state.belt_speed); }

  // The belt's velocity over the body, in B [m/s], and the link it moves.
  static Eigen::Vector3d belt_velocity_B(const Runtime& runtime, const State& state) {
    return -state.belt_speed * runtime.direction_B;
  }
  static std::size_t belt_link(const Runtime& runtime) { return runtime.link; }
  // Records the soil's shear force on the belt's link (in B) as the load for the next step.
  static void take_belt_force(const Runtime& runtime, State& state, const Eigen::Vector3d& force_B) {
    state.load_N = force_B.dot(runtime.direction_B);
  }
};

}  // namespace hadal::physics
