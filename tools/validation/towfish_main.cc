// hadal-validate-towfish: the towed side-scan fish's steady depth at two tow speeds against the steady towed-cable
// solution (issue 43's figure; docs/validation.md, "Towed cable").
//
//   hadal-validate-towfish [--slow-kn 3] [--fast-kn 5] [--duration 600] [--out DIR] [--scenario PATH]
//
// Default scenario configs/scenarios/towfish.yaml: its first cable between two vehicles ("tow"), towing the one named
// `fish` (else its `to` end's) from the other. For each speed U the cable's ship end becomes a tow point moving at U along the ship's heading
// (`velocity` of a fixed end: the ship's own dynamics are not what is measured), the ship is made static and the
// fish's sensors are left out (its side-scan's rays cost and measure nothing here). The fish, cable and tow point
// start moving together at U with the cable straight at 30 deg; hadal::Simulation steps for --duration s and the
// last quarter is averaged: the fish's tow point's depth and layback below and behind the tow point, the top
// tension and the force the cable puts on the fish.
//
// Closed form (the steady towed-cable equations; e.g. Pode 1951, Ablow & Schechter 1983): in the plane of the tow,
// arc length s (unstretched) from the fish up to the tow point, the cable at angle phi above the horizontal, water
// streaming past at U, wet weight w per metre, normal drag D_n = 1/2 rho C_dn d U^2 and tangential
// D_t = 1/2 rho C_dt pi d U^2 per metre (the model's own Morison terms, physics/cable.h):
//   dT/ds = w sin(phi) + D_t cos^2(phi),     T dphi/ds = w cos(phi) - D_n sin^2(phi),
//   dx/ds = (1 + T / EA) cos(phi),            dz/ds = (1 + T / EA) sin(phi),
// integrated by RK4 from the fish, where T and phi are the simulated pull on the fish (the fish's own drag and
// weight: its model, not the cable's), over the cable's length. It predicts the depth and layback of the fish
// below and behind the tow point and the top tension; the lumped-mass cable should land within ~1 %.
// The figure's curve extends the slow run's fish load to other speeds (its drag as U^2, its wet weight as is).
//
// Writes into --out (default "."):
//   towfish_depth.png  left: the simulated cable's nodes and the closed-form shape at both speeds (layback vs depth);
//                      right: steady depth vs tow speed, closed form and the two simulated points
//   towfish_depth.csv  run,t_s,fish_depth_m,layback_m,top_tension_N
// and prints one JSON object (stdout) with both runs' figures and their relative differences.
//
// Exit status: 0 success; 1 the scenario does not load or has no towed vehicle, the simulation throws or an output
// cannot be written; 2 usage error; 3 a run went non-finite or did not settle (depth still moving > 1 % over its
// averaging window).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "hadal/core/simulation.h"
#include "plot.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using namespace hadal::validation;

constexpr const char* kTool = "hadal-validate-towfish";
constexpr const char* kUsage =
    "usage: hadal-validate-towfish [--slow-kn A] [--fast-kn B] [--duration S] [--out DIR] [--scenario PATH]\n"
    "  --slow-kn A      first tow speed [kn] (default 3, in (0, 15])\n"
    "  --fast-kn B      second tow speed [kn] (default 5, in (0, 15], above --slow-kn)\n"
    "  --duration S     sim time of each run [s] (default 600, in [20, 7200]); the last quarter is averaged\n"
    "  --out DIR        output directory for towfish_depth.{png,csv} (default .)\n"
    "  --scenario PATH  scenario (default configs/scenarios/towfish.yaml)\n"
    "Tows the fish at both speeds and compares its steady depth with the towed-cable solution; prints JSON.\n";

constexpr double kKnot = 1852.0 / 3600.0;  // [m/s]
constexpr double kSampleInterval = 0.5;    // [s of sim time]
constexpr double kStartAngle = 30.0 / kDegPerRad;

