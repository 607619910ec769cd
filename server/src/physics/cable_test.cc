// The lumped-mass cable alone, against closed forms: a vertical cable's top tension is its wet weight; a cable
// hung between two points settles to the catenary's sag; in a uniform current with normal drag only it settles at
// the angle where weight and drag balance across it; an axial step travels at sqrt(EA / m); without damping, drag
// or added mass a swinging cable keeps its energy; the sub-steps follow the stiffness. A winch ramps and stops
// exactly at its target, and a cable it pays out carries the wet weight of what is in the water.
#include "hadal/physics/cable.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace hadal::physics {
namespace {

constexpr double kDt = 0.002;  // 500 Hz, the default physics rate [s]

CableSpec steel_rope() {
  CableSpec spec;
  spec.length = 100.0;
  spec.segments = 20;
  spec.diameter = 0.03;
  spec.density = 3000.0;
  spec.axial_stiffness = 1.0e6;
  spec.damping_s = 0.01;
  return spec;
}

CableEnd held_at(const Eigen::Vector3d& p_W) { return {true, p_W, p_W}; }

// Wet weight per metre [N/m] in water of 1025 kg/m^3.
double wet_weight(const CableSpec& spec, double g = 9.80665) { return (spec.density - 1025.0) * spec.area() * g; }

// Hung from a fixed point, the cable settles (axial damping, drag) and pulls the point down with its whole wet
// weight: w L (1 % for the axial oscillation left after 60 s; it is ~1e-5).
TEST(CableTest, AVerticalCablesTopTensionIsItsWetWeight) {
  const CableSpec spec = steel_rope();
  const Eigen::Vector3d top(3.0, -2.0, -10.0);
  CableState state = straight_cable(spec, top, top - Eigen::Vector3d(0.0, 0.0, spec.length));
  const CableWorld world;
  CableStepResult result;
  for (int k = 0; k < 30000; ++k) result = step_cable(spec, world, held_at(top), CableEnd{}, kDt, state);
  const double weight = wet_weight(spec) * spec.length;
  EXPECT_NEAR(result.f_W_end0.z(), -weight, 0.01 * weight);
  EXPECT_NEAR(result.f_W_end0.head<2>().norm(), 0.0, 1e-9 * weight);
  EXPECT_TRUE(result.f_W_end1.isZero());
  // The tension falls linearly to the free end: the top segment's carries all but half a segment's weight.
  const std::vector<double> tensions = cable_tensions(spec, state);
  EXPECT_NEAR(tensions.front(), weight * (1.0 - 0.5 / spec.segments), 0.01 * weight);
  EXPECT_NEAR(tensions.back(), 0.5 * weight / spec.segments, 0.01 * weight);
  EXPECT_NEAR(state.p_W.back().x(), top.x(), 1e-9);
}

// 100 m of rope between two points 80 m apart at one height settles (drag damps the swing) in 120 s to the catenary:
// L = 2 a sinh(S / 2a), sag = a (cosh(S / 2a) - 1), within 1 % (the bound; 50 segments put the
// discretisation near 0.05 %, the stretch at ~1e-4).
TEST(CableTest, AHangingCableSettlesToTheCatenary) {
  CableSpec spec = steel_rope();
  spec.segments = 50;
  spec.axial_stiffness = 1.0e7;
  spec.damping_s = 1e-4;  // a little: a stiffer damper needs far smaller sub-steps (cable_substeps)
  const double span = 80.0;
  const Eigen::Vector3d a(-0.5 * span, 5.0, -100.0), b(0.5 * span, 5.0, -100.0);
  CableState state = straight_cable(spec, a, b);  // slack: it falls from the chord
  const CableWorld world;
  for (int k = 0; k < 60000; ++k) step_cable(spec, world, held_at(a), held_at(b), kDt, state);
  double lo = 1.0, hi = 1000.0;  // a: the catenary's parameter, where 2 a sinh(S / 2a) = L
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (2.0 * mid * std::sinh(span / (2.0 * mid)) > spec.length ? lo : hi) = mid;
  }
  const double sag = lo * (std::cosh(span / (2.0 * lo)) - 1.0);
  const Eigen::Vector3d& middle = state.p_W[static_cast<std::size_t>(spec.segments / 2)];
  EXPECT_NEAR(-100.0 - middle.z(), sag, 0.01 * sag) << "catenary parameter " << lo << " m";
  EXPECT_NEAR(middle.x(), 0.0, 1e-3);  // symmetric, but for what is left of the swing
  EXPECT_NEAR(middle.y(), 5.0, 1e-9);
  // What is left of the swing (quadratic drag damps it ever more slowly): centimetres a second, at the swing's
  // ~0.6 rad/s a few centimetres of the 24 m sag.
  EXPECT_LT(state.v_W[static_cast<std::size_t>(spec.segments / 2)].norm(), 0.05);
}

