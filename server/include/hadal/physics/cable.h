// A cable in the water -- a tether, umbilical, lift line or tow cable -- as a lumped-mass chain
// (docs/ARCHITECTURE.md, "Cables").
//
// N segments of rest length L0 = length / N join N + 1 nodes p_i (W, m). A segment s from node a to node b,
// l = |p_b - p_a|, unit tangent t = (p_b - p_a) / l, carries the axial tension (Kelvin–Voigt, tension only: a
// cable does not push)
//   T = max(0, EA (l - L0) / L0 + EA damping_s (dl/dt) / L0)            [N]
// and the distributed loads over it, half to each of its nodes:
//   wet weight      (rho_c - rho_w) A L0 g                               A = pi d^2 / 4, rho_w at the node's depth
//   normal drag     -1/2 rho_w C_dn d L0 |v_n| v_n                       v_n, v_t: the segment's mid velocity
//   tangential drag -1/2 rho_w C_dt pi d L0 |v_t| v_t                    relative to the current, across and along t
// Bending (EI > 0): at each interior node i the two segments meeting there, unit tangents t_a and t_b, store
//   E_i = (EI / L0) (1 - t_a . t_b)            (= EI theta^2 / 2 L0 at small angles: a beam's EI kappa^2 / 2 over L0)
// and push their three nodes with -dE_i/dp (a conservative force: the swing keeps its energy with it). The ends are
// pinned (no moment where the cable is held or free).
// Each node has the mass m = rho_c A L0 (half at the ends) and, across its tangent, the added mass
// m_a = C_an rho_w A L0: the node's acceleration is
//   a = (I - t t^T) f / (m + m_a) + t t^T f / m.
// Seabed: a node less than d/2 above it is pushed out by a penalty spring (seabed_stiffness per metre of cable,
// critically damped for the node) and slowed along it by Coulomb friction (friction x the normal force,
// regularised below 1 cm/s).
//
// Integration: velocity Verlet (kick, drift, kick; symplectic and second order; the damping and drag at the
// half-kicked velocities), in as many equal sub-steps h of the physics step as the stiffest segment needs:
// h <= 1/4 of the stability limit 2 / omega (sqrt(1 + zeta^2) - zeta) of a chain's highest axial mode,
// omega = 2 sqrt(EA / (L0 m)), zeta = omega damping_s / 2, i.e. omega h <= 0.5 undamped; with bending, omega^2 also
// has the zigzag mode's 16 EI / (m L0^3) added (each node between neighbours displaced the other way: a joint angle
// of 4 delta / L0). At omega h near 1 the
// energy of a swinging cable drifts (resonance between its swing and its axial modes: +37 J of 366 J over 60 s at
// 0.92, seen here); at 0.5 it stays within 0.05 J. So the cable is stable at its physical stiffness at any physics
// rate and keeps the energy of an undamped, drag-free swing. Stiff damping costs sub-steps: a Kelvin–Voigt time
// constant near 1 / omega or above multiplies them.
// The ocean's density and current are sampled at each node once per physics step.
//
// Length: the cable's unstretched length in the water is state (CableState::length), the spec's at the start; a
// winch at an end pays it out or hauls it in at a rate, and the N segments share it evenly (L0 = length / N: the
// variable-length lumped-mass line of MoorDyn, docs/ARCHITECTURE.md "Cables"), so the node masses, stiffness EA / L0
// and drag lengths follow it within the step, the damping taking the rest-length rate out of the strain rate.
// The state's size stays N + 1 nodes; the sub-steps are sized for the shortest length over the step.
//
// Ends: each end node is free, or held (a fixed point, or a point on a body): a held node follows the holder's
// position, linearly over the step, and the cable pulls the holder with the force it puts on that node (the end
// segment's tension along it plus the node's share of the loads), averaged over the sub-steps.
// Deliberately left out (for now): a bending moment at the ends (clamped ends), torsion, the added mass along the
// cable, vortex-induced vibration, contact with bodies.
#pragma once

#include <Eigen/Core>

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hadal/config/key_table_fwd.h"

namespace hadal::physics {

class Ocean;

struct CableSpec {
  double length = 100.0;                  // unstretched [m]
  int segments = 20;
  double diameter = 0.02;                 // [m]
  double density = 2000.0;                // of the cable (its mass per volume: with diameter, its mass per metre) [kg/m^3]
  double axial_stiffness = 1.0e6;         // EA [N]
  double bending_stiffness = 0.0;         // EI [N m^2]; 0: a cable that bends freely
  double damping_s = 0.0;                 // Kelvin–Voigt time constant: T_damp = EA damping_s strain rate [s]
  double normal_drag_coefficient = 1.2;   // C_dn, on the diameter
  double tangential_drag_coefficient = 0.01;  // C_dt, on the circumference
  double normal_added_mass_coefficient = 1.0;  // C_an
  double seabed_stiffness = 1.0e5;        // [N/m per metre of cable]
  double friction = 0.5;                  // Coulomb, on the seabed

