// hadal-validate-lander: the paper's figure "lander lift/Magnus" (Environmental Flow Modeling and
// Hydrodynamic Forces): a free-fall deep-sea lander descends from the surface to a depth in the
// surface fluid model (per-face buoyancy, drag, skin friction, lift, Magnus; pycnocline density
// ramp), twice: as configured, and with lift and Magnus off (C_L = C_M = 0 on the loaded Model).
//
//   hadal-validate-lander [--depth 3000] [--out DIR] [--scenario PATH] [--segments 16] [--magnus C_M]
//
// Default scenario tools/validation/scenarios/lander_descent.yaml (free_fall_lander.yaml: frame,
// glass flotation spheres, ballast, housings and four canted vanes). The seabed plane is put 100 m
// below --depth. The hydrodynamic mesh is the collision primitives tessellated, as hadald does, but
// with --segments around the axis (hadald: 32) so the spheres cost 224 faces instead of 960 and the
// two descents take seconds: each link's primitives become a link mesh built at load time. Each run steps hadal::Simulation until the centre of mass reaches the depth,
// sampling every 0.5 s of sim time: centre-of-mass position, yaw (unwrapped), roll, pitch.
// Writes into --out (default "."):
//   lander_lift_magnus.png  left: XY tracks of the centre of mass (east, north), both runs;
//                           right: yaw vs depth, both runs
//   lander_lift_magnus.csv  run,t_s,x_m,y_m,z_m,depth_m,yaw_deg,roll_deg,pitch_deg,
//                           descent_rate_m_s,spin_deg_s
// and prints one JSON object (stdout): per run the descent time, terminal velocity (mean descent
// rate over the last 20 % of the depth), spin rate over the same window, final XY offset and yaw,
// maximum tilt; the difference between the runs; and the closed-form terminal velocity.
//
// Closed form (upright lander, descent speed V, fluid seen from the body v_c = V z_W): per face of
// area A and outward normal n, pressure drag 1/2 rho C_D A max(-n_z, 0)^3 V^2 and skin friction
// 1/2 rho C_f A (1 - n_z^2)^(3/2) V^2 push up, lift is horizontal, so the terminal velocity is
//   V_t = sqrt(2 (m - rho V_disp) g / (rho sum_f A_f [C_D max(-n_z, 0)^3 + C_f (1 - n_z^2)^(3/2)]))
// with rho at the depth (ramp: rho0 + 0.3 % below the pycnocline). It neglects the spin (the vanes
// see a tilted flow) and the tilt, so the simulated rate should sit within a few per cent of it.
//
// Exit status: 0 success; 1 the scenario does not load, the simulation throws or an output cannot
// be written; 2 usage error; 3 a run did not reach the depth within the time limit.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "hadal/core/simulation.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/physics/mass_properties.h"
#include "hadal/physics/ocean.h"
#include "plot.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using namespace hadal::validation;

constexpr const char* kTool = "hadal-validate-lander";
constexpr const char* kUsage =
    "usage: hadal-validate-lander [--depth D] [--out DIR] [--scenario PATH]\n"
    "  --depth D        target depth of the lander's centre of mass [m] (default 3000, in (0, 10900])\n"
    "  --out DIR        output directory for lander_lift_magnus.{png,csv} (default .)\n"
    "  --scenario PATH  scenario (default tools/validation/scenarios/lander_descent.yaml)\n"
    "  --segments N     segments around the axis of tessellated round primitives (default 16,\n"
    "                   even, in [8, 64]; hadald uses 32)\n"
    "  --magnus C_M     overrides fluid.hydrodynamics.magnus [s] of the configured run (a negative\n"
    "                   value reverses the force, for experiments with its sign)\n"
    "Runs the free-fall descent with lift and Magnus as configured and with both off; prints JSON.\n";

constexpr double kSampleInterval = 0.5;  // [s of sim time]
constexpr double kSeabedClearance = 100.0;  // seabed plane below the target depth [m]
constexpr double kMinDescentRate = 0.05;    // a run slower than this on average is abandoned [m/s]


struct Sample {
  double t = 0.0;
  Eigen::Vector3d p_WBcm = Eigen::Vector3d::Zero();
  double depth = 0.0;
  double yaw = 0.0, roll = 0.0, pitch = 0.0;  // [rad], yaw unwrapped
};

