#include "hadal/physics/cable.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "hadal/physics/ocean.h"

namespace hadal::physics {

double CableSpec::area() const { return 0.25 * std::numbers::pi * diameter * diameter; }
double CableSpec::mass_per_metre() const { return density * area(); }

CableState straight_cable(const CableSpec& spec, const Eigen::Vector3d& p_Wa, const Eigen::Vector3d& p_Wb) {
  CableState state;
  state.length = spec.length;
  const int n = spec.segments;
  for (int i = 0; i <= n; ++i) {
    state.p_W.push_back(p_Wa + (static_cast<double>(i) / n) * (p_Wb - p_Wa));
    state.v_W.push_back(Eigen::Vector3d::Zero());
  }
  return state;
}

int CableModel::winch_end() const {
  for (int e = 0; e < 2; ++e) {
    if (ends[static_cast<std::size_t>(e)].winch) return e;
  }
  return -1;
}

int cable_substeps(const CableSpec& spec, double dt, double length) {
  const double L0 = (length > 0.0 ? length : spec.length) / spec.segments;
  const double m = spec.mass_per_metre() * L0;
  const double omega_axial = 2.0 * std::sqrt(spec.axial_stiffness / (L0 * m));
  const double omega = std::sqrt(omega_axial * omega_axial + 16.0 * spec.bending_stiffness / (m * L0 * L0 * L0));
  const double zeta = 0.5 * omega_axial * spec.damping_s;
  const double h_max = 0.25 * 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
  return std::max(1, static_cast<int>(std::ceil(dt / h_max)));
}

namespace {

// The bending forces -dE/dp of E = k_b sum_i (1 - t_a . t_b) over the interior nodes, added into `force`, from each
// segment's unit tangent t[s] and length l[s] (0: a degenerate segment, which bends nothing).
void add_bending(const std::vector<Eigen::Vector3d>& t, const std::vector<double>& l, double k_b,
                 std::vector<Eigen::Vector3d>& force) {
  for (std::size_t i = 1; i < l.size(); ++i) {  // the node between segments i - 1 and i
    const double la = l[i - 1], lb = l[i];
    if (!(la > 0.0) || !(lb > 0.0)) continue;
    const Eigen::Vector3d& ta = t[i - 1];
    const Eigen::Vector3d& tb = t[i];
    const double c = ta.dot(tb);
    const Eigen::Vector3d f_next = k_b * (ta - c * tb) / lb;   // k_b dc/dp_{i+1}
    const Eigen::Vector3d f_prev = -k_b * (tb - c * ta) / la;  // k_b dc/dp_{i-1}
    force[i + 1] += f_next;
    force[i - 1] += f_prev;
    force[i] -= f_next + f_prev;
  }
}

// Per node, what is sampled once a step: the water's density and current.
struct NodeWater {
  double rho = 1025.0;
  Eigen::Vector3d current_W = Eigen::Vector3d::Zero();
};

}  // namespace

CableStepResult step_cable(const CableSpec& spec, const CableWorld& world, const CableEnd& end0, const CableEnd& end1,
                           double dt, CableState& state, double length_rate) {
  CableStepResult result;
  const int n = spec.segments;
  const auto nodes = static_cast<std::size_t>(n + 1);
  const double A = spec.area();
  const double length0 = state.length > 0.0 ? state.length : spec.length;
  // The rest length and what follows from it, at a fraction s of the step.
  double L0 = 0.0, L0_rate = length_rate / n, m_segment = 0.0, k = 0.0, c = 0.0;
  const auto set_length = [&](double s) {
    L0 = (length0 + s * dt * length_rate) / n;
    m_segment = spec.mass_per_metre() * L0;
    k = spec.axial_stiffness / L0;
    c = k * spec.damping_s;
  };
  set_length(0.0);

  std::vector<NodeWater> water(nodes);
  std::vector<double> seabed(nodes, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < nodes; ++i) {
    if (world.ocean) {
      water[i].rho = world.ocean->density(world.ocean->depth(state.p_W[i].z()));
      water[i].current_W = world.ocean->current_W(state.p_W[i], world.time);
    } else {
      water[i].rho = world.water_density;
      water[i].current_W = world.current_W;
    }
    if (world.seabed_z) seabed[i] = world.seabed_z(state.p_W[i].x(), state.p_W[i].y());
  }
  // Each node's share of a segment's mass and, across its tangent, added mass (half at each end).
  const auto share = [&](std::size_t i) { return (i == 0 || i + 1 == nodes) ? 0.5 : 1.0; };
  std::vector<double> mass(nodes), added(nodes);
  const auto set_masses = [&] {
    for (std::size_t i = 0; i < nodes; ++i) {
      mass[i] = share(i) * m_segment;
      added[i] = spec.normal_added_mass_coefficient * water[i].rho * A * L0 * share(i);
    }
  };
  set_masses();

  const int substeps = cable_substeps(spec, dt, std::min(length0, length0 + dt * length_rate));
  const double h = dt / substeps;
  result.substeps = substeps;
  std::vector<Eigen::Vector3d> force(nodes), tangent(nodes), accel(nodes);
  std::vector<Eigen::Vector3d> segment_t(nodes - 1);  // each segment's unit tangent and length (bending)
  std::vector<double> segment_l(nodes - 1);
  const auto place_end = [&](const CableEnd& end, std::size_t node, double s) {
    if (!end.held) return;
    state.p_W[node] = end.p_W0 + s * (end.p_W1 - end.p_W0);
    state.v_W[node] = (end.p_W1 - end.p_W0) / dt;
  };
  const auto held = [&](std::size_t i) { return (i == 0 && end0.held) || (i + 1 == nodes && end1.held); };
  // Every node's force at the state, its acceleration, and what the held ends feel.
  Eigen::Vector3d f_end0 = Eigen::Vector3d::Zero(), f_end1 = Eigen::Vector3d::Zero();
  const auto accelerations = [&] {
    for (std::size_t i = 0; i < nodes; ++i) {
      force[i] = mass[i] * world.gravity_W - water[i].rho * (mass[i] / spec.density) * world.gravity_W;
      tangent[i].setZero();
    }
    for (std::size_t s = 0; s + 1 < nodes; ++s) {
      const Eigen::Vector3d d = state.p_W[s + 1] - state.p_W[s];
      const double l = d.norm();
      segment_l[s] = l > 1e-12 ? l : 0.0;
      if (!(l > 1e-12)) continue;
      const Eigen::Vector3d t = d / l;
      segment_t[s] = t;
      tangent[s] += t;
      tangent[s + 1] += t;
      const Eigen::Vector3d dv = state.v_W[s + 1] - state.v_W[s];
      const double tension = std::max(0.0, k * (l - L0) + c * (dv.dot(t) - L0_rate));
      force[s] += tension * t;
      force[s + 1] -= tension * t;
      // Drag on the segment's middle, relative to the water there.
      const double rho = 0.5 * (water[s].rho + water[s + 1].rho);
      const Eigen::Vector3d v_rel =
          0.5 * (state.v_W[s] + state.v_W[s + 1]) - 0.5 * (water[s].current_W + water[s + 1].current_W);
      const Eigen::Vector3d v_t = v_rel.dot(t) * t;
      const Eigen::Vector3d v_n = v_rel - v_t;
      const Eigen::Vector3d drag =
          -0.5 * rho * L0 *
          (spec.normal_drag_coefficient * spec.diameter * v_n.norm() * v_n +
           spec.tangential_drag_coefficient * std::numbers::pi * spec.diameter * v_t.norm() * v_t);
      force[s] += 0.5 * drag;
      force[s + 1] += 0.5 * drag;
    }
    // Bending: at each interior node, the angle between its two segments (the header's E_i).
    if (spec.bending_stiffness > 0.0) add_bending(segment_t, segment_l, spec.bending_stiffness / L0, force);
    // The seabed.
    for (std::size_t i = 0; i < nodes; ++i) {
      const double penetration = seabed[i] + 0.5 * spec.diameter - state.p_W[i].z();
      if (penetration <= 0.0) continue;
      const double stiffness = spec.seabed_stiffness * share(i) * L0;
      const double normal =
          std::max(0.0, stiffness * penetration - 2.0 * std::sqrt(stiffness * mass[i]) * state.v_W[i].z());
      force[i].z() += normal;
      const Eigen::Vector3d v_h(state.v_W[i].x(), state.v_W[i].y(), 0.0);
      force[i] -= spec.friction * normal * v_h / std::max(v_h.norm(), 0.01);
    }
    f_end0 = force.front();
    f_end1 = force.back();
    for (std::size_t i = 0; i < nodes; ++i) {
      const double tn = tangent[i].norm();
      accel[i] = force[i] / mass[i];
      if (tn > 1e-12 && added[i] > 0.0) {  // across the tangent the water moves with the node
        const Eigen::Vector3d t = tangent[i] / tn;
        const Eigen::Vector3d along = force[i].dot(t) * t;
        accel[i] = along / mass[i] + (force[i] - along) / (mass[i] + added[i]);
      }
    }
  };
  // Velocity Verlet (kick, drift, kick), the velocity-dependent forces at the half-kicked velocities.
  place_end(end0, 0, 0.0);
  place_end(end1, nodes - 1, 0.0);
  accelerations();
  for (int sub = 0; sub < substeps; ++sub) {
    const Eigen::Vector3d f0_start = f_end0, f1_start = f_end1;
    for (std::size_t i = 0; i < nodes; ++i) {
      if (held(i)) continue;
      state.v_W[i] += 0.5 * h * accel[i];
      state.p_W[i] += h * state.v_W[i];
    }
    const double s1 = static_cast<double>(sub + 1) / substeps;
    if (length_rate != 0.0) {
      set_length(s1);
      set_masses();
    }
    place_end(end0, 0, s1);
    place_end(end1, nodes - 1, s1);
    accelerations();
    for (std::size_t i = 0; i < nodes; ++i) {
      if (!held(i)) state.v_W[i] += 0.5 * h * accel[i];
    }
    // What the holders feel: the forces on their nodes, averaged over the sub-steps (trapezoidal).
    if (end0.held) result.f_W_end0 += 0.5 * (f0_start + f_end0) / substeps;
    if (end1.held) result.f_W_end1 += 0.5 * (f1_start + f_end1) / substeps;
  }
  state.length = length0 + dt * length_rate;
  return result;
}

std::vector<double> cable_tensions(const CableSpec& spec, const CableState& state) {
  std::vector<double> tensions;
  const double L0 = state.length / spec.segments;
  for (std::size_t s = 0; s + 1 < state.p_W.size(); ++s) {
    tensions.push_back(std::max(0.0, spec.axial_stiffness * ((state.p_W[s + 1] - state.p_W[s]).norm() - L0) / L0));
  }
  return tensions;
}

double cable_energy(const CableSpec& spec, const CableState& state, double rho_w, const Eigen::Vector3d& gravity_W) {
  const std::size_t nodes = state.p_W.size();
  const double L0 = state.length / spec.segments;
  const double m_segment = spec.mass_per_metre() * L0;
  double energy = 0.0;
  for (std::size_t i = 0; i < nodes; ++i) {
    const double m = (i == 0 || i + 1 == nodes) ? 0.5 * m_segment : m_segment;
    const double wet = m * (1.0 - rho_w / spec.density);
    energy += 0.5 * m * state.v_W[i].squaredNorm() - wet * gravity_W.dot(state.p_W[i]);
  }
  for (std::size_t s = 0; s + 1 < nodes; ++s) {
    const double stretch = std::max(0.0, (state.p_W[s + 1] - state.p_W[s]).norm() - L0);
    energy += 0.5 * spec.axial_stiffness / L0 * stretch * stretch;
  }
  for (std::size_t i = 1; i + 1 < nodes; ++i) {
    const Eigen::Vector3d a = state.p_W[i] - state.p_W[i - 1], b = state.p_W[i + 1] - state.p_W[i];
    if (a.norm() > 1e-12 && b.norm() > 1e-12) energy += spec.bending_stiffness / L0 * (1.0 - a.normalized().dot(b.normalized()));
  }
  return energy;
}

double advance_winch(const WinchSpec& winch, double dt, CableState& state) {
  WinchState& w = state.winch;
  const double length = state.length;
  const double a = winch.max_acceleration;
  // Its way: with a target, toward it at the commanded speed's magnitude, stopping there; without one, at the
  // commanded speed until the drum's end (paying out) or min_length (hauling in).
  double speed = w.command_speed;
  double stop = speed > 0.0 ? winch.drum_length : winch.min_length;
  if (w.target_length > 0.0) {
    speed = w.target_length > length ? std::abs(speed) : w.target_length < length ? -std::abs(speed) : 0.0;
    stop = w.target_length;
  }
  // No faster than it can still brake to rest at the stop: the speed v1 at the step's end with v1^2 <= 2 a d1 for
  // the distance d1 left after the step, d1 = d0 - (v0 + v1) dt / 2 (the trapezoid the length moves by); the speed
  // changes by at most a dt.
  const double v0 = w.speed;
  const double toward = speed > 0.0 ? v0 : -v0;  // v0 toward the stop
  const double room = std::max(0.0, std::abs(stop - length) - 0.5 * toward * dt);
  const double reachable = std::max(0.0, 0.5 * (-a * dt + std::sqrt(a * a * dt * dt + 8.0 * a * room)));
  const double wanted = std::clamp(speed, -reachable, reachable);
  double v1 = v0 + std::clamp(wanted - v0, -a * dt, a * dt);
  double next = length + 0.5 * (v0 + v1) * dt;
  // Never past the stop it is heading for, nor the drum's ends: the last bit is covered exactly and it stops.
  if ((speed > 0.0 && next > stop) || (speed < 0.0 && next < stop)) next = stop, v1 = 0.0;
  const double low = std::min(winch.min_length, length), high = std::max(winch.drum_length, length);
  if (next < low || next > high) next = std::clamp(next, low, high), v1 = 0.0;
  w.speed = v1;
  w.at_limit = (next >= winch.drum_length && speed > 0.0) || (next <= winch.min_length && speed < 0.0);
  return (next - length) / dt;
}

namespace {

std::string metres(double x, const char* unit) {
  std::ostringstream out;
  out << x << ' ' << unit;
  return out.str();
}

}  // namespace

std::string check_winch_command(const WinchSpec& winch, double speed, double target_length) {
  if (!std::isfinite(speed)) return "speed is not finite";
  if (!std::isfinite(target_length)) return "target_length is not finite";
  if (std::abs(speed) > winch.max_speed) {
    return "speed " + metres(speed, "m/s") + " is beyond the winch's max_speed (" + metres(winch.max_speed, "m/s") + ")";
  }
  if (target_length < 0.0) return "target_length " + metres(target_length, "m") + " is negative (0: no target)";
  if (target_length > winch.drum_length) {
    return "target_length " + metres(target_length, "m") + " is beyond the drum (drum_length " +
           metres(winch.drum_length, "m") + ")";
  }
  if (target_length > 0.0 && target_length < winch.min_length) {
    return "target_length " + metres(target_length, "m") + " is below the winch's min_length (" +
           metres(winch.min_length, "m") + ")";
  }
  return "";
}

}  // namespace hadal::physics