  double area() const;             // pi d^2 / 4 [m^2]
  double mass_per_metre() const;   // rho_c A [kg/m]
  double rest_segment() const { return length / segments; }  // L0 at the spec's length [m]
};

// A winch at a held end (`winch:` of a cable end): a drum that pays the cable out or hauls it in at a commanded
// speed, within its limits.
struct WinchSpec {
  double drum_length = 0.0;        // cable it holds, in the water and on the drum together [m]
  double min_length = 1.0;         // hauling in stops with this much in the water [m]
  double max_speed = 1.0;          // [m/s]
  double max_acceleration = 0.5;   // the drum's speed changes at most this fast [m/s^2]
};

// A winch's state: its line speed (+ paying out) and what it was last told.
struct WinchState {
  double speed = 0.0;              // [m/s]
  double command_speed = 0.0;      // [m/s], within +-max_speed
  double target_length = 0.0;      // stop when the length in the water reaches it [m]; 0: no target
  bool at_limit = false;           // stopped at min_length or the drum's end
};

// A cable of a scenario (`cables:`; keys: cable_keys(), configs/REFERENCE.md): its spec and what holds each end.
struct CableEndSpec {
  bool free = false;           // nothing holds it
  std::string vehicle;         // "": fixed in W at `position` (unless free)
  std::string link;            // on a vehicle: its link ("": the base link)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // fixed: p_W at t = 0; on a vehicle: p_L in the link's frame [m]
  // Fixed: the point moves at this velocity in W [m/s] (a tow point whose course the cable does not change).
  Eigen::Vector3d velocity_W = Eigen::Vector3d::Zero();
  std::optional<WinchSpec> winch;  // a winch holds it (on the fixed point or the vehicle's link)
  // Resolved by the loader: the vehicle's index in Model::vehicles and the link's in its links.
  int vehicle_index = -1;
  int link_index = 0;
  bool on_vehicle() const { return !free && !vehicle.empty(); }
};
struct CableModel {
  std::string name;
  CableSpec spec;
  double rate_hz = 10.0;  // of its topics (end forces, shape)
  std::array<CableEndSpec, 2> ends;  // `from`, `to`
  // The end with a winch (at most one per cable), or -1.
  int winch_end() const;
};
const config::KeyTable<CableModel>& cable_keys();
// The keys of one end (`from`, `to`) and of its winch, which the loader reads again to place its own errors.
const config::KeyTable<CableEndSpec>& cable_end_keys();
const config::KeyTable<WinchSpec>& winch_keys();

// What holds an end: nothing (a free end) or a point it follows.
struct CableEnd {
  bool held = false;
  Eigen::Vector3d p_W0 = Eigen::Vector3d::Zero();  // the holder's point at the step's start [m]
  Eigen::Vector3d p_W1 = Eigen::Vector3d::Zero();  // and at its end
};

struct CableState {
  double length = 0.0;               // unstretched, in the water [m]
  WinchState winch;                  // of its winch, if it has one
  std::vector<Eigen::Vector3d> p_W;  // nodes 0..N [m]
  std::vector<Eigen::Vector3d> v_W;  // [m/s]
  // The mean force the cable put on what holds each end over the last step [N, W] (zero at a free end).
  std::array<Eigen::Vector3d, 2> f_W_ends{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
};

// The water and the seabed as the cable sees them.
struct CableWorld {
  const Ocean* ocean = nullptr;  // null: water of water_density moving at current_W
  double water_density = 1025.0;  // [kg/m^3], without an ocean
  Eigen::Vector3d current_W = Eigen::Vector3d::Zero();  // [m/s], without an ocean
  Eigen::Vector3d gravity_W = Eigen::Vector3d(0.0, 0.0, -9.80665);  // [m/s^2]
  double time = 0.0;             // sim time at the step's start (the current) [s]
  // Height of the seabed under (x, y) [m]; empty: no seabed.
  std::function<double(double, double)> seabed_z;
};

// What a step gives back: the mean force the cable put on what holds each end [N, W].
struct CableStepResult {
  Eigen::Vector3d f_W_end0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d f_W_end1 = Eigen::Vector3d::Zero();
  int substeps = 0;
};

// A straight cable from a to b, at rest: its nodes evenly spaced (stretched or slack as the distance says).
CableState straight_cable(const CableSpec& spec, const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb);

// The sub-steps a physics step dt needs (above), at an unstretched length (0: the spec's).
int cable_substeps(const CableSpec& spec, double dt, double length = 0.0);

// Advances the cable by dt (above), its length changing at length_rate [m/s] over the step.
CableStepResult step_cable(const CableSpec& spec, const CableWorld& world, const CableEnd& end0, const CableEnd& end1,
                           double dt, CableState& state, double length_rate = 0.0);

// The winch over a step dt: its speed moves toward the command (or toward stopping at the target, min_length or
// the drum's end, whichever comes first) within max_acceleration, so that it stops exactly there. Updates
// state.winch and returns the mean rate of the length over the step [m/s] for step_cable.
double advance_winch(const WinchSpec& winch, double dt, CableState& state);

// Why a winch command is refused ("" if it is not): a speed or target that is not finite, a speed beyond
// max_speed, a target beyond the drum (drum_length) or below min_length, each naming its key.
std::string check_winch_command(const WinchSpec& winch, double speed, double target_length);

// Axial tension of each segment at the state [N] (without its damping part).
std::vector<double> cable_tensions(const CableSpec& spec, const CableState& state);

// Kinetic, gravitational (wet weight), elastic and bending energy [J], in a water of uniform density rho_w: what a cable
// without damping, drag or added mass conserves.
double cable_energy(const CableSpec& spec, const CableState& state, double rho_w, const Eigen::Vector3d& gravity_W);

}  // namespace hadal::physics