// Hung in a uniform current U = 1 m/s along +x with normal drag only (C_dt = 0), the cable settles straight at the angle
// theta from the vertical where its weight across it balances the drag on its normal flow:
//   w sin(theta) = 1/2 rho C_dn d (U cos(theta))^2,
// within 1 deg (the bound).
TEST(CableTest, InAUniformCurrentItSettlesAtTheDragAngle) {
  CableSpec spec = steel_rope();
  spec.length = 50.0;
  spec.tangential_drag_coefficient = 0.0;
  CableWorld world;
  world.current_W = Eigen::Vector3d(1.0, 0.0, 0.0);
  const Eigen::Vector3d top(0.0, 0.0, -10.0);
  CableState state = straight_cable(spec, top, top - Eigen::Vector3d(0.0, 0.0, spec.length));
  for (int k = 0; k < 60000; ++k) step_cable(spec, world, held_at(top), CableEnd{}, kDt, state);
  const double q = 0.5 * 1025.0 * spec.normal_drag_coefficient * spec.diameter * 1.0 / wet_weight(spec);
  // sin(theta) = q cos^2(theta) = q (1 - sin^2(theta)): the positive root.
  const double sin_theta = (-1.0 + std::sqrt(1.0 + 4.0 * q * q)) / (2.0 * q);
  const Eigen::Vector3d chord = state.p_W.back() - state.p_W.front();
  const double theta = std::atan2(chord.x(), -chord.z());
  EXPECT_NEAR(theta * 180.0 / std::numbers::pi, std::asin(sin_theta) * 180.0 / std::numbers::pi, 1.0);
  EXPECT_GT(theta, 0.1);  // it trails downstream (+x), by ~44 deg (the whole flow as normal drag: ~54 deg)
  EXPECT_NEAR(chord.y(), 0.0, 1e-9);
  // Straight: the middle node lies on the chord within a centimetre.
  const Eigen::Vector3d& middle = state.p_W[static_cast<std::size_t>(spec.segments / 2)];
  EXPECT_LT((middle - 0.5 * (state.p_W.front() + state.p_W.back())).norm(), 0.01 * spec.length);
}

