// hadal-validate-coriolis: the paper's figure "lateral deviation vs distance" (Environmental Flow
// Modeling and Hydrodynamic Forces): a vehicle runs a long straight leg with Earth-rotation Coriolis
// on and off, and the lateral deviation from the ideal straight path is plotted against the distance
// travelled; without Coriolis it stays at zero (the dashed baseline).
//
//   hadal-validate-coriolis [--distance 5000] [--out DIR] [--scenario PATH] [--no-hold]
//
// Default scenario tools/validation/scenarios/coriolis_auv.yaml: the default torpedo AUV
// (configs/vehicles/torpedo_auv.yaml) at 45 deg N heading east, main thruster at full speed. The two
// runs set model.world.dynamics.earth_rotation true / false on the loaded Model (Simulation applies
// F = -2 m Omega_W x v_WBcm at the centre of mass, Omega_W = Omega_E (0, cos lat, sin lat) in ENU).
// Attitude is held by an ideal autopilot: after every step the body is turned back to its initial
// orientation about its centre of mass and its rotation stopped, keeping the centre of mass's
// position and velocity: pure moments, no force. So heading, pitch and roll stay fixed (no
// weathervaning, no diving on a pitch-down trim) and the lateral force balance is Coriolis against
// the hull's sway damping alone. A real autopilot steering with fins or the AUV's nose tunnel
// thruster would add side forces of the size of the Coriolis force itself (the added-mass Munk
// moment it must cancel is proportional to the sway velocity), so the figure would show the
// autopilot as much as Coriolis. Each run stops when the along-track distance reaches --distance.
// --no-hold leaves the vehicle to its own stability: the default AUV then curves away by itself
// (1.1 km to port over a 5 km leg: the propeller torque heels it), and the Coriolis part (the
// difference between the runs, 45 m there) acts mostly through the heading; the closed forms, which
// assume a held heading, do not apply.
//
// What the result means. Track coordinates: s along the initial heading, y to its right (starboard).
// At latitude phi the horizontal Coriolis force on a body moving horizontally at U is
// 2 m Omega_E sin(phi) U to the right of its track (northern hemisphere). A free particle (no fluid)
// accelerates sideways at a = 2 Omega sin(phi) U, so after a distance L = U t
//   y_free = 1/2 a t^2 = Omega sin(phi) L^2 / U                          (quadratic in L).
// A hull in water is not free sideways: its sway damping Y_v balances the Coriolis force within a few
// sway time constants ((m + m_A) / Y_v, about a second here), after which it crabs at the steady sway
// velocity v_ss = 2 m Omega sin(phi) U / Y_v, so
//   y_hull = v_ss t = v_ss L / U = 2 m Omega sin(phi) L / Y_v            (linear in L),
// centimetres to metres over kilometres where the free particle would be hundreds of metres off.
// Y_v is the lumped model's sway damping (linear + quadratic at v_ss), or for the surface model the
// per-face side force linearised at the cruise speed (central difference of SurfaceHydrodynamics at
// sideslip +-1 %: lift of the fins and hull, skin friction; it grows with U, so y_hull still does
// not depend much on the speed). The simulated deviation should follow y_hull; the free-particle law
// is the upper bound the paper's intuition refers to (what a drag-free or current-borne body does).
// The right panel shows both laws and the simulation on log-log axes: slopes 1 and 2.
//
// Writes into --out (default "."):
//   coriolis_deviation.png  left: lateral deviation vs distance, with Coriolis, without (dashed,
//                           zero), damped-hull closed form; right: |deviation| log-log with both laws
//   coriolis_deviation.csv  run,t_s,along_track_m,lateral_right_m,x_m,y_m,z_m,speed_m_s,yaw_deg
// and prints one JSON object (stdout): lateral deviation at the end with and without Coriolis, the
// closed forms, the cruise speed, the latitude.
//
// Exit status: 0 success; 1 the scenario does not load, the simulation throws or an output cannot
// be written; 2 usage error; 3 a run did not reach the distance within the time limit.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "hadal/core/simulation.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/ocean.h"
#include "hadal/physics/surface_hydrodynamics.h"
#include "plot.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using namespace hadal::validation;

constexpr const char* kTool = "hadal-validate-coriolis";
constexpr const char* kUsage =
    "usage: hadal-validate-coriolis [--distance L] [--out DIR] [--scenario PATH]\n"
    "  --distance L     along-track distance of each run [m] (default 5000, in (0, 1e6])\n"
    "  --out DIR        output directory for coriolis_deviation.{png,csv} (default .)\n"
    "  --scenario PATH  scenario (default tools/validation/scenarios/coriolis_auv.yaml)\n"
    "  --no-hold        no attitude autopilot: the vehicle keeps course by its own stability only\n"
    "Runs the straight leg with Earth-rotation Coriolis on and off; prints JSON.\n";