struct RunSummary {
  bool reached = false;
  double descent_time = 0.0;        // [s]
  double terminal_velocity = 0.0;   // mean descent rate over the last 20 % of the depth [m/s]
  double spin_rate = 0.0;           // mean yaw rate over the same window [rad/s]
  Eigen::Vector2d final_xy = Eigen::Vector2d::Zero();  // centre of mass minus its start [m]
  double final_offset = 0.0;        // |final_xy| [m]
  double max_offset = 0.0;          // [m]
  double final_yaw = 0.0;           // unwrapped, from the start [rad]
  double max_tilt = 0.0;            // [rad], after the first 10 s (release transient excluded)
};

struct Run {
  std::string name;
  std::vector<Sample> samples;
  RunSummary summary;
  Vector6d added_mass_diagonal = Vector6d::Zero();  // M_A0 at the surface [kg x3, kg m^2 x3]
};

// Descends until the centre of mass is `depth` below the surface or the time limit passes.
Run descend(const Model& model, double depth, const std::string& name) {
  Run run;
  run.name = name;
  Simulation sim(model);
  run.added_mass_diagonal = sim.added_mass(0).diagonal();
  const Eigen::Vector3d p_BBcm = sim.mass_properties(0).p_BBcm;
  const double surface_z = model.world.water.surface_z;
  const double dt = model.world.step_size();
  const auto sample_every = static_cast<std::uint64_t>(std::max(1.0, std::round(kSampleInterval / dt)));
  const double t_limit = 600.0 + depth / kMinDescentRate;
  Unwrapper unwrap;
  Eigen::Vector3d p_start = Eigen::Vector3d::Zero();
  double next_report = 500.0;
  auto record = [&]() {
    const RigidBodyState& body = sim.state().vehicles[0].body;
    const Eigen::Matrix3d R = body.X_WB.linear();
    Sample s;
    s.t = sim.time();
    s.p_WBcm = body.X_WB * p_BBcm;
    s.depth = surface_z - s.p_WBcm.z();
    s.yaw = unwrap(yaw_of(R));
    s.roll = std::atan2(R(2, 1), R(2, 2));
    s.pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
    if (run.samples.empty()) p_start = s.p_WBcm;
    const Eigen::Vector2d xy = (s.p_WBcm - p_start).head<2>();
    run.summary.max_offset = std::max(run.summary.max_offset, xy.norm());
    if (s.t > 10.0) run.summary.max_tilt = std::max(run.summary.max_tilt, tilt_of(R));
    run.samples.push_back(s);
    return s.depth;
  };
  record();
  for (;;) {
    sim.step();
    const RigidBodyState& body = sim.state().vehicles[0].body;
    const double d = surface_z - (body.X_WB * p_BBcm).z();
    const bool done = d >= depth;
    if (done || sim.state().step_count % sample_every == 0) record();
    if (d >= next_report) {
      std::fprintf(stderr, "%s: %s: %.0f m at t = %.0f s\n", kTool, name.c_str(), d, sim.time());
      next_report += 500.0;
    }
    if (done) {
      run.summary.reached = true;
      break;
    }
    if (sim.time() > t_limit) break;
  }
  RunSummary& s = run.summary;
  const Sample& last = run.samples.back();
  s.descent_time = last.t;
  s.final_xy = (last.p_WBcm - p_start).head<2>();
  s.final_offset = s.final_xy.norm();
  s.final_yaw = last.yaw - run.samples.front().yaw;
  // Window: the last 20 % of the depth reached.
  const double d0 = run.samples.front().depth + 0.8 * (last.depth - run.samples.front().depth);
  std::size_t k = 0;
  while (k + 1 < run.samples.size() && run.samples[k].depth < d0) ++k;
  const Sample& first = run.samples[k];
  if (last.t > first.t) {
    s.terminal_velocity = (last.depth - first.depth) / (last.t - first.t);
    s.spin_rate = (last.yaw - first.yaw) / (last.t - first.t);
  }
  return run;
}

