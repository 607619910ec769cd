// Fin: the servo's rate limit, lift and drag against the finite-wing closed forms (Helmbold's slope,
// induced drag), the flat plate past stall, Galilean invariance against a current, nothing in air.
#include "hadal/physics/fin.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hadal/core/model.h"
#include "hadal/core/units.h"
#include "hadal/physics/ocean.h"

namespace hadal::physics {
namespace {

constexpr double kDt = 0.01;

// An elevator: hinge along y, chord along x, 0.02 m^2, effective aspect ratio 2.
FinActuator::Spec elevator() {
  FinActuator::Spec spec;
  spec.p_LF = Eigen::Vector3d(-0.6, 0.1, 0.0);
  spec.hinge_axis_L = Eigen::Vector3d::UnitY();
  spec.chord_L = Eigen::Vector3d::UnitX();
  spec.area = 0.02;
  spec.aspect_ratio = 2.0;
  spec.max_angle = 25.0 * kDegToRad;
  spec.max_rate = 60.0 * kDegToRad;
  spec.lift_slope = FinActuator::helmbold_lift_slope(2.0);
  spec.stall_angle = 20.0 * kDegToRad;
  return spec;
}

struct Wrench {
  FinActuator::State state;
  StepWrench out;
};

// The fin's wrench with B at the origin (attitude R_WB, identity by default) moving at v_WB and turning at
// w_WB, at 50 m depth.
Wrench fin_wrench(const FinActuator::Spec& spec, double angle, const Eigen::Vector3d& v_WB, const Ocean& ocean,
                  double z = -50.0, const Eigen::Vector3d& w_WB = Eigen::Vector3d::Zero(),
                  const Eigen::Matrix3d& R_WB = Eigen::Matrix3d::Identity(),
                  const Eigen::Isometry3d& X_BL = Eigen::Isometry3d::Identity()) {
  const FinActuator::Runtime runtime = FinActuator::prepare(spec, ActuatorSetup{X_BL, 1025.0, kDt, 0});
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.linear() = R_WB;
  X_WB.translation() = Eigen::Vector3d(0.0, 0.0, z);
  const Eigen::Vector3d p_WBcm = X_WB.translation();
  Wrench w;
  w.state.angle = angle;
  ActuatorForceInput in{X_WB, p_WBcm, 0.0};
  in.v_WB = v_WB;
  in.w_WB = w_WB;
  in.ocean = &ocean;
  FinActuator::add_wrench(runtime, w.state, in, w.out);
  return w;
}

TEST(Fin, HelmboldLiftSlope) {
  // 2 pi AR / (2 + sqrt(AR^2 + 4)): AR 2 -> 4 pi / (2 + 2 sqrt 2); large AR -> 2 pi; AR -> 0: pi AR / 2.
  EXPECT_NEAR(FinActuator::helmbold_lift_slope(2.0), 4.0 * kPi / (2.0 + 2.0 * std::sqrt(2.0)), 1e-12);
  EXPECT_NEAR(FinActuator::helmbold_lift_slope(1e4) / (2.0 * kPi), 1.0, 1e-3);
  EXPECT_NEAR(FinActuator::helmbold_lift_slope(1e-4) / (kPi * 1e-4 / 2.0), 1.0, 1e-3);
}

// The servo turns at its rate to the commanded angle and stops there.
TEST(Fin, ServoTurnsAtItsRate) {
  const FinActuator::Spec spec = elevator();
  const Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  const FinActuator::Runtime runtime = FinActuator::prepare(spec, ActuatorSetup{X_BL, 1025.0, kDt, 0});
  FinActuator::State state;
  const double setpoint = 0.8;  // 20 deg: 1/3 s at 60 deg/s
  FinActuator::command(state, &setpoint);
  for (int k = 1; k <= 50; ++k) {
    FinActuator::actuate(runtime, state);
    ASSERT_NEAR(state.angle, std::min(k * 0.6, 20.0) * kDegToRad, 1e-12) << k;
  }
  EXPECT_EQ(FinActuator::check(spec, &setpoint, 3), "");
  const double bad = 1.2;
  EXPECT_EQ(FinActuator::check(spec, &bad, 3), "setpoint[3] = 1.2 is outside [-1, 1]");
}

// Moving forward at 1.5 m/s with the fin turned 6 deg (leading edge down, the right-hand turn about +y):
// the water meets it at alpha = 6 deg from above, lift L = q S C_La alpha down and drag
// D = q S (C_D0 + C_L^2 / (pi e AR)) aft, at the centre of pressure.
TEST(Fin, LiftAndDragOfAFiniteWing) {
  const WorldSpec world;
  const Ocean ocean(world);
  const FinActuator::Spec spec = elevator();
  const double delta = 6.0 * kDegToRad, U = 1.5;
  const Wrench w = fin_wrench(spec, delta, Eigen::Vector3d(U, 0, 0), ocean);
  const double rho = ocean.density(50.0);
  const double qS = 0.5 * rho * U * U * spec.area;
  const double C_L = spec.lift_slope * delta;
  const double C_D = 0.01 + C_L * C_L / (kPi * 0.9 * 2.0);
  EXPECT_NEAR(w.state.attack_angle, delta, 1e-12);
  EXPECT_NEAR(w.state.lift_N, qS * C_L, 1e-9);
  EXPECT_NEAR(w.state.drag_N, qS * C_D, 1e-9);
  EXPECT_NEAR(w.out.f_W.x(), -qS * C_D, 1e-9);
  EXPECT_NEAR(w.out.f_W.y(), 0.0, 1e-12);
  EXPECT_NEAR(w.out.f_W.z(), -qS * C_L, 1e-9);
  // About the centre of mass at B's origin: r = (-0.6, 0.1, 0) x f.
  EXPECT_TRUE(w.out.tau_W.isApprox(Eigen::Vector3d(-0.6, 0.1, 0.0).cross(w.out.f_W), 1e-12));
  // The tail pushed down pitches the nose up: with y to the left, a negative moment about y.
  EXPECT_LT(w.out.tau_W.y(), 0.0);
}

// A pitch rate moves the tail through the water: with the fin at 0 deg, moving forward at 1.5 m/s and pitching
// nose down at q = 0.25 rad/s, the fin (0.6 m aft) rises at q x 0.6 = 0.15 m/s, so the water meets it from
// above at alpha = atan(0.15 / 1.5) = atan(0.1): lift q S C_La alpha perpendicular to the flow, down (and a
// little forward), drag along it, with q = rho (1.5^2 + 0.15^2) / 2. The moment opposes the pitch rate
// (tau_y < 0 for q > 0): the fin damps pitch.
TEST(Fin, PitchRateGivesTheFinAnAngleOfAttackThatDampsIt) {
  const WorldSpec world;
  const Ocean ocean(world);
  const FinActuator::Spec spec = elevator();
  const double U = 1.5, q = 0.25, w_up = q * 0.6;
  const Wrench w = fin_wrench(spec, 0.0, Eigen::Vector3d(U, 0, 0), ocean, -50.0, Eigen::Vector3d(0.0, q, 0.0));
  const double alpha = std::atan(w_up / U);
  const double speed2 = U * U + w_up * w_up, n = std::sqrt(speed2);
  const double qS = 0.5 * ocean.density(50.0) * speed2 * spec.area;
  const double C_L = spec.lift_slope * alpha, C_D = 0.01 + C_L * C_L / (kPi * 0.9 * 2.0);
  EXPECT_NEAR(w.state.attack_angle, alpha, 1e-12);
  EXPECT_NEAR(w.state.lift_N, qS * C_L, 1e-9);
  const Eigen::Vector3d lift_dir(w_up / n, 0.0, -U / n), drag_dir(-U / n, 0.0, -w_up / n);
  const Eigen::Vector3d f = qS * C_L * lift_dir + qS * C_D * drag_dir;
  EXPECT_NEAR((w.out.f_W - f).norm(), 0.0, 1e-9);
  EXPECT_NEAR((w.out.tau_W - Eigen::Vector3d(-0.6, 0.1, 0.0).cross(f)).norm(), 0.0, 1e-9);
  EXPECT_LT(w.out.tau_W.y(), -0.5 * 0.6 * qS * C_L);
}

// The same fin on a vehicle yawed 90 deg (nose to W's +y) moving along W's +y: the wrench of
// LiftAndDragOfAFiniteWing turned by the yaw, force and moment, the same lift and drag (the fin's axes are
// taken into W with R_WB, not its transpose: with that, hinge and chord point the other way).
TEST(Fin, AYawedVehicleGetsTheSameWrenchTurned) {
  const WorldSpec world;
  const Ocean ocean(world);
  const FinActuator::Spec spec = elevator();
  const double delta = 6.0 * kDegToRad, U = 1.5;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.5 * kPi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Wrench ahead = fin_wrench(spec, delta, Eigen::Vector3d(U, 0, 0), ocean);
  const Wrench yawed = fin_wrench(spec, delta, R * Eigen::Vector3d(U, 0, 0), ocean, -50.0, Eigen::Vector3d::Zero(), R);
  EXPECT_NEAR(yawed.state.attack_angle, delta, 1e-12);
  EXPECT_NEAR(yawed.state.lift_N, ahead.state.lift_N, 1e-9);
  EXPECT_NEAR(yawed.state.drag_N, ahead.state.drag_N, 1e-9);
  EXPECT_NEAR((yawed.out.f_W - R * ahead.out.f_W).norm(), 0.0, 1e-9);
  EXPECT_NEAR((yawed.out.tau_W - R * ahead.out.tau_W).norm(), 0.0, 1e-9);
  EXPECT_GT(ahead.out.f_W.norm(), 1.0);  // not a comparison of zeros
}

// A fin on a link: its spec in L, the link at X_BL (turned 90 deg about x_B and offset), acts as the same fin
// given in B (position X_BL p_LF, hinge and chord R_BL times theirs) on the body itself.
TEST(Fin, AFinOnALinkActsAsItsSpecTakenIntoB) {
  const WorldSpec world;
  const Ocean ocean(world);
  Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  X_BL.linear() = Eigen::AngleAxisd(0.5 * kPi, Eigen::Vector3d::UnitX()).toRotationMatrix();
  X_BL.translation() = Eigen::Vector3d(-0.2, 0.05, 0.1);
  const FinActuator::Spec on_link = elevator();  // hinge along y_L: a rudder once the link is turned
  FinActuator::Spec in_B = on_link;
  in_B.p_LF = X_BL * on_link.p_LF;
  in_B.hinge_axis_L = X_BL.linear() * on_link.hinge_axis_L;
  in_B.chord_L = X_BL.linear() * on_link.chord_L;
  const double delta = 6.0 * kDegToRad;
  const Eigen::Vector3d v(1.5, 0.0, 0.0), w(0.0, 0.0, 0.3);  // a yaw rate: the fin's lever arm counts
  const Wrench linked = fin_wrench(on_link, delta, v, ocean, -50.0, w, Eigen::Matrix3d::Identity(), X_BL);
  const Wrench direct = fin_wrench(in_B, delta, v, ocean, -50.0, w);
  EXPECT_GT(direct.out.f_W.norm(), 1.0);
  EXPECT_GT(std::abs(direct.out.f_W.y()), 0.5 * direct.state.lift_N);  // a rudder: its lift is sideways
  EXPECT_NEAR((linked.out.f_W - direct.out.f_W).norm(), 0.0, 1e-9);
  EXPECT_NEAR((linked.out.tau_W - direct.out.tau_W).norm(), 0.0, 1e-9);
}

// Past the stall angle: the lift falls off as sin 2 alpha from its value at the stall (zero broadside),
// the drag rises toward the flat plate's 1.2 broadside; both continuous at alpha_s.
TEST(Fin, StalledFinFallsOffContinuously) {
  const WorldSpec world;
  const Ocean ocean(world);
  const FinActuator::Spec spec = elevator();  // stall at 20 deg
  const double U = 1.0, a_s = spec.stall_angle;
  const double qS = 0.5 * ocean.density(50.0) * U * U * spec.area;
  const double C_L_s = spec.lift_slope * a_s;
  const double C_D_s = 0.01 + C_L_s * C_L_s / (kPi * 0.9 * 2.0);
  const double delta = 35.0 * kDegToRad;
  const Wrench w = fin_wrench(spec, delta, Eigen::Vector3d(U, 0, 0), ocean);
  EXPECT_NEAR(w.state.lift_N, qS * C_L_s * std::sin(2 * delta) / std::sin(2 * a_s), 1e-9);
  EXPECT_NEAR(w.state.drag_N, qS * (C_D_s + 1.2 * (std::pow(std::sin(delta), 2) - std::pow(std::sin(a_s), 2))), 1e-9);
  // Continuous at the stall angle: just below and just above agree to first order in the step.
  const Wrench below = fin_wrench(spec, a_s - 1e-7, Eigen::Vector3d(U, 0, 0), ocean);
  const Wrench above = fin_wrench(spec, a_s + 1e-7, Eigen::Vector3d(U, 0, 0), ocean);
  EXPECT_NEAR(below.state.lift_N, above.state.lift_N, 1e-5);
  EXPECT_NEAR(below.state.drag_N, above.state.drag_N, 1e-5);
  // Broadside: no lift, the drag near a flat plate's.
  const Wrench broadside = fin_wrench(spec, 0.5 * kPi, Eigen::Vector3d(U, 0, 0), ocean);
  EXPECT_NEAR(broadside.state.lift_N, 0.0, 1e-9);
  EXPECT_NEAR(broadside.state.drag_N / qS, C_D_s + 1.2 * std::pow(std::cos(a_s), 2), 1e-9);
  // Turned the other way (-35 deg), stalled too: the same drag, the opposite lift (a stall test on alpha
  // rather than |alpha| would take -35 deg for attached flow: |C_L| = C_La 35 deg, not the fall-off above).
  const Wrench negative = fin_wrench(spec, -delta, Eigen::Vector3d(U, 0, 0), ocean);
  EXPECT_NEAR(negative.state.attack_angle, -delta, 1e-12);
  EXPECT_NEAR(negative.state.lift_N, -w.state.lift_N, 1e-9);
  EXPECT_NEAR(negative.state.drag_N, w.state.drag_N, 1e-9);
}

// Only the water's velocity relative to the fin counts: moving at v through still water equals resting
// in a current of -v; flow along the span (the hinge axis) makes no force.
TEST(Fin, RelativeFlowOnly) {
  const FinActuator::Spec spec = elevator();
  const WorldSpec still;
  const Ocean still_ocean(still);
  WorldSpec flowing;
  flowing.water.current.uniform_W = Eigen::Vector3d(-1.2, 0.0, 0.3);
  const Ocean current_ocean(flowing);
  const Wrench moving = fin_wrench(spec, 0.1, Eigen::Vector3d(1.2, 0.0, -0.3), still_ocean);
  const Wrench drifting = fin_wrench(spec, 0.1, Eigen::Vector3d::Zero(), current_ocean);
  EXPECT_TRUE(moving.out.f_W.isApprox(drifting.out.f_W, 1e-12));
  EXPECT_GT(moving.out.f_W.norm(), 1.0);
  const Wrench spanwise = fin_wrench(spec, 0.1, Eigen::Vector3d(0.0, 2.0, 0.0), still_ocean);
  EXPECT_EQ(spanwise.out.f_W.norm(), 0.0);
}

TEST(Fin, NothingInAir) {
  const WorldSpec world;
  const Ocean ocean(world);
  const Wrench w = fin_wrench(elevator(), 0.1, Eigen::Vector3d(2.0, 0, 0), ocean, /*z=*/1.0);
  EXPECT_EQ(w.out.f_W.norm(), 0.0);
  EXPECT_EQ(w.state.lift_N, 0.0);
}

}  // namespace
}  // namespace hadal::physics