// A taut, neutrally buoyant cable (no weight, drag or damping) pulled at one end at constant speed from t = 0:
// the strain front reaches the fixed end after L / c, c = sqrt(EA / m) (m per unstretched metre), where the
// tension there rises by v0 sqrt(EA m). The time its rise passes half way matches L / c within 2 % (the issue's
// bound; the chain's dispersion smears the front over a few segments of 100).
TEST(CableTest, AnAxialStepTravelsAtSqrtEaOverM) {
  CableSpec spec;
  spec.length = 1000.0;
  spec.segments = 100;
  spec.diameter = 0.02;
  spec.density = 1025.0;
  spec.axial_stiffness = 1.0e5;
  spec.normal_drag_coefficient = spec.tangential_drag_coefficient = spec.normal_added_mass_coefficient = 0.0;
  const double stretch = 1.001, v0 = 0.05;
  const Eigen::Vector3d a(0.0, 0.0, -50.0), b0 = a + Eigen::Vector3d(spec.length * stretch, 0.0, 0.0);
  CableState state = straight_cable(spec, a, b0);
  const CableWorld world;
  const double m = spec.mass_per_metre(), c = std::sqrt(spec.axial_stiffness / m);
  const double T0 = spec.axial_stiffness * (stretch - 1.0), jump = v0 * std::sqrt(spec.axial_stiffness * m);
  double t = 0.0, arrival = -1.0;
  while (t < 3.0 * spec.length / c && arrival < 0.0) {
    const Eigen::Vector3d b1 = b0 + Eigen::Vector3d(v0 * (t + kDt), 0.0, 0.0);
    const CableStepResult r = step_cable(spec, world, held_at(a), {true, b0 + Eigen::Vector3d(v0 * t, 0.0, 0.0), b1},
                                         kDt, state);
    t += kDt;
    if (r.f_W_end0.x() > T0 + 0.5 * jump) arrival = t;
  }
  ASSERT_GT(arrival, 0.0);
  EXPECT_NEAR(arrival, spec.length / c, 0.02 * spec.length / c) << "c = " << c << " m/s";
}

// Without damping, drag or added mass, a cable released 30 deg from the vertical swings under its wet weight and keeps
// its energy (kinetic + wet weight + elastic) within 1 % of what it has to swing with (its energy above the
// vertical rest) over 60 s: symplectic Euler oscillates about the energy, it does not drift.
TEST(CableTest, WithoutDampingOrDragASwingingCableKeepsItsEnergy) {
  CableSpec spec = steel_rope();
  spec.length = 20.0;
  spec.damping_s = 0.0;
  spec.normal_drag_coefficient = spec.tangential_drag_coefficient = spec.normal_added_mass_coefficient = 0.0;
  const Eigen::Vector3d top(0.0, 0.0, -30.0);
  const double start = 30.0 * std::numbers::pi / 180.0;  // from the vertical
  CableState state = straight_cable(spec, top,
                                    top + spec.length * Eigen::Vector3d(std::sin(start), 0.0, -std::cos(start)));
  const CableWorld world;
  const double e0 = cable_energy(spec, state, 1025.0, world.gravity_W);
  const double e_rest = cable_energy(spec, straight_cable(spec, top, top - Eigen::Vector3d(0.0, 0.0, spec.length)),
                                     1025.0, world.gravity_W);
  double worst = 0.0;
  for (int k = 0; k < 30000; ++k) {
    step_cable(spec, world, held_at(top), CableEnd{}, kDt, state);
    worst = std::max(worst, std::abs(cable_energy(spec, state, 1025.0, world.gravity_W) - e0));
  }
  EXPECT_LT(worst, 0.01 * (e0 - e_rest)) << "energy to swing with " << e0 - e_rest << " J";
  EXPECT_LT(state.p_W.back().x(), 0.0);  // it did swing through
}