// Each link without a mesh gets its collision primitives tessellated with `segments` as its link mesh
// (vertices in L), which Simulation then uses as that link's hydrodynamic mesh.
void tessellate_links(VehicleSpec& spec, int segments) {
  for (LinkSpec& link : spec.links) {
    if (link.mesh || link.collisions.empty()) continue;
    auto mesh = std::make_shared<geometry::TriangleMesh>();
    for (const CollisionShape& shape : link.collisions) {
      geometry::append_transformed(geometry::tessellate(shape, segments), shape.X_LG, mesh.get());
    }
    LinkMesh link_mesh;
    link_mesh.file = "(collision primitives, " + std::to_string(segments) + " segments)";
    link_mesh.mesh = mesh;
    link_mesh.closed = true;  // each primitive is closed
    link.mesh = link_mesh;
  }
}

struct ClosedForm {
  std::size_t faces = 0;
  double volume = 0.0;            // enclosed volume of the mesh [m^3]
  double drag_area = 0.0;         // sum A [C_D max(-n_z,0)^3 + C_f (1-n_z^2)^1.5] [m^2]
  double frontal_area = 0.0;      // sum A max(-n_z, 0) (projected from below) [m^2]
};

ClosedForm closed_form_terms(const geometry::TriangleMesh& mesh,
                             const physics::HydrodynamicCoefficients& k) {
  ClosedForm c;
  c.faces = mesh.num_triangles();
  for (std::size_t f = 0; f < mesh.num_triangles(); ++f) {
    Eigen::Vector3d v[3];
    for (int j = 0; j < 3; ++j) {
      const std::uint32_t i = mesh.indices[3 * f + j];
      v[j] = Eigen::Vector3d(mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]);
    }
    const Eigen::Vector3d cross = (v[1] - v[0]).cross(v[2] - v[0]);
    const double area = 0.5 * cross.norm();
    c.volume += v[0].dot(v[1].cross(v[2])) / 6.0;
    if (!(area > 0.0)) continue;
    const double nz = cross.z() / cross.norm();
    const double down = std::max(-nz, 0.0);
    c.drag_area += area * (k.drag * down * down * down + k.skin_friction * std::pow(1.0 - nz * nz, 1.5));
    c.frontal_area += area * down;
  }
  return c;
}

double terminal_velocity(double mass, double volume, double rho, double g, double drag_area) {
  const double net = (mass - rho * volume) * g;
  return net > 0.0 && drag_area > 0.0 ? std::sqrt(2.0 * net / (rho * drag_area)) : 0.0;
}

std::string run_json(const Run& run) {
  const RunSummary& s = run.summary;
  JsonObject o(2);
  o.boolean("reached", s.reached)
      .number("descent_time_s", s.descent_time)
      .number("terminal_velocity_m_s", s.terminal_velocity)
      .number("spin_rate_deg_s", s.spin_rate * kDegPerRad)
      .raw("final_xy_m", "[" + json_rounded(s.final_xy.x()) + ", " + json_rounded(s.final_xy.y()) + "]")
      .number("final_offset_m", s.final_offset)
      .number("max_offset_m", s.max_offset)
      .number("final_yaw_deg", s.final_yaw * kDegPerRad)
      .number("max_tilt_deg", s.max_tilt * kDegPerRad);
  return o.str();
}

std::string write_csv(const std::vector<const Run*>& runs, const std::string& path) {
  std::ofstream out(path);
  if (!out) return path + ": cannot write the CSV";
  out << "run,t_s,x_m,y_m,z_m,depth_m,yaw_deg,roll_deg,pitch_deg,descent_rate_m_s,spin_deg_s\n";
  char line[320];
  for (const Run* run : runs) {
    const auto& v = run->samples;
    for (std::size_t i = 0; i < v.size(); ++i) {
      // Rates by central differences (one-sided at the ends).
      const std::size_t a = i == 0 ? 0 : i - 1, b = i + 1 < v.size() ? i + 1 : i;
      const double span = v[b].t - v[a].t;
      const double rate = span > 0.0 ? (v[b].depth - v[a].depth) / span : 0.0;
      const double spin = span > 0.0 ? (v[b].yaw - v[a].yaw) / span * kDegPerRad : 0.0;
      std::snprintf(line, sizeof(line), "%s,%.3f,%.6f,%.6f,%.6f,%.6f,%.5f,%.5f,%.5f,%.6f,%.5f\n",
                    run->name.c_str(), v[i].t, v[i].p_WBcm.x(), v[i].p_WBcm.y(), v[i].p_WBcm.z(),
                    v[i].depth, v[i].yaw * kDegPerRad, v[i].roll * kDegPerRad,
                    v[i].pitch * kDegPerRad, rate, spin);
      out << line;
    }
  }
  out.close();
  return out ? std::string() : path + ": write failed";
}