struct Tow {
  std::size_t cable = 0;
  std::size_t ship_end = 0, fish_end = 1;
  int ship = -1, fish = -1;  // vehicle indices
};

struct Sample {
  double t = 0.0;
  double depth = 0.0;    // of the fish's tow point below the tow point [m]
  double layback = 0.0;  // behind it, along the tow [m]
  double top_tension = 0.0;  // [N]
};

struct Shape {
  std::vector<double> layback, depth;  // [m], from the fish to the tow point
  double top_tension = 0.0;            // [N]
};

struct Run {
  std::string name;
  double speed = 0.0;  // [m/s]
  std::vector<Sample> samples;
  double depth = 0.0, layback = 0.0, top_tension = 0.0, depth_drift = 0.0;  // the window's means; drift max - min
  Eigen::Vector2d fish_pull = Eigen::Vector2d::Zero();  // the cable's mean pull on the fish (along, up) [N]
  Shape simulated;  // the last state's nodes
  Shape closed;
  bool finite = true;
};

// The towed-cable equations above from the fish (pull T0 at phi0) over `length` [m]; RK4 in 4000 steps.
Shape towed_cable(const physics::CableSpec& spec, double rho, double g, double U, double T0, double phi0) {
  const double w = (spec.density - rho) * spec.area() * g;
  const double Dn = 0.5 * rho * spec.normal_drag_coefficient * spec.diameter * U * U;
  const double Dt = 0.5 * rho * spec.tangential_drag_coefficient * std::numbers::pi * spec.diameter * U * U;
  const double EA = spec.axial_stiffness;
  using State = Eigen::Vector4d;  // T, phi, x (forward, toward the ship), z (up)
  const auto rate = [&](const State& y) {
    const double T = y[0], phi = y[1], c = std::cos(phi), s = std::sin(phi), stretch = 1.0 + T / EA;
    return State(w * s + Dt * c * c, (w * c - Dn * s * s) / T, stretch * c, stretch * s);
  };
  const int steps = 4000;
  const double h = spec.length / steps;
  State y(T0, phi0, 0.0, 0.0);
  std::vector<State> path{y};
  for (int k = 0; k < steps; ++k) {
    const State k1 = rate(y), k2 = rate(y + 0.5 * h * k1), k3 = rate(y + 0.5 * h * k2), k4 = rate(y + h * k3);
    y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    path.push_back(y);
  }
  Shape shape;
  for (const State& p : path) {  // relative to the tow point at the top
    shape.layback.push_back(y[2] - p[2]);
    shape.depth.push_back(y[3] - p[3]);
  }
  shape.top_tension = y[0];
  return shape;
}