// Bending: a 10 m beam (EI 100 N m^2, 0.63 kg/m) pinned at both ends at its length, in no gravity and no water, let go
// from its first mode's shape sin(pi x / L) with a 10 mm sag, swings at that mode's frequency
// omega_1 = (pi / L)^2 sqrt(EI / m) (Euler-Bernoulli; 5.05 s): the period within 1 % (40 segments put the lumped
// beam's error near 0.1 %; the stretch the sag needs, 2.5e-6, adds its tension's ~0.03 %). Its energy keeps within
// 1 % of the swing's.
TEST(CableTest, APinnedBeamSwingsAtItsFirstBendingFrequency) {
  CableSpec spec;
  spec.length = 10.0;
  spec.segments = 40;
  spec.diameter = 0.02;
  spec.density = 2000.0;
  spec.axial_stiffness = 1.0e4;
  spec.bending_stiffness = 100.0;
  const double m = spec.mass_per_metre(), sag = 0.01;
  CableState state = straight_cable(spec, Eigen::Vector3d::Zero(), Eigen::Vector3d(spec.length, 0.0, 0.0));
  for (std::size_t i = 0; i < state.p_W.size(); ++i) {
    state.p_W[i].z() = sag * std::sin(std::numbers::pi * state.p_W[i].x() / spec.length);
  }
  CableWorld world;
  world.water_density = 0.0;  // no buoyancy, drag or added mass
  world.gravity_W.setZero();
  const Eigen::Vector3d a = state.p_W.front(), b = state.p_W.back();
  const double e0 = cable_energy(spec, state, 0.0, world.gravity_W);
  const std::size_t middle = state.p_W.size() / 2;
  std::vector<double> crossings;  // downward zero crossings of the middle, interpolated [s]
  double previous = state.p_W[middle].z(), worst = 0.0;
  for (int k = 1; k <= 12000; ++k) {  // 24 s: four periods and more
    step_cable(spec, world, held_at(a), held_at(b), kDt, state);
    const double z = state.p_W[middle].z();
    if (previous > 0.0 && z <= 0.0) crossings.push_back((k - 1 + previous / (previous - z)) * kDt);
    previous = z;
    worst = std::max(worst, std::abs(cable_energy(spec, state, 0.0, world.gravity_W) - e0));
  }
  ASSERT_GE(crossings.size(), 4u);
  const double period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  const double omega1 = std::pow(std::numbers::pi / spec.length, 2) * std::sqrt(spec.bending_stiffness / m);
  EXPECT_NEAR(period, 2.0 * std::numbers::pi / omega1, 0.01 * 2.0 * std::numbers::pi / omega1);
  EXPECT_LT(worst, 0.01 * e0) << "bending energy " << e0 << " J";
  // It starts with its bending energy: EI pi^4 sag^2 / (4 L^3) for the sine (1 %: the discrete angles).
  EXPECT_NEAR(e0, spec.bending_stiffness * std::pow(std::numbers::pi, 4) * sag * sag / (4.0 * std::pow(spec.length, 3)),
              0.01 * e0);
  // A hundred times stiffer in bending, its zigzag mode (16 EI / m L0^3: 8 krad/s) is faster than its axial one: the
  // sub-steps follow it, and the swing keeps its energy over 2 s (sub-steps sized for the axial mode alone blow up).
  spec.bending_stiffness = 1.0e4;
  CableState stiff = straight_cable(spec, a, b);
  for (std::size_t i = 0; i < stiff.p_W.size(); ++i) {
    stiff.p_W[i].z() = sag * std::sin(std::numbers::pi * stiff.p_W[i].x() / spec.length);
  }
  const double e_stiff = cable_energy(spec, stiff, 0.0, world.gravity_W);
  for (int k = 0; k < 1000; ++k) step_cable(spec, world, held_at(a), held_at(b), kDt, stiff);
  EXPECT_NEAR(cable_energy(spec, stiff, 0.0, world.gravity_W), e_stiff, 0.01 * e_stiff);
}

// A cable does not push: held with its ends closer than its length (here neutrally buoyant, so nothing pulls it
// taut), it puts no force on what holds it.
TEST(CableTest, ASlackCablePushesNothing) {
  CableSpec spec = steel_rope();
  spec.density = 1025.0;
  const Eigen::Vector3d a(0.0, 0.0, -50.0), b(50.0, 0.0, -50.0);
  CableState state = straight_cable(spec, a, b);  // 100 m over 50 m: every segment at half its length
  const CableWorld world;
  CableStepResult result;
  for (int k = 0; k < 500; ++k) result = step_cable(spec, world, held_at(a), held_at(b), kDt, state);
  EXPECT_LT(result.f_W_end0.norm(), 1e-9);
  EXPECT_LT(result.f_W_end1.norm(), 1e-9);
  for (const double tension : cable_tensions(spec, state)) EXPECT_EQ(tension, 0.0);
}