std::string write_figure(const Run& on, const Run& off, double depth, const std::string& path) {
  namespace plot = hadal::validation::plot;
  plot::Figure figure;
  char title[128];
  std::snprintf(title, sizeof(title), "Free-fall lander to %.0f m: lift and Magnus on vs off", depth);
  figure.title = title;
  figure.panel_width = 620;
  figure.panel_height = 560;

  auto track = [](const Run& run, const std::string& label, plot::Color color, bool dashed) {
    plot::Series s;
    s.label = label;
    s.color = color;
    s.dashed = dashed;
    const Eigen::Vector3d p0 = run.samples.front().p_WBcm;
    for (const Sample& x : run.samples) {
      s.x.push_back(x.p_WBcm.x() - p0.x());
      s.y.push_back(x.p_WBcm.y() - p0.y());
    }
    return s;
  };
  auto end_marker = [](const plot::Series& s, plot::Color color) {
    plot::Series m;
    m.x = {s.x.back()};
    m.y = {s.y.back()};
    m.color = color;
    m.line_width = 0.0;
    m.marker = plot::Marker::kCircle;
    m.marker_size = 5;
    return m;
  };
  const plot::Color c_on = plot::palette(1), c_off = plot::palette(0);
  plot::Panel xy;
  xy.title = "XY track of the centre of mass";
  xy.x.label = "east [m]";
  xy.y.label = "north [m]";
  xy.equal_aspect = true;
  xy.legend = plot::LegendPosition::kTopLeft;
  const plot::Series s_on = track(on, "lift + Magnus", c_on, false);
  const plot::Series s_off = track(off, "no lift, no Magnus", c_off, true);
  plot::Series start;
  start.label = "release";
  start.x = {0.0};
  start.y = {0.0};
  start.color = plot::palette(7);
  start.line_width = 0.0;
  start.marker = plot::Marker::kSquare;
  xy.series = {s_on, s_off, end_marker(s_on, c_on), end_marker(s_off, c_off), start};

  plot::Panel yaw;
  yaw.title = "Yaw vs depth";
  yaw.x.label = "depth [m]";
  yaw.y.label = "yaw (unwrapped) [deg]";
  yaw.legend = plot::LegendPosition::kTopLeft;
  for (const Run* run : {&on, &off}) {
    plot::Series s;
    s.label = run == &on ? "lift + Magnus" : "no lift, no Magnus";
    s.color = run == &on ? c_on : c_off;
    s.dashed = run == &off;
    const double yaw0 = run->samples.front().yaw;
    for (const Sample& x : run->samples) {
      s.x.push_back(x.depth);
      s.y.push_back((x.yaw - yaw0) * kDegPerRad);
    }
    yaw.series.push_back(s);
  }
  figure.panels = {xy, yaw};
  return plot::write_png(figure, path);
}

}  // namespace

