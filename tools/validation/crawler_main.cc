// hadal-validate-crawler: the paper's soil-vehicle force figure (Seabed Interaction and Terramechanics
// Modeling): a tracked crawler on soft sediment starts from rest, accelerates and drives straight at a
// steady speed. Longitudinally, the soil's traction on its tracks first exceeds the resistance (the water's
// drag), the difference accelerating the vehicle; as the speed settles the two balance. Laterally the
// forces of the two tracks stay symmetric about zero: nothing pushes sideways.
//
//   hadal-validate-crawler [--duration 20] [--setpoint 0.6] [--out DIR] [--scenario PATH]
//
// Default scenario configs/scenarios/crawler.yaml (configs/vehicles/tracked_crawler.yaml on the deep-sea
// ooze). Its schedule is replaced: 2 s at rest (the tracks settle into the sediment), then both tracks at
// --setpoint for --duration seconds. Forces are in the heading frame H (x_H the body's x on the horizontal
// plane, z_H up), in which gravity, buoyancy and the flat seabed's normal force have no horizontal part
// even while the hull pitches (the water's drag above the tracks' traction pitches it nose-up a little):
//   traction    the soil's shear on the track links along x_H (each track and their sum)
//   resistance  minus everything else the force elements add along x_H: the water's drag and skin
//               friction (the tracks themselves add no force)
//   net         traction - resistance, which accelerates the vehicle and its added mass
//   lateral     the soil's shear on each track along y_H, and the fluid's side force
// Writes into --out (default "."):
//   crawler_forces.png  left: longitudinal traction, resistance, net force and speed (x 1000); middle: the
//                       same zoomed to the steady forces; right: lateral forces of both tracks and the water
//   crawler_forces.csv  t_s,speed_m_s,traction_port_N,traction_starboard_N,traction_N,resistance_N,
//                       lateral_port_N,lateral_starboard_N,lateral_fluid_N,sinkage_m,slip
// and prints one JSON object (stdout): steady speed, belt speed, slip, traction and resistance at the end,
// the largest net force while accelerating, the largest lateral force, the sinkage and its closed form.
//
// Exit status: 0 success; 1 the scenario does not load, the simulation throws or an output cannot be
// written; 2 usage error.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "hadal/core/simulation.h"
#include "hadal/physics/terramechanics.h"
#include "hadal/physics/track.h"
#include "plot.h"
#include "validation_support.h"

namespace {

using namespace hadal;
using namespace hadal::validation;

constexpr const char* kTool = "hadal-validate-crawler";
constexpr const char* kUsage =
    "usage: hadal-validate-crawler [--duration S] [--setpoint U] [--out DIR] [--scenario PATH]\n"
    "  --duration S     seconds of driving after 2 s at rest (default 20, in (0, 3600])\n"
    "  --setpoint U     both tracks' normalised belt speed (default 0.6, in (0, 1])\n"
    "  --out DIR        output directory for crawler_forces.{png,csv} (default .)\n"
    "  --scenario PATH  scenario with a crawler as its first vehicle (default configs/scenarios/crawler.yaml)\n"
    "Drives the crawler straight from rest; prints JSON.\n";

constexpr double kSettle = 2.0;           // [s] at rest before driving
constexpr double kSampleInterval = 0.05;  // [s]

struct Sample {
  double t, speed, traction_port, traction_starboard, resistance, lateral_port, lateral_starboard, lateral_fluid,
      sinkage, slip;
  double traction() const { return traction_port + traction_starboard; }
};

}  // namespace