// The sub-steps follow the stiffest mode (omega h <= 0.5): 2 ms needs 2 for EA = 1e6 N on 5 m segments of
// 2.1 kg/m (omega = 275 rad/s), 4x more for 16x the stiffness; damping needs more; a soft cable takes the step
// whole.
TEST(CableTest, SubstepsFollowTheStiffness) {
  CableSpec spec = steel_rope();
  spec.damping_s = 0.0;
  const int base = cable_substeps(spec, kDt);
  const double omega = 2.0 * std::sqrt(spec.axial_stiffness / (spec.rest_segment() * spec.mass_per_metre() * spec.rest_segment()));
  EXPECT_EQ(base, static_cast<int>(std::ceil(kDt * omega / 0.5)));
  EXPECT_EQ(base, 2);
  spec.axial_stiffness *= 16.0;
  EXPECT_EQ(cable_substeps(spec, kDt), static_cast<int>(std::ceil(kDt * 4.0 * omega / 0.5)));  // 5
  spec.damping_s = 0.01;
  EXPECT_GT(cable_substeps(spec, kDt), 10);
  spec.axial_stiffness = 10.0;
  spec.damping_s = 0.0;
  EXPECT_EQ(cable_substeps(spec, kDt), 1);
}

// The winch alone: its line speed ramps at max_acceleration to the command, then brakes so that it stops exactly at
// the target (v^2 = 2 a d); told on without a target it stops at the drum's end or at min_length, saying so.
TEST(WinchTest, ItRampsToItsSpeedAndStopsExactlyAtItsTarget) {
  const WinchSpec winch{200.0, 5.0, 1.0, 0.5};  // drum_length, min_length, max_speed, max_acceleration
  CableState state;
  state.length = 50.0;
  state.winch.command_speed = 0.8;
  state.winch.target_length = 60.0;
  double t = 0.0, arrived = -1.0, fastest = 0.0, harshest = 0.0;
  for (int k = 0; k < 10000 && arrived < 0.0; ++k) {
    const double v0 = state.winch.speed;
    state.length += advance_winch(winch, kDt, state) * kDt;
    harshest = std::max(harshest, std::abs(state.winch.speed - v0) / kDt);
    t += kDt;
    fastest = std::max(fastest, state.winch.speed);
    EXPECT_LE(state.length, 60.0);
    if (std::abs(t - 1.6) < 0.5 * kDt) {
      EXPECT_NEAR(state.winch.speed, 0.8, 1e-9);  // 0.8 m/s after 0.8 / 0.5 s
    }
    if (state.winch.speed == 0.0 && state.length == 60.0) arrived = t;
  }
  EXPECT_EQ(state.length, 60.0);
  EXPECT_NEAR(fastest, 0.8, 1e-12);
  // Up in 1.6 s over 0.64 m, down the same, 8.72 m at 0.8 m/s between: 14.1 s (within a step), never changing its
  // speed faster than max_acceleration, also in the last step.
  EXPECT_NEAR(arrived, 14.1, kDt);
  EXPECT_LE(harshest, 0.5 + 1e-9);
  EXPECT_FALSE(state.winch.at_limit);
  // A target behind it: it runs back at |speed|.
  state.winch.target_length = 55.0;
  for (int k = 0; k < 10000; ++k) state.length += advance_winch(winch, kDt, state) * kDt;
  EXPECT_EQ(state.length, 55.0);
  // Hauling in without a target stops at min_length; paying out at the drum's end.
  state.winch = WinchState{0.0, -1.0, 0.0, false};
  for (int k = 0; k < 60000; ++k) state.length += advance_winch(winch, kDt, state) * kDt;
  EXPECT_EQ(state.length, 5.0);
  EXPECT_EQ(state.winch.speed, 0.0);
  EXPECT_TRUE(state.winch.at_limit);
  state.winch.command_speed = 1.0;
  for (int k = 0; k < 120000; ++k) state.length += advance_winch(winch, kDt, state) * kDt;
  EXPECT_EQ(state.length, 200.0);
  EXPECT_TRUE(state.winch.at_limit);
}