Run tow_at(const Model& scenario, const Tow& tow, double U, double duration, const std::string& name) {
  Run run;
  run.name = name;
  run.speed = U;
  Model model = scenario;
  VehicleSpec& ship = model.vehicles[static_cast<std::size_t>(tow.ship)];
  VehicleSpec& fish = model.vehicles[static_cast<std::size_t>(tow.fish)];
  physics::CableModel& cable = model.cables[tow.cable];
  physics::CableEndSpec& top = cable.ends[tow.ship_end];
  const Eigen::Vector3d p_W0 = ship.X_WB_initial * (ship.links[static_cast<std::size_t>(top.link_index)].X_BL * top.position);
  Eigen::Vector3d heading_W = ship.X_WB_initial.linear().col(0);
  heading_W.z() = 0.0;
  heading_W.normalize();
  top = physics::CableEndSpec{};
  top.position = p_W0;
  top.velocity_W = U * heading_W;
  ship.is_static = true;
  fish.sensors.clear();
  // The fish trails at 30 deg below the tow point, level and facing the tow.
  const physics::CableEndSpec& bottom = cable.ends[tow.fish_end];
  const Eigen::Vector3d p_B = fish.links[static_cast<std::size_t>(bottom.link_index)].X_BL * bottom.position;
  const Eigen::Vector3d p_Wfish =
      p_W0 - cable.spec.length * (std::cos(kStartAngle) * heading_W + std::sin(kStartAngle) * Eigen::Vector3d::UnitZ());
  fish.X_WB_initial = Eigen::Isometry3d::Identity();
  fish.X_WB_initial.linear() << heading_W.x(), -heading_W.y(), 0.0, heading_W.y(), heading_W.x(), 0.0, 0.0, 0.0, 1.0;
  fish.X_WB_initial.translation() = p_Wfish - fish.X_WB_initial.linear() * p_B;

  Simulation sim(model);
  SimState state = sim.state();  // everything moving with the tow point from the start
  state.vehicles[static_cast<std::size_t>(tow.fish)].body.v_WB = U * heading_W;
  for (Eigen::Vector3d& v : state.cables[tow.cable].v_W) v = U * heading_W;
  sim.set_state(state);

  const double dt = model.world.step_size();
  const auto every = static_cast<std::uint64_t>(std::max(1.0, std::round(kSampleInterval / dt)));
  const auto steps = static_cast<std::uint64_t>(std::llround(duration / dt));
  const auto record = [&] {
    const physics::CableState& c = sim.state().cables[tow.cable];
    const Eigen::Vector3d& top_W = c.p_W[tow.ship_end == 0 ? 0 : c.p_W.size() - 1];
    const Eigen::Vector3d& fish_W = c.p_W[tow.fish_end == 0 ? 0 : c.p_W.size() - 1];
    Sample s;
    s.t = sim.time();
    s.depth = top_W.z() - fish_W.z();
    s.layback = (top_W - fish_W).dot(heading_W);
    s.top_tension = c.f_W_ends[tow.ship_end].norm();
    run.finite = run.finite && std::isfinite(s.depth) && std::isfinite(s.top_tension);
    run.samples.push_back(s);
  };
  Eigen::Vector3d pull_W = Eigen::Vector3d::Zero();
  std::uint64_t pulls = 0;
  for (std::uint64_t k = 1; k <= steps && run.finite; ++k) {
    sim.step();
    if (sim.time() >= 0.75 * duration) {
      pull_W += sim.state().cables[tow.cable].f_W_ends[tow.fish_end];
      ++pulls;
    }
    if (k % every == 0) record();
  }
  pull_W /= static_cast<double>(std::max<std::uint64_t>(pulls, 1));
  run.fish_pull = Eigen::Vector2d(pull_W.dot(heading_W), pull_W.z());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  int n = 0;
  for (const Sample& s : run.samples) {
    if (s.t < 0.75 * duration) continue;
    run.depth += s.depth;
    run.layback += s.layback;
    run.top_tension += s.top_tension;
    lo = std::min(lo, s.depth);
    hi = std::max(hi, s.depth);
    ++n;
  }
  run.depth /= n;
  run.layback /= n;
  run.top_tension /= n;
  run.depth_drift = hi - lo;
  const physics::CableState& c = sim.state().cables[tow.cable];
  const Eigen::Vector3d& top_W = c.p_W[tow.ship_end == 0 ? 0 : c.p_W.size() - 1];
  for (std::size_t i = 0; i < c.p_W.size(); ++i) {
    const Eigen::Vector3d& p = c.p_W[tow.fish_end == 0 ? i : c.p_W.size() - 1 - i];
    run.simulated.layback.push_back((top_W - p).dot(heading_W));
    run.simulated.depth.push_back(top_W.z() - p.z());
  }
  run.closed = towed_cable(cable.spec, model.world.water.density, model.world.gravity_W.norm(), U,
                           run.fish_pull.norm(), std::atan2(run.fish_pull.y(), run.fish_pull.x()));
  return run;
}