constexpr double kSampleInterval = 1.0;  // [s of sim time]
constexpr double kMinSpeed = 0.05;       // a run slower than this on average is abandoned [m/s]


struct Sample {
  double t = 0.0;
  double along = 0.0;  // s [m]
  double right = 0.0;  // y, positive to starboard [m]
  Eigen::Vector3d p_WBcm = Eigen::Vector3d::Zero();
  double speed = 0.0;  // horizontal speed of the centre of mass [m/s]
  double yaw = 0.0;    // [rad]
};

struct Run {
  std::string name;
  std::vector<Sample> samples;
  bool reached = false;
  double max_attitude_correction = 0.0;  // largest per-step correction of the autopilot [rad]
};

// Ideal attitude autopilot: after each step an impulsive pure moment about the centre of mass stops
// the body's rotation, and the body is turned back to R_WB0 about its centre of mass. With added
// mass the 6x6 inertia M = M_RB + kappa M_A (about the centre of mass, B axes) couples rotation and
// translation, so the impulse h that cancels w_B also changes the linear velocity:
//   M^-1 = [P Q; Q^T S],  S h = -w_B  ->  dv_B = Q h = -Q S^-1 w_B,
// and, as the step's moments built w_B and this coupled velocity together and Bullet's symplectic
// Euler moved the body with it for dt, the centre of mass is moved back by dv_B dt too. Without these
// terms the moments of each step (propeller torque, trim) would leak into a steady drift through the
// coupling, which a real autopilot's counter-moment, acting through the same M, prevents.
class AttitudeHold {
 public:
  AttitudeHold(const Simulation& sim, const Eigen::Matrix3d& R_WB0)
      : R_WB0_(R_WB0), dt_(sim.model().world.step_size()) {
    const physics::MassProperties& mp = sim.mass_properties(0);
    p_BBcm_ = mp.p_BBcm;
    const double depth = sim.ocean().depth((sim.state().vehicles[0].body.X_WB * p_BBcm_).z());
    Matrix6d M = Matrix6d::Zero();
    M.topLeftCorner<3, 3>() = mp.mass * Eigen::Matrix3d::Identity();
    M.bottomRightCorner<3, 3>() = mp.I_BBcm_B;
    M += sim.ocean().kappa(std::max(depth, 0.0)) * sim.added_mass(0);
    const Matrix6d M_inv = M.inverse();
    coupling_ = M_inv.topRightCorner<3, 3>() * M_inv.bottomRightCorner<3, 3>().inverse();
  }

  // Applies the hold to vehicle 0; returns the attitude correction angle [rad].
  double apply(Simulation& sim) const {
    SimState state = sim.state();
    RigidBodyState& body = state.vehicles[0].body;
    const Eigen::Matrix3d R_WB = body.X_WB.linear();
    const double angle = Eigen::AngleAxisd(R_WB0_.transpose() * R_WB).angle();
    if (angle == 0.0 && body.w_WB.isZero(0.0)) return 0.0;
    Eigen::Vector3d p_WBcm = body.X_WB * p_BBcm_;
    Eigen::Vector3d v_WBcm = body.v_WB + body.w_WB.cross(p_WBcm - body.X_WB.translation());
    const Eigen::Vector3d dv_W = -R_WB * (coupling_ * (R_WB.transpose() * body.w_WB));
    v_WBcm += dv_W;
    p_WBcm += dv_W * dt_;
    body.X_WB.linear() = R_WB0_;
    body.X_WB.translation() = p_WBcm - R_WB0_ * p_BBcm_;
    body.w_WB.setZero();
    body.v_WB = v_WBcm;
    sim.set_state(state);
    return angle;
  }

 private:
  Eigen::Matrix3d R_WB0_;
  double dt_;
  Eigen::Vector3d p_BBcm_;
  Eigen::Matrix3d coupling_;  // Q S^-1
};