TEST(WinchTest, CommandsBeyondItsLimitsAreRefusedNamingTheKey) {
  const WinchSpec winch{300.0, 2.0, 1.5, 0.5};
  EXPECT_EQ(check_winch_command(winch, -1.5, 0.0), "");
  EXPECT_EQ(check_winch_command(winch, 1.0, 300.0), "");
  EXPECT_EQ(check_winch_command(winch, 1.6, 0.0), "speed 1.6 m/s is beyond the winch's max_speed (1.5 m/s)");
  EXPECT_EQ(check_winch_command(winch, 1.0, 350.0), "target_length 350 m is beyond the drum (drum_length 300 m)");
  EXPECT_EQ(check_winch_command(winch, 1.0, 1.0), "target_length 1 m is below the winch's min_length (2 m)");
  EXPECT_EQ(check_winch_command(winch, 1.0, -3.0), "target_length -3 m is negative (0: no target)");
  EXPECT_EQ(check_winch_command(winch, std::nan(""), 0.0), "speed is not finite");
  EXPECT_EQ(check_winch_command(winch, 0.0, std::numeric_limits<double>::infinity()), "target_length is not finite");
}

// A vertical rope on a fixed winch, paid out from 20 m to 40 m at 0.5 m/s: while it goes out slowly the top
// tension is the wet weight of what is in the water, w L(t) (2 %: what is left of the start), and the free end
// hangs L(t) and the stretch w L^2 / 2 EA (3-11 mm) below the winch (2 mm): the axial damping (a stiff 0.05 s here)
// must not take the payout for a stretch rate, which would shorten the stretch by damping_s x the payout speed,
// 25 mm. Once it has stopped and settled: 40 m and the stretch (5 mm), the top tension w L (1 %).
TEST(WinchTest, PayingOutLowersTheEndAndTheTopTensionFollowsTheLength) {
  CableSpec spec = steel_rope();
  spec.length = 20.0;
  spec.damping_s = 0.05;
  const WinchSpec winch{100.0, 1.0, 1.0, 0.5};
  const Eigen::Vector3d top(1.0, 2.0, -5.0);
  CableState state = straight_cable(spec, top, top - Eigen::Vector3d(0.0, 0.0, spec.length));
  const CableWorld world;
  CableStepResult result;
  for (int k = 0; k < 10000; ++k) result = step_cable(spec, world, held_at(top), CableEnd{}, kDt, state);  // settle
  state.winch.command_speed = 0.5;
  state.winch.target_length = 40.0;
  const double w = wet_weight(spec);
  int checked = 0;
  for (int k = 0; k < 30000; ++k) {
    const double rate = advance_winch(winch, kDt, state);
    result = step_cable(spec, world, held_at(top), CableEnd{}, kDt, state, rate);
    if (state.length > 25.0 && state.length < 38.0 && k % 500 == 0) {
      EXPECT_NEAR(-result.f_W_end0.z(), w * state.length, 0.02 * w * state.length) << "at " << state.length << " m";
      const double stretch = w * state.length * state.length / (2.0 * spec.axial_stiffness);
      EXPECT_NEAR(state.p_W.back().z(), top.z() - state.length - stretch, 0.002) << "at " << state.length << " m";
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
  EXPECT_EQ(state.length, 40.0);
  EXPECT_NEAR(-result.f_W_end0.z(), w * 40.0, 0.01 * w * 40.0);
  const double stretch = w * 40.0 * 40.0 / (2.0 * spec.axial_stiffness);
  EXPECT_NEAR(state.p_W.back().z(), top.z() - 40.0 - stretch, 0.005) << "stretch " << stretch << " m";
  EXPECT_NEAR(state.p_W.back().x(), top.x(), 1e-9);
}


}  // namespace
}  // namespace hadal::physics