int main(int argc, char** argv) {
  double duration = 20.0, setpoint = 0.6;
  std::string out_dir = ".";
  std::string scenario = HADAL_SOURCE_DIR "/configs/scenarios/crawler.yaml";
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--duration", &duration, NumberRange::left_open(0.0, 3600.0))
      .number("--setpoint", &setpoint, NumberRange::left_open(0.0, 1.0))
      .text("--out", &out_dir)
      .text("--scenario", &scenario);
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  std::optional<Model> loaded = prepare_run(out_dir, scenario, kTool);
  if (!loaded) return 1;
  Model model = std::move(*loaded);
  if (model.vehicles.empty() || model.vehicles[0].seabed_contact != SeabedContact::kSoil) {
    std::fprintf(stderr, "%s: %s: the first vehicle must have seabed_contact soil\n", kTool, scenario.c_str());
    return 1;
  }
  VehicleSpec& crawler = model.vehicles[0];
  // The tracks: their indices in the control vector and links, port (y > 0) first.
  std::vector<std::size_t> tracks;
  for (std::size_t k = 0; k < crawler.actuators.size(); ++k) {
    if (std::holds_alternative<physics::TrackActuator::Spec>(crawler.actuators[k].kind)) tracks.push_back(k);
  }
  if (tracks.size() != 2 || crawler.num_controls() != 2) {
    std::fprintf(stderr, "%s: %s: the crawler must have exactly two tracks and no other actuator\n", kTool,
                 scenario.c_str());
    return 1;
  }
  const auto link_y = [&](std::size_t k) {
    return crawler.links[static_cast<std::size_t>(crawler.actuators[k].link_index)].X_BL.translation().y();
  };
  if (link_y(tracks[0]) < link_y(tracks[1])) std::swap(tracks[0], tracks[1]);
  const std::size_t port_link = static_cast<std::size_t>(crawler.actuators[tracks[0]].link_index);
  const std::size_t starboard_link = static_cast<std::size_t>(crawler.actuators[tracks[1]].link_index);
  crawler.schedule = {SetpointKeyframe{0.0, {0.0, 0.0}}, SetpointKeyframe{kSettle, {setpoint, setpoint}}};
  const auto& drive = std::get<physics::TrackActuator::Spec>(crawler.actuators[tracks[0]].kind);
  const double belt_speed = setpoint * drive.max_speed_rad_s * drive.sprocket_radius;

  std::vector<Sample> samples;
  double sinkage_closed_form = 0.0;
  try {
    Simulation sim(model);
    const double dt = model.world.step_size();
    const double seabed_z = model.world.seabed.z;
    const auto steps = static_cast<long>(std::lround((kSettle + duration) / dt));
    double next_sample = 0.0;
    for (long k = 0; k < steps; ++k) {
      sim.step();
      const SimState& state = sim.state();
      if (state.time + 1e-9 < next_sample) continue;
      next_sample += kSampleInterval;
      const RigidBodyState& body = state.vehicles[0].body;
      // The heading frame H: x_H the body's x on the horizontal plane, z_H up (gravity, buoyancy and the
      // flat seabed's normal force have no part along x_H, y_H even when the hull pitches).
      const Eigen::Vector3d x_H = Eigen::Vector3d(body.X_WB.linear()(0, 0), body.X_WB.linear()(1, 0), 0.0).normalized();
      Eigen::Matrix3d R_HW;
      R_HW.row(0) = x_H.transpose();
      R_HW.row(1) = Eigen::Vector3d::UnitZ().cross(x_H).transpose();
      R_HW.row(2) = Eigen::Vector3d::UnitZ().transpose();
      const Eigen::Matrix3d& R_BW = R_HW;
      const physics::SoilWrench& soil = *sim.soil_wrench(0);
      const Eigen::Vector3d other_B = R_BW * (sim.applied_wrench(0).f_W - soil.f_W);
      const Eigen::Vector3d port_B = R_BW * soil.link_shear_force_W[port_link];
      const Eigen::Vector3d starboard_B = R_BW * soil.link_shear_force_W[starboard_link];
      const double speed = (R_BW * body.v_WB).x();
      const double belt = std::get<physics::TrackActuator::State>(state.vehicles[0].actuators[tracks[0]]).belt_speed;
      samples.push_back(Sample{state.time, speed, port_B.x(), starboard_B.x(), -other_B.x(), port_B.y(),
                               starboard_B.y(), other_B.y(), seabed_z - body.X_WB.translation().z(),
                               belt > 1e-6 ? 1.0 - speed / belt : 0.0});
    }
    // Closed-form static sinkage of one track under half the weight in water (flat ground run of the
    // track link's box: length x width).
    const LinkSpec& track_link = crawler.links[port_link];
    if (!track_link.collisions.empty() && track_link.collisions[0].type == CollisionShapeType::kBox) {
      double mass = 0.0, volume = 0.0;
      for (const LinkSpec& link : crawler.links) {
        mass += link.mass;
        for (const CollisionShape& shape : link.collisions) {
          if (shape.type == CollisionShapeType::kBox) volume += shape.box_size.prod();
        }
      }
      const Eigen::Vector3d size = track_link.collisions[0].box_size;
      const double W = (mass - model.world.water.density * volume) * model.world.gravity_W.norm();
      sinkage_closed_form = model.world.soil.parameters.static_sinkage(0.5 * W, size.x() * size.y(),
                                                                        std::min(size.x(), size.y()));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }

  const std::string csv_path = join_path(out_dir, "crawler_forces.csv");
  {
    std::ofstream csv(csv_path);
    csv << "t_s,speed_m_s,traction_port_N,traction_starboard_N,traction_N,resistance_N,lateral_port_N,"
           "lateral_starboard_N,lateral_fluid_N,sinkage_m,slip\n";
    for (const Sample& s : samples) {
      csv << json_number(s.t) << ',' << json_number(s.speed) << ',' << json_number(s.traction_port) << ','
          << json_number(s.traction_starboard) << ',' << json_number(s.traction()) << ','
          << json_number(s.resistance) << ',' << json_number(s.lateral_port) << ','
          << json_number(s.lateral_starboard) << ',' << json_number(s.lateral_fluid) << ','
          << json_number(s.sinkage) << ',' << json_number(s.slip) << '\n';
    }
    if (!csv) {
      std::fprintf(stderr, "%s: %s: cannot write\n", kTool, csv_path.c_str());
      return 1;
    }
  }

  namespace plot = hadal::validation::plot;
  plot::Figure figure;
  char title[200];
  std::snprintf(title, sizeof(title), "Soil-vehicle forces of a tracked crawler on %s, belts at %.2f m/s",
                model.world.soil.preset.empty() ? "soil" : model.world.soil.preset.c_str(), belt_speed);
  figure.title = title;
  figure.panel_width = 560;
  figure.panel_height = 460;
  const auto series = [&](const std::string& label, int color, bool dashed, auto value) {
    plot::Series s;
    s.label = label;
    s.color = plot::palette(color);
    s.dashed = dashed;
    for (const Sample& sample : samples) {
      s.x.push_back(sample.t);
      s.y.push_back(value(sample));
    }
    return s;
  };
  plot::Panel longitudinal;
  longitudinal.title = "Longitudinal (x_H)";
  longitudinal.x.label = "time [s]";
  longitudinal.y.label = "force [N]";
  longitudinal.series = {
      series("traction (both tracks)", 0, false, [](const Sample& s) { return s.traction(); }),
      series("resistance (water)", 1, false, [](const Sample& s) { return s.resistance; }),
      series("net = traction - resistance", 2, true, [](const Sample& s) { return s.traction() - s.resistance; }),
      series("speed x 1000 [m/s]", 7, true, [](const Sample& s) { return 1000.0 * s.speed; })};
  plot::Panel lateral;
  lateral.title = "Lateral (y_H)";
  lateral.x.label = "time [s]";
  lateral.y.label = "force [N]";
  lateral.series = {series("port track", 0, false, [](const Sample& s) { return s.lateral_port; }),
                    series("starboard track", 1, true, [](const Sample& s) { return s.lateral_starboard; }),
                    series("water", 2, false, [](const Sample& s) { return s.lateral_fluid; })};
  lateral.legend = plot::LegendPosition::kBottomRight;
  // The same, zoomed to the steady forces: the acceleration's peak is ~50 times the water's drag.
  plot::Panel steady = longitudinal;
  steady.title = "Longitudinal, zoomed to steady driving";
  const double scale = std::max(std::abs(samples.back().resistance), 1.0);
  steady.y.min = -2.0 * scale;
  steady.y.max = 4.0 * scale;
  steady.legend = plot::LegendPosition::kBottomRight;
  steady.series.pop_back();  // the speed is off this scale
  figure.panels = {longitudinal, steady, lateral};
  const std::string png_path = join_path(out_dir, "crawler_forces.png");
  if (const std::string error = plot::write_png(figure, png_path); !error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }

  // Summary: the last sample is steady; the net force's peak is while accelerating.
  const Sample& last = samples.back();
  double peak_net = 0.0, peak_lateral = 0.0;
  for (const Sample& s : samples) {
    peak_net = std::max(peak_net, s.traction() - s.resistance);
    peak_lateral = std::max({peak_lateral, std::abs(s.lateral_port + s.lateral_starboard + s.lateral_fluid)});
  }
  JsonObject json;
  json.text("scenario", scenario);
  json.number("belt_speed_m_s", belt_speed);
  json.number("steady_speed_m_s", last.speed);
  json.number("steady_slip", last.slip);
  json.number("steady_traction_N", last.traction());
  json.number("steady_resistance_N", last.resistance);
  json.number("peak_net_force_N", peak_net);
  json.number("peak_lateral_force_N", peak_lateral);
  json.number("sinkage_m", last.sinkage);
  json.number("sinkage_closed_form_m", sinkage_closed_form);
  json.text("png", png_path);
  json.text("csv", csv_path);
  std::printf("%s\n", json.str().c_str());
  return 0;
}