Run straight_leg(const Model& model, double distance, bool hold_attitude, const std::string& name) {
  Run run;
  run.name = name;
  Simulation sim(model);
  const Eigen::Vector3d p_BBcm = sim.mass_properties(0).p_BBcm;
  const double dt = model.world.step_size();
  const auto sample_every = static_cast<std::uint64_t>(std::max(1.0, std::round(kSampleInterval / dt)));
  const double t_limit = 600.0 + distance / kMinSpeed;

  const RigidBodyState& body0 = sim.state().vehicles[0].body;
  const Eigen::Matrix3d R_WB0 = body0.X_WB.linear();
  const double psi0 = yaw_of(R_WB0);
  const AttitudeHold hold(sim, R_WB0);
  const Eigen::Vector3d p0 = body0.X_WB * p_BBcm;
  const Eigen::Vector2d track(std::cos(psi0), std::sin(psi0));
  const Eigen::Vector2d right(std::sin(psi0), -std::cos(psi0));
  double next_report = 1000.0;
  auto record = [&]() {
    const RigidBodyState& body = sim.state().vehicles[0].body;
    Sample s;
    s.t = sim.time();
    s.p_WBcm = body.X_WB * p_BBcm;
    const Eigen::Vector2d d = (s.p_WBcm - p0).head<2>();
    s.along = d.dot(track);
    s.right = d.dot(right);
    const Eigen::Vector3d v = body.v_WB + body.w_WB.cross(s.p_WBcm - body.X_WB.translation());
    s.speed = v.head<2>().norm();
    s.yaw = yaw_of(body.X_WB.linear());
    run.samples.push_back(s);
    return s.along;
  };
  record();
  for (;;) {
    sim.step();
    if (hold_attitude) {
      run.max_attitude_correction = std::max(run.max_attitude_correction, hold.apply(sim));
    }
    const RigidBodyState& body = sim.state().vehicles[0].body;
    const double along = ((body.X_WB * p_BBcm) - p0).head<2>().dot(track);
    const bool done = along >= distance;
    if (done || sim.state().step_count % sample_every == 0) record();
    if (along >= next_report) {
      std::fprintf(stderr, "%s: %s: %.0f m at t = %.0f s\n", kTool, name.c_str(), along, sim.time());
      next_report += 1000.0;
    }
    if (done) {
      run.reached = true;
      break;
    }
    if (sim.time() > t_limit) break;
  }
  return run;
}

// Mean along-track speed over the second half of the run (past the acceleration) [m/s].
double cruise_speed(const Run& run) {
  const Sample& last = run.samples.back();
  std::size_t k = 0;
  while (k + 1 < run.samples.size() && run.samples[k].along < 0.5 * last.along) ++k;
  const Sample& mid = run.samples[k];
  return last.t > mid.t ? (last.along - mid.along) / (last.t - mid.t) : 0.0;
}

// Steady sway velocity of a lumped hull: Y_v v + Y_v|v| v^2 = force (all >= 0) [m/s].
double steady_sway(double linear, double quadratic, double force) {
  if (quadratic > 0.0) return (-linear + std::sqrt(linear * linear + 4.0 * quadratic * force)) / (2.0 * quadratic);
  return linear > 0.0 ? force / linear : std::numeric_limits<double>::infinity();
}

// Linear sway damping of a surface-model hull [N s/m]: -dF_y/dv of the per-face fluid force on the
// level body moving at (U, v, 0) in B through water at rest, by central difference at v = +-0.01 U.
// The body is placed deep (1000 m) so no face is near the surface.
double surface_sway_damping(const VehicleSpec& spec, const Eigen::Vector3d& p_BBcm, double rho, double g,
                            double U) {
  physics::SurfaceHydrodynamics hydro(hydrodynamic_mesh_B(spec), spec.fluid.hydrodynamics);
  physics::UniformWater water;
  water.density = rho;
  water.gravity = g;
  physics::BodyMotion motion;
  motion.X_WB.translation() = Eigen::Vector3d(0.0, 0.0, -1000.0);
  motion.p_WBcm = motion.X_WB * p_BBcm;
  const double dv = 0.01 * U;
  motion.v_WBcm = Eigen::Vector3d(U, dv, 0.0);
  const double f_plus = hydro.compute(motion, water).f_W.y();
  motion.v_WBcm = Eigen::Vector3d(U, -dv, 0.0);
  const double f_minus = hydro.compute(motion, water).f_W.y();
  return -(f_plus - f_minus) / (2.0 * dv);
}

