// Fin (actuator kind "fin", YAML list `fins`): a servo-driven lifting surface -- an AUV's elevator or
// rudder, a glider's tail -- with its own lift and drag. Its control is one normalised deflection
// setpoint in [-1, 1]: delta_cmd = setpoint delta_max. A fin is the whole hydrodynamics of that surface:
// do not also list it among the link's collision shapes, whose faces the surface fluid model would
// count a second time.
//
//   servo     delta moves towards delta_cmd at the servo's rate omega_s:
//             delta_{k+1} = delta_k + clamp(delta_cmd - delta_k, -omega_s dt, omega_s dt)
//   geometry  hinge axis a (unit), chord direction c0 (unit, from trailing to leading edge, a . c0 = 0),
//             both in B; a positive deflection turns the chord about a (right hand):
//             c = c0 cos delta + (a x c0) sin delta,   n = a x c
//   flow      at the fin's centre of pressure p_WF: U = v_water(p_WF) - v_WF (water relative to the fin),
//             its part across the span U_p = U - (U . a) a, e = U_p / |U_p|;
//             angle of attack alpha = atan2(e . n, -e . c)  (0 when the water comes at the leading edge)
//   forces    L = q S C_L(alpha) (e x a),  D = q S C_D(alpha) e,  q = rho |U_p|^2 / 2,  at p_WF
//             attached (|alpha| <= alpha_s): C_L = C_La alpha,  C_D = C_D0 + C_L^2 / (pi e_O AR)
//             stalled, continuous at alpha_s (a controller that saturates the fin meets no jump):
//               C_L = C_La alpha_s sin(2 alpha) / sin(2 alpha_s)      (zero broadside, reversed behind)
//               C_D = C_D(alpha_s) + C_N90 (sin^2 alpha - sin^2 alpha_s)  (toward the flat plate's)
//             (C_N90 = 1.2, a flat plate's normal-force coefficient broadside: Hoerner, "Fluid-Dynamic
//             Drag", 1965, ch. 3). Real stall is more abrupt; this keeps the force a continuous
//             function of the state. Low-aspect-ratio fins stall late, ~30 deg below AR 2 (default).
//   C_La      the lift slope of a finite wing of effective aspect ratio AR (Helmbold's equation:
//             C_La = 2 pi AR / (2 + sqrt(AR^2 + 4)); 2.60 per radian at AR 2)
// Nothing above the water surface. A fin standing on a hull has the hull as a reflection plane: its
// effective aspect ratio is twice its span over its chord.
//
// YAML keys: FinActuator::keys() (server/src/physics/fin.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/config/key_table_fwd.h"
#include "hadal/core/units.h"
#include "hadal/physics/actuator_kind.h"
#include "hadal/physics/fin_spec.h"

namespace hadal::physics {

struct FinActuator {
  static constexpr std::string_view kType = "fin";
  static constexpr std::string_view kListKey = "fins";
  static constexpr std::size_t kControls = 1;  // the normalised deflection setpoint
  static constexpr double kBroadsideNormalForce = 1.2;  // C_N90 of a flat plate

  using Spec = FinSpec;
  struct State {
    using Kind = FinActuator;
    double setpoint = 0.0;        // normalised command in [-1, 1] currently applied
    double angle = 0.0;           // delta [rad]
    double attack_angle = 0.0;    // alpha [rad] in the last step
    double lift_N = 0.0;          // |L| signed as C_L
    double drag_N = 0.0;          // |D|
  };
  struct Runtime {
    Eigen::Vector3d p_BF = Eigen::Vector3d::Zero();
    Eigen::Vector3d a_B = Eigen::Vector3d::UnitY();
    Eigen::Vector3d c0_B = Eigen::Vector3d::UnitX();
    double area = 0.0, aspect_ratio = 0.0, max_angle = 0.0, max_step = 0.0, lift_slope = 0.0;
    double stall_angle = 0.0, drag_coefficient = 0.01, oswald_efficiency = 0.9;
  };

  // Helmbold's lift slope of a wing of aspect ratio AR [1/rad].
  static double helmbold_lift_slope(double aspect_ratio) {
    return 2.0 * 3.14159265358979323846 * aspect_ratio / (2.0 + std::sqrt(aspect_ratio * aspect_ratio + 4.0));
  }
  // C_L and C_D at angle of attack alpha [rad].
  static void coefficients(const Runtime& runtime, double alpha, double* C_L, double* C_D);

  // Its YAML keys besides name and link, declared once (configs/REFERENCE.md shows them).
  static const config::KeyTable<Spec>& keys();
  static Runtime prepare(const Spec& spec, const ActuatorSetup& setup);
  static std::string check(const Spec& spec, const double* controls, std::size_t first);
  static void command(State& state, const double* controls);
  static void actuate(const Runtime& runtime, State& state);
  static void add_wrench(const Runtime& runtime, State& state, const ActuatorForceInput& in, StepWrench& out);
  // The non-finite policy: the fin stays where it is (at 0 if its angle is not finite), no force.
  static void stop(State& state);
  static bool is_finite(const State& state) { return std::isfinite(state.angle); }
};

}  // namespace hadal::physics
