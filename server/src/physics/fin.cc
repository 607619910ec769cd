#include "hadal/physics/fin.h"

#include <algorithm>
#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/core/units.h"
#include "hadal/physics/ocean.h"

namespace hadal::physics {

using config::Range;

const config::KeyTable<FinActuator::Spec>& FinActuator::keys() {
  return config::declare_keys<Spec>([](config::KeyTable<Spec>& t) {
    t.describe("fin", "a servo-driven lifting surface (rudder, elevator) and its hydrodynamics");
    t.vector("position", &Spec::p_LF).required().unit("m").doc("p_LF, the fin's centre of pressure in L");
    t.direction("hinge_axis", &Spec::hinge_axis_L).required()
        .doc("the servo's axis (the span) in L; a positive deflection turns the chord about it by the right-hand rule");
    t.direction("chord_direction", &Spec::chord_L)
        .doc("perpendicular to hinge_axis; trailing to leading edge at zero deflection, in L");
    t.number("area", &Spec::area).required().unit("m²").range(Range::left_open(0.0, 1e3)).doc("S");
    t.number("aspect_ratio", &Spec::aspect_ratio).required().range(Range::left_open(0.0, 100.0))
        .doc("effective AR (a fin on a hull: twice its span over its chord)");
    t.number("max_angle_deg", &Spec::max_angle).degrees().range(Range::left_open(0.0, 90.0))
        .doc("setpoint +-1 commands +- this");
    t.number("max_rate_deg_per_s", &Spec::max_rate)
        .convert([](double deg_s) { return deg_s * kDegToRad; }, [](double rad_s) { return to_degrees(rad_s); }, "deg/s")
        .range(Range::left_open(0.0, 1e4)).doc("the servo's slew rate");
    t.number("lift_slope", &Spec::lift_slope).unit("1/rad").range(Range::left_open(0.0, 20.0))
        .default_text("Helmbold's 2 pi AR / (2 + sqrt(AR² + 4))").doc("C_L_alpha");
    t.number("stall_angle_deg", &Spec::stall_angle).degrees().range(Range::left_open(0.0, 60.0))
        .doc("alpha_s (low-aspect-ratio fins stall late: ~30° below AR 2); a max_angle_deg beyond it is a warning");
    t.number("drag_coefficient", &Spec::drag_coefficient).range(Range::closed(0.0, 10.0)).doc("C_D0");
    t.number("oswald_efficiency", &Spec::oswald_efficiency).range(Range::left_open(0.0, 1.0)).doc("e");
    t.check([](const config::KeyReads& reads, Spec& spec, config::NoContext&) {
      bool ok = true;
      if (reads.ok("hinge_axis") && reads.ok("chord_direction") && std::abs(spec.hinge_axis_L.dot(spec.chord_L)) > 1e-6) {
        reads.error_at_key(reads.has("chord_direction") ? "chord_direction" : "hinge_axis",
                           "the chord direction must be perpendicular to the hinge axis (their angle is " +
                               config::format_approximate(
                                   to_degrees(std::acos(std::clamp(spec.hinge_axis_L.dot(spec.chord_L), -1.0, 1.0)))) +
                               " deg)");
        ok = false;
      }
      if (!reads.has("lift_slope")) spec.lift_slope = helmbold_lift_slope(spec.aspect_ratio);
      if (spec.max_angle > spec.stall_angle + 1e-12) {
        reads.map().value().warn("max_angle_deg " + config::format_approximate(to_degrees(spec.max_angle)) +
                                 " is beyond stall_angle_deg " + config::format_approximate(to_degrees(spec.stall_angle)) +
                                 ": full deflection stalls the fin and gives less lift than a smaller one");
      }
      return ok;
    });
  });
}
FinActuator::Runtime FinActuator::prepare(const Spec& spec, const ActuatorSetup& setup) {
  Runtime r;
  r.p_BF = setup.X_BL * spec.p_LF;
  r.a_B = (setup.X_BL.linear() * spec.hinge_axis_L).normalized();
  r.c0_B = (setup.X_BL.linear() * spec.chord_L).normalized();
  r.area = spec.area;
  r.aspect_ratio = spec.aspect_ratio;
  r.max_angle = spec.max_angle;
  r.max_step = spec.max_rate * setup.step_size;
  r.lift_slope = spec.lift_slope;
  r.stall_angle = spec.stall_angle;
  r.drag_coefficient = spec.drag_coefficient;
  r.oswald_efficiency = spec.oswald_efficiency;
  return r;
}

std::string FinActuator::check(const Spec&, const double* controls, std::size_t first) {
  return check_normalised_setpoint(controls[0], first);
}

void FinActuator::command(State& state, const double* controls) { state.setpoint = held_setpoint(controls[0]); }

void FinActuator::actuate(const Runtime& r, State& state) {
  const double target = state.setpoint * r.max_angle;
  state.angle += std::clamp(target - state.angle, -r.max_step, r.max_step);
}

void FinActuator::coefficients(const Runtime& r, double alpha, double* C_L, double* C_D) {
  if (std::abs(alpha) <= r.stall_angle) {
    *C_L = r.lift_slope * alpha;
    *C_D = r.drag_coefficient + *C_L * *C_L / (kPi * r.oswald_efficiency * r.aspect_ratio);
  } else {
    const double a_s = r.stall_angle;
    const double C_L_s = r.lift_slope * a_s;
    const double C_D_s = r.drag_coefficient + C_L_s * C_L_s / (kPi * r.oswald_efficiency * r.aspect_ratio);
    const double s = std::sin(alpha), s_s = std::sin(a_s);
    *C_L = C_L_s * std::sin(2.0 * alpha) / std::sin(2.0 * a_s);
    *C_D = C_D_s + kBroadsideNormalForce * (s * s - s_s * s_s);
  }
}

void FinActuator::add_wrench(const Runtime& r, State& state, const ActuatorForceInput& in, StepWrench& out) {
  state.attack_angle = 0.0;
  state.lift_N = 0.0;
  state.drag_N = 0.0;
  const Eigen::Vector3d p_WF = in.X_WB * r.p_BF;
  if (in.ocean == nullptr || p_WF.z() >= in.surface_z) return;  // in air
  const Eigen::Matrix3d& R_WB = in.X_WB.linear();
  const Eigen::Vector3d a_W = R_WB * r.a_B;
  const Eigen::Vector3d c0_W = R_WB * r.c0_B;
  const Eigen::Vector3d c_W = c0_W * std::cos(state.angle) + a_W.cross(c0_W) * std::sin(state.angle);
  const Eigen::Vector3d n_W = a_W.cross(c_W);
  const Eigen::Vector3d v_WF = in.v_WB + in.w_WB.cross(p_WF - in.X_WB.translation());
  const Eigen::Vector3d U_W = in.ocean->current_W(p_WF, in.time) - v_WF;
  const Eigen::Vector3d U_p = U_W - U_W.dot(a_W) * a_W;
  const double speed = U_p.norm();
  if (speed < 1e-9) return;
  const Eigen::Vector3d e_W = U_p / speed;
  const double alpha = std::atan2(e_W.dot(n_W), -e_W.dot(c_W));
  double C_L = 0.0, C_D = 0.0;
  coefficients(r, alpha, &C_L, &C_D);
  const double qS = 0.5 * in.ocean->density(in.ocean->depth(p_WF.z())) * speed * speed * r.area;
  const Eigen::Vector3d f_W = qS * (C_L * e_W.cross(a_W) + C_D * e_W);
  state.attack_angle = alpha;
  state.lift_N = qS * C_L;
  state.drag_N = qS * C_D;
  out.f_W += f_W;
  out.tau_W += (p_WF - in.p_WBcm).cross(f_W);
}

void FinActuator::stop(State& state) {
  if (!std::isfinite(state.angle)) state.angle = 0.0;
  state.attack_angle = 0.0;
  state.lift_N = 0.0;
  state.drag_N = 0.0;
}

}  // namespace hadal::physics