int main(int argc, char** argv) {
  double depth = 3000.0;
  double segments = 16;
  std::optional<double> magnus;
  std::string out_dir = ".";
  std::string scenario = HADAL_SOURCE_DIR "/tools/validation/scenarios/lander_descent.yaml";
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--depth", &depth, NumberRange::left_open(0.0, 10900.0))
      .text("--out", &out_dir)
      .text("--scenario", &scenario)
      .option("--segments",
              [&](const std::string& value) -> std::string {
                if (!parse_number(value, &segments) || segments != std::floor(segments) || segments < 8 ||
                    segments > 64 || std::fmod(segments, 2.0) != 0.0) {
                  return "--segments must be an even integer in [8, 64] (got '" + value + "')";
                }
                return "";
              })
      .option("--magnus", [&](const std::string& value) {
        double magnus_value = 0.0;
        const std::string error = tools::read_number("--magnus", value, NumberRange::any(), &magnus_value);
        if (error.empty()) magnus = magnus_value;
        return error;
      });
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  std::optional<Model> loaded = prepare_run(out_dir, scenario, kTool);
  if (!loaded) return 1;
  Model model = std::move(*loaded);
  if (model.vehicles.empty() || model.vehicles[0].fluid.model != FluidModelType::kSurface) {
    std::fprintf(stderr, "%s: %s: vehicle 0 must use fluid.model: surface\n", kTool, scenario.c_str());
    return 1;
  }
  // The seabed is a plane below the target depth (the descent ends before it).
  model.world.seabed = SeabedSpec{};
  model.world.seabed.z = model.world.water.surface_z - depth - kSeabedClearance;
  if (magnus) model.vehicles[0].fluid.hydrodynamics.magnus = *magnus;
  if (static_cast<int>(segments) != geometry::kPrimitiveSegments) {
    tessellate_links(model.vehicles[0], static_cast<int>(segments));
  }

  Model model_off = model;
  model_off.vehicles[0].fluid.hydrodynamics.lift = 0.0;
  model_off.vehicles[0].fluid.hydrodynamics.magnus = 0.0;

  const auto wall_start = std::chrono::steady_clock::now();
  Run on, off;
  double mass = 0.0;
  try {
    mass = physics::composite_mass_properties(model.vehicles[0].links).mass;
    on = descend(model, depth, "lift_magnus");
    off = descend(model_off, depth, "no_lift_magnus");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  const VehicleSpec& lander = model.vehicles[0];
  const ClosedForm cf = closed_form_terms(hydrodynamic_mesh_B(lander), lander.fluid.hydrodynamics);
  const physics::Ocean ocean(model.world);
  const double g = model.world.gravity_W.norm();
  const double rho_surface = ocean.density(0.0), rho_depth = ocean.density(depth);

  const std::string png = join_path(out_dir, "lander_lift_magnus.png");
  const std::string csv = join_path(out_dir, "lander_lift_magnus.csv");
  std::string error = write_figure(on, off, depth, png);
  if (error.empty()) error = write_csv({&on, &off}, csv);
  if (!error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }

  JsonObject closed(2);
  closed.number("at_surface_m_s", terminal_velocity(mass, cf.volume, rho_surface, g, cf.drag_area))
      .number("at_depth_m_s", terminal_velocity(mass, cf.volume, rho_depth, g, cf.drag_area))
      .number("drag_area_m2", cf.drag_area)
      .number("frontal_area_m2", cf.frontal_area);
  JsonObject json;
  json.text("scenario", scenario)
      .number("depth_m", depth)
      .number("physics_rate_hz", model.world.physics_rate_hz)
      .raw("faces", std::to_string(cf.faces))
      .raw("segments", std::to_string(static_cast<int>(segments)))
      .number("mass_kg", mass)
      .number("displaced_volume_m3", cf.volume)
      .number("net_weight_at_depth_N", (mass - rho_depth * cf.volume) * g)
      .raw("added_mass_diagonal", [&] {
        std::string list = "[";
        for (int k = 0; k < 6; ++k) list += (k ? ", " : "") + json_rounded(on.added_mass_diagonal[k], 4);
        return list + "]";
      }())
      .number("lift_coefficient", lander.fluid.hydrodynamics.lift)
      .number("magnus_coefficient_s", lander.fluid.hydrodynamics.magnus)
      .raw("closed_form_terminal_velocity", closed.str())
      .raw("with_lift_magnus", run_json(on))
      .raw("without_lift_magnus", run_json(off))
      .number("final_offset_difference_m", on.summary.final_offset - off.summary.final_offset)
      .number("final_separation_m", (on.summary.final_xy - off.summary.final_xy).norm())
      .number("final_yaw_difference_deg", (on.summary.final_yaw - off.summary.final_yaw) * kDegPerRad)
      .number("wall_time_s", wall, 3)
      .text("png", png)
      .text("csv", csv);
  std::printf("%s\n", json.str().c_str());
  return on.summary.reached && off.summary.reached ? 0 : 3;
}