std::string write_csv(const std::vector<const Run*>& runs, const std::string& path) {
  std::ofstream out(path);
  if (!out) return path + ": cannot write the CSV";
  out << "run,t_s,fish_depth_m,layback_m,top_tension_N\n";
  char line[200];
  for (const Run* run : runs) {
    for (const Sample& s : run->samples) {
      std::snprintf(line, sizeof(line), "%s,%.3f,%.6f,%.6f,%.3f\n", run->name.c_str(), s.t, s.depth, s.layback,
                    s.top_tension);
      out << line;
    }
  }
  out.close();
  return out ? std::string() : path + ": write failed";
}

double relative(double simulated, double closed) { return (simulated - closed) / closed; }

}  // namespace

int main(int argc, char** argv) {
  double slow_kn = 3.0, fast_kn = 5.0, duration = 600.0;
  std::string out_dir = ".";
  std::string scenario = HADAL_SOURCE_DIR "/configs/scenarios/towfish.yaml";
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--slow-kn", &slow_kn, NumberRange::left_open(0.0, 15.0))
      .number("--fast-kn", &fast_kn, NumberRange::left_open(0.0, 15.0))
      .number("--duration", &duration, NumberRange::closed(20.0, 7200.0))
      .text("--out", &out_dir)
      .text("--scenario", &scenario);
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  if (!(fast_kn > slow_kn)) {
    std::fprintf(stderr, "%s: --fast-kn (%g) must be above --slow-kn (%g)\n%s", kTool, fast_kn, slow_kn, kUsage);
    return 2;
  }
  const std::optional<Model> model = prepare_run(out_dir, scenario, kTool);
  if (!model) return 1;
  Tow tow;
  bool found = false;
  for (std::size_t c = 0; c < model->cables.size() && !found; ++c) {
    const physics::CableModel& cable = model->cables[c];
    if (!cable.ends[0].on_vehicle() || !cable.ends[1].on_vehicle()) continue;
    // The towed end: the one on a vehicle named "fish", else `to`.
    const std::size_t fish = model->vehicles[static_cast<std::size_t>(cable.ends[0].vehicle_index)].name == "fish" ? 0 : 1;
    tow = Tow{c, 1 - fish, fish, cable.ends[1 - fish].vehicle_index, cable.ends[fish].vehicle_index};
    found = true;
  }
  if (!found) {
    std::fprintf(stderr, "%s: %s: no cable between two vehicles (a ship and what it tows)\n", kTool, scenario.c_str());
    return 1;
  }
  const auto wall_start = std::chrono::steady_clock::now();
  Run slow, fast;
  try {
    slow = tow_at(*model, tow, slow_kn * kKnot, duration, "slow");
    fast = tow_at(*model, tow, fast_kn * kKnot, duration, "fast");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  const physics::CableSpec& spec = model->cables[tow.cable].spec;
  const double rho = model->world.water.density, g = model->world.gravity_W.norm();

  // The closed-form curve: the slow run's fish load, its drag scaled as U^2.
  plot::Series curve;
  curve.label = "towed-cable solution (fish load of the slow run, drag ~ U^2)";
  curve.color = plot::palette(0);
  for (int k = 0; k <= 60; ++k) {
    const double U = (0.5 + 7.5 * k / 60.0) * kKnot;
    const Eigen::Vector2d pull(slow.fish_pull.x() * (U / slow.speed) * (U / slow.speed), slow.fish_pull.y());
    const Shape shape = towed_cable(spec, rho, g, U, pull.norm(), std::atan2(pull.y(), pull.x()));
    curve.x.push_back(U / kKnot);
    curve.y.push_back(-shape.depth.front());
  }
  namespace plot = hadal::validation::plot;
  plot::Figure figure;
  figure.title = "Towfish on " + json_rounded(spec.length, 4) + " m of cable: steady depth vs tow speed";
  figure.panel_width = 620;
  figure.panel_height = 480;
  plot::Panel shapes;
  shapes.title = "The cable in the plane of the tow";
  shapes.x.label = "layback behind the tow point [m]";
  shapes.y.label = "depth below the tow point [m]";
  shapes.legend = plot::LegendPosition::kBottomLeft;
  plot::Panel depth;
  depth.title = "Steady depth of the fish";
  depth.x.label = "tow speed [kn]";
  depth.y.label = "depth below the tow point [m]";
  depth.legend = plot::LegendPosition::kTopLeft;
  depth.series.push_back(curve);
  plot::Series points;
  points.label = "simulated (lumped-mass cable, fish)";
  points.color = plot::palette(1);
  points.line_width = 0.0;
  points.marker = plot::Marker::kCircle;
  points.marker_size = 6;
  int colour = 1;
  for (const Run* run : {&slow, &fast}) {
    plot::Series nodes, closed;
    const std::string speed = json_rounded(run->speed / kKnot, 3) + " kn";
    nodes.label = "simulated nodes, " + speed;
    nodes.color = plot::palette(colour);
    nodes.line_width = 0.0;
    nodes.marker = plot::Marker::kCircle;
    nodes.marker_size = 3;
    closed.label = "closed form, " + speed;
    closed.color = plot::palette(colour);
    closed.dashed = true;
    closed.color = plot::palette(colour == 1 ? 7 : 0);  // black and blue, over the nodes' colours
    closed.line_width = 1.5;
    for (std::size_t i = 0; i < run->simulated.depth.size(); ++i) {
      nodes.x.push_back(run->simulated.layback[i]);
      nodes.y.push_back(-run->simulated.depth[i]);
    }
    for (std::size_t i = 0; i < run->closed.depth.size(); ++i) {
      closed.x.push_back(run->closed.layback[i]);
      closed.y.push_back(-run->closed.depth[i]);
    }
    shapes.series.push_back(nodes);
    shapes.series.push_back(closed);  // on top: the nodes lie on it
    points.x.push_back(run->speed / kKnot);
    points.y.push_back(-run->depth);
    colour += 1;
  }
  depth.series.push_back(points);
  shapes.x.min = 0.0;
  figure.panels = {shapes, depth};
  const std::string png = join_path(out_dir, "towfish_depth.png");
  const std::string csv = join_path(out_dir, "towfish_depth.csv");
  std::string error = plot::write_png(figure, png);
  if (error.empty()) error = write_csv({&slow, &fast}, csv);
  if (!error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }

  const auto summary = [&](const Run& run) {
    JsonObject o(2);
    o.number("speed_kn", run.speed / kKnot)
        .number("speed_m_s", run.speed)
        .number("fish_depth_m", run.depth)
        .number("closed_form_fish_depth_m", run.closed.depth.front())
        .number("depth_relative_difference", relative(run.depth, run.closed.depth.front()))
        .number("layback_m", run.layback)
        .number("closed_form_layback_m", run.closed.layback.front())
        .number("layback_relative_difference", relative(run.layback, run.closed.layback.front()))
        .number("top_tension_N", run.top_tension)
        .number("closed_form_top_tension_N", run.closed.top_tension)
        .number("top_tension_relative_difference", relative(run.top_tension, run.closed.top_tension))
        .number("fish_pull_along_N", run.fish_pull.x())
        .number("fish_pull_up_N", run.fish_pull.y())
        .number("depth_drift_in_window_m", run.depth_drift);
    return o.str();
  };
  const bool settled = slow.finite && fast.finite && slow.depth_drift < 0.01 * slow.depth &&
                       fast.depth_drift < 0.01 * fast.depth;
  JsonObject json;
  json.text("scenario", scenario)
      .text("cable", model->cables[tow.cable].name)
      .number("cable_length_m", spec.length)
      .number("segments", spec.segments)
      .number("physics_rate_hz", model->world.physics_rate_hz)
      .number("duration_s", duration)
      .raw("slow", summary(slow))
      .raw("fast", summary(fast))
      .boolean("settled", settled)
      .number("wall_time_s", wall, 3)
      .text("png", png)
      .text("csv", csv);
  std::printf("%s\n", json.str().c_str());
  return settled ? 0 : 3;
}