std::string write_csv(const std::vector<const Run*>& runs, const std::string& path) {
  std::ofstream out(path);
  if (!out) return path + ": cannot write the CSV";
  out << "run,t_s,along_track_m,lateral_right_m,x_m,y_m,z_m,speed_m_s,yaw_deg\n";
  char line[256];
  for (const Run* run : runs) {
    for (const Sample& s : run->samples) {
      std::snprintf(line, sizeof(line), "%s,%.3f,%.6f,%.9f,%.6f,%.6f,%.6f,%.6f,%.9f\n",
                    run->name.c_str(), s.t, s.along, s.right, s.p_WBcm.x(), s.p_WBcm.y(),
                    s.p_WBcm.z(), s.speed, s.yaw * kDegPerRad);
      out << line;
    }
  }
  out.close();
  return out ? std::string() : path + ": write failed";
}

}  // namespace

int main(int argc, char** argv) {
  double distance = 5000.0;
  bool hold = true;
  std::string out_dir = ".";
  std::string scenario = HADAL_SOURCE_DIR "/tools/validation/scenarios/coriolis_auv.yaml";
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--distance", &distance, NumberRange::left_open(0.0, 1e6))
      .text("--out", &out_dir)
      .text("--scenario", &scenario)
      .flag("--no-hold", [&] { hold = false; });
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  std::optional<Model> loaded = prepare_run(out_dir, scenario, kTool);
  if (!loaded) return 1;
  Model model_on = std::move(*loaded);
  if (model_on.vehicles.empty()) {
    std::fprintf(stderr, "%s: %s: no vehicle\n", kTool, scenario.c_str());
    return 1;
  }
  model_on.world.dynamics.earth_rotation = true;
  Model model_off = model_on;
  model_off.world.dynamics.earth_rotation = false;

  const auto wall_start = std::chrono::steady_clock::now();
  Run on, off;
  double mass = 0.0;
  try {
    mass = physics::composite_mass_properties(model_on.vehicles[0].links).mass;
    on = straight_leg(model_on, distance, hold, "coriolis");
    off = straight_leg(model_off, distance, hold, "no_coriolis");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  // Closed forms at the cruise speed of the Coriolis run.
  const VehicleSpec& vehicle = model_on.vehicles[0];
  const double latitude = model_on.world.origin.latitude_rad;
  const double omega = model_on.world.dynamics.earth_rotation_rate;
  const double f = omega * std::sin(latitude);  // Omega sin(phi) [rad/s]
  const double U = cruise_speed(on);
  const double force = 2.0 * mass * f * U;
  const bool lumped = vehicle.fluid.model == FluidModelType::kLumped;
  double sway_damping = 0.0, v_ss = 0.0;
  if (lumped) {
    v_ss = steady_sway(vehicle.fluid.linear_damping[1], vehicle.fluid.quadratic_damping[1], force);
    sway_damping = v_ss > 0.0 ? force / v_ss : vehicle.fluid.linear_damping[1];
  } else {
    const Eigen::Vector3d p_BBcm = physics::composite_mass_properties(vehicle.links).p_BBcm;
    sway_damping = surface_sway_damping(vehicle, p_BBcm, model_on.world.water.density,
                                        model_on.world.gravity_W.norm(), U);
    v_ss = sway_damping > 0.0 ? force / sway_damping : std::numeric_limits<double>::quiet_NaN();
  }
  auto y_free = [&](double L) { return U > 0.0 ? f * L * L / U : 0.0; };
  auto y_hull = [&](double L) { return U > 0.0 ? v_ss * L / U : 0.0; };

  // Figure.
  namespace plot = hadal::validation::plot;
  plot::Figure figure;
  char title[160];
  std::snprintf(title, sizeof(title), "Coriolis drift of a straight %.0f m leg at %.1f deg latitude",
                distance, latitude * kDegPerRad);
  figure.title = title;
  figure.panel_width = 620;
  figure.panel_height = 500;
  const plot::Color c_on = plot::palette(1), c_off = plot::palette(0), c_hull = plot::palette(2),
                    c_free = plot::palette(5);
  plot::Series s_on, s_off, s_hull, s_free, a_on;
  s_on.label = a_on.label = "with Coriolis (simulated)";
  s_on.color = a_on.color = c_on;
  s_off.label = "without Coriolis";
  s_off.color = c_off;
  s_off.dashed = true;
  s_hull.label = "closed form, damped hull";
  s_hull.color = c_hull;
  s_hull.dashed = true;
  s_free.label = "closed form, free particle";
  s_free.color = c_free;
  s_free.dashed = true;
  for (const Sample& s : on.samples) {
    s_on.x.push_back(s.along);
    s_on.y.push_back(s.right);
    a_on.x.push_back(s.along);
    a_on.y.push_back(std::fabs(s.right));
  }
  for (const Sample& s : off.samples) {
    s_off.x.push_back(s.along);
    s_off.y.push_back(s.right);
  }
  for (int k = 0; k <= 200; ++k) {
    const double L = distance * std::pow(10.0, -3.0 + 3.0 * k / 200.0);  // 1e-3 L .. L, log-spaced
    s_free.x.push_back(L);
    s_free.y.push_back(y_free(L));
    s_hull.x.push_back(L);
    s_hull.y.push_back(y_hull(L));
  }
  plot::Panel linear;
  linear.title = "Lateral deviation from the straight path";
  linear.x.label = "distance travelled [m]";
  linear.y.label = "lateral deviation, + starboard [m]";
  linear.x.min = 0.0;
  linear.x.max = distance;
  // Room below zero so the dashed zero baseline is not hidden by the frame.
  double y_max = 0.0;
  for (double y : s_on.y) y_max = std::max(y_max, std::fabs(y));
  for (double y : s_off.y) y_max = std::max(y_max, std::fabs(y));
  if (y_max > 0.0) {
    const plot::Ticks ticks = plot::nice_ticks(0.0, y_max, 5);
    linear.y.min = -0.5 * ticks.step;
  }
  linear.legend = plot::LegendPosition::kTopLeft;
  linear.series = {s_off, s_on, s_hull};
  plot::Panel loglog;
  loglog.title = "Log-log: hull ~ L, free particle ~ L^2";
  loglog.x.label = "distance travelled [m]";
  loglog.y.label = "|lateral deviation| [m]";
  loglog.x.scale = loglog.y.scale = plot::Scale::kLog10;
  loglog.x.min = distance * 1e-2;
  loglog.x.max = distance;
  loglog.legend = plot::LegendPosition::kTopLeft;
  loglog.series = {a_on, s_free, s_hull};
  // Limit the log y axis to the curves' range at the left edge (free-particle values there are tiny).
  const double y_top = y_free(distance);
  const double y_low = std::min(y_hull(distance * 1e-2), y_free(distance * 1e-2));
  if (y_top > 0.0 && y_low > 0.0) {
    loglog.y.min = std::pow(10.0, std::floor(std::log10(y_low)));
    loglog.y.max = std::pow(10.0, std::ceil(std::log10(y_top)));
  }
  figure.panels = {linear, loglog};

  const std::string png = join_path(out_dir, "coriolis_deviation.png");
  const std::string csv = join_path(out_dir, "coriolis_deviation.csv");
  std::string error = plot::write_png(figure, png);
  if (error.empty()) error = write_csv({&on, &off}, csv);
  if (!error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }

  const Sample& end_on = on.samples.back();
  const Sample& end_off = off.samples.back();
  const double difference = end_on.right - end_off.right;
  JsonObject closed(2);
  closed.number("free_particle_m", y_free(end_on.along))
      .number("damped_hull_m", y_hull(end_on.along))
      .number("sway_damping_N_s_m", sway_damping)
      .number("steady_sway_velocity_m_s", v_ss);
  JsonObject json;
  json.text("scenario", scenario)
      .number("distance_m", distance)
      .number("latitude_deg", latitude * kDegPerRad)
      .number("earth_rotation_rate_rad_s", omega)
      .number("physics_rate_hz", model_on.world.physics_rate_hz)
      .text("fluid_model", lumped ? "lumped" : "surface")
      .number("mass_kg", mass)
      .number("cruise_speed_m_s", U)
      .number("coriolis_force_N", force)
      .number("time_s", end_on.t)
      .number("lateral_deviation_with_coriolis_m", end_on.right)
      .number("lateral_deviation_without_coriolis_m", end_off.right)
      .number("lateral_deviation_difference_m", difference)
      .raw("closed_form_lateral_deviation", closed.str())
      .number("simulated_over_damped_hull", y_hull(end_on.along) > 0.0 ? difference / y_hull(end_on.along)
                                                                      : std::numeric_limits<double>::quiet_NaN())
      .boolean("coriolis_effect_detected", std::fabs(difference) > 1e-6 * distance)
      .boolean("attitude_hold", hold)
      .number("max_attitude_correction_deg", std::max(on.max_attitude_correction, off.max_attitude_correction) * kDegPerRad)
      .number("depth_change_m", end_on.p_WBcm.z() - on.samples.front().p_WBcm.z())
      .boolean("reached", on.reached && off.reached)
      .number("wall_time_s", wall, 3)
      .text("png", png)
      .text("csv", csv);
  std::printf("%s\n", json.str().c_str());
  return on.reached && off.reached ? 0 : 3;
}
