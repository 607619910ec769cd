// hadal-validate-arm: an ROV swinging its arm in water moves and tilts (issue 40's coupling figure).
// The vehicle hovers, its arm stowed (folded down under its front); at --start its position controllers
// unfold the arm straight forward. The base, free in the water with its thrusters off, answers the arm: it
// pitches nose-down as the arm's wet weight moves forward of the centre of buoyancy (the statics), and it
// moves and rocks while the arm swings (the reaction of the arm's acceleration and of the water the arm
// drags). The second run is the same vehicle without the coupling: a base that does not feel its arm (a
// kinematic arm, what a simulator without vehicle-arm dynamics shows), which stays at its trim.
//
//   hadal-validate-arm [--duration 30] [--start 5] [--out DIR] [--scenario PATH]
//
// Default scenario tools/validation/scenarios/arm_reaction.yaml. The first vehicle is the ROV; its joint
// controllers are commanded to zero (the arm straight out) at --start. Writes into --out (default "."):
//   arm_reaction.png  base pitch, surge (x) and heave (z) against time, coupled and not; the joint angles
//   arm_reaction.csv  run,t_s,pitch_deg,x_m,z_m,q_0_deg,q_1_deg,...
// and prints one JSON object (stdout): per run the largest pitch and displacement, and the pitch at the end.
//
// Exit status: 0 success; 1 the scenario does not load, has no articulated first vehicle, the simulation
// throws or an output cannot be written; 2 usage error.
#include <algorithm>
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

constexpr const char* kTool = "hadal-validate-arm";
constexpr const char* kUsage =
    "usage: hadal-validate-arm [--duration S] [--start S] [--out DIR] [--scenario PATH]\n"
    "  --duration S     seconds simulated (default 30, in (0, 600])\n"
    "  --start S        when the arm starts to unfold (default 5, in [0, 600])\n"
    "  --out DIR        output directory for arm_reaction.{png,csv} (default .)\n"
    "  --scenario PATH  scenario with an articulated vehicle first (default\n"
    "                   tools/validation/scenarios/arm_reaction.yaml)\n"
    "Unfolds the ROV's arm, with and without the vehicle-arm coupling; prints JSON.\n";

constexpr double kSampleInterval = 0.02;  // [s]

struct Sample {
  double t, pitch_deg, x, z;
  std::vector<double> q_deg;
};

// Pitch of B about its y axis [deg]: nose down positive (x_B turning towards -z_W).
double pitch_deg(const Eigen::Matrix3d& R_WB) { return std::asin(std::clamp(-R_WB(2, 0), -1.0, 1.0)) * kDegPerRad; }

}  // namespace

int main(int argc, char** argv) {
  double duration = 30.0, start = 5.0;
  std::string out_dir = ".";
  std::string scenario = HADAL_SOURCE_DIR "/tools/validation/scenarios/arm_reaction.yaml";
  CommandLine command_line = make_command_line(kTool, kUsage);
  command_line.number("--duration", &duration, NumberRange::left_open(0.0, 600.0))
      .number("--start", &start, NumberRange::closed(0.0, 600.0))
      .text("--out", &out_dir)
      .text("--scenario", &scenario);
  if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
  std::optional<Model> loaded = prepare_run(out_dir, scenario, kTool);
  if (!loaded) return 1;
  const Model model = std::move(*loaded);
  if (model.vehicles.empty() || model.vehicles[0].joint_controllers.empty()) {
    std::fprintf(stderr, "%s: %s: the first vehicle must have joint controllers\n", kTool, scenario.c_str());
    return 1;
  }
  const VehicleSpec& rov = model.vehicles[0];

  std::vector<std::vector<Sample>> runs(2);
  const char* const names[2] = {"coupled", "without coupling"};
  try {
    for (int run = 0; run < 2; ++run) {
      Simulation sim(model);
      const double dt = model.world.step_size();
      const auto steps = static_cast<long>(std::lround(duration / dt));
      bool commanded = false;
      double next_sample = 0.0;
      for (long k = 0; k <= steps; ++k) {
        if (!commanded && sim.time() + 1e-9 >= start) {
          commanded = true;
          // Without the coupling the base never feels the arm: as if it had not moved.
          if (run == 0) {
            for (const physics::JointControllerSpec& controller : rov.joint_controllers) {
              const std::string error =
                  sim.set_joint_commands(0, controller.name, std::vector<double>(controller.joints.size(), 0.0));
              if (!error.empty()) throw std::runtime_error(error);
            }
          }
        }
        if (sim.time() + 1e-9 >= next_sample) {
          next_sample += kSampleInterval;
          const VehicleState& v = sim.state().vehicles[0];
          Sample s{sim.time(), pitch_deg(v.body.X_WB.linear()), v.body.X_WB.translation().x(),
                   v.body.X_WB.translation().z(), {}};
          for (double q : v.joint_positions) s.q_deg.push_back(q * kDegPerRad);
          runs[static_cast<std::size_t>(run)].push_back(std::move(s));
        }
        if (k < steps) sim.step();
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kTool, e.what());
    return 1;
  }

  const std::string csv_path = join_path(out_dir, "arm_reaction.csv");
  {
    std::ofstream csv(csv_path);
    csv << "run,t_s,pitch_deg,x_m,z_m";
    for (std::size_t j = 0; j < runs[0][0].q_deg.size(); ++j) csv << ",q_" << j << "_deg";
    csv << '\n';
    for (int run = 0; run < 2; ++run) {
      for (const Sample& s : runs[static_cast<std::size_t>(run)]) {
        csv << (run == 0 ? "coupled" : "uncoupled") << ',' << json_number(s.t) << ',' << json_number(s.pitch_deg)
            << ',' << json_number(s.x) << ',' << json_number(s.z);
        for (double q : s.q_deg) csv << ',' << json_number(q);
        csv << '\n';
      }
    }
    if (!csv) {
      std::fprintf(stderr, "%s: %s: cannot write\n", kTool, csv_path.c_str());
      return 1;
    }
  }

  namespace plot = hadal::validation::plot;
  plot::Figure figure;
  figure.title = "An ROV unfolding its arm in water at t = " + json_rounded(start, 3) +
                 " s: the base's answer, with and without the vehicle-arm coupling";
  figure.panel_width = 480;
  figure.panel_height = 400;
  const auto base_panel = [&](const std::string& title, const std::string& label, auto value) {
    plot::Panel panel;
    panel.title = title;
    panel.x.label = "time [s]";
    panel.y.label = label;
    for (int run = 0; run < 2; ++run) {
      plot::Series s;
      s.label = names[run];
      s.color = plot::palette(run);
      s.dashed = run == 1;
      const std::vector<Sample>& samples = runs[static_cast<std::size_t>(run)];
      for (const Sample& sample : samples) {
        s.x.push_back(sample.t);
        s.y.push_back(value(sample, samples.front()));
      }
      panel.series.push_back(std::move(s));
    }
    return panel;
  };
  plot::Panel pitch = base_panel("Base pitch (nose down +)", "pitch [deg]",
                                 [](const Sample& s, const Sample&) { return s.pitch_deg; });
  plot::Panel surge =
      base_panel("Base surge", "x - x(0) [m]", [](const Sample& s, const Sample& s0) { return s.x - s0.x; });
  plot::Panel heave =
      base_panel("Base heave", "z - z(0) [m]", [](const Sample& s, const Sample& s0) { return s.z - s0.z; });
  plot::Panel joints;
  joints.title = "Arm joints (coupled run)";
  joints.x.label = "time [s]";
  joints.y.label = "q [deg]";
  for (std::size_t j = 0; j < runs[0][0].q_deg.size(); ++j) {
    plot::Series s;
    std::size_t dof = 0;
    for (const LinkSpec& link : rov.links) {
      if (link.joint.type == JointType::kFixed) continue;
      if (dof++ == j) s.label = joint_name(link);
    }
    s.color = plot::palette(static_cast<int>(j) + 2);
    for (const Sample& sample : runs[0]) {
      s.x.push_back(sample.t);
      s.y.push_back(sample.q_deg[j]);
    }
    joints.series.push_back(std::move(s));
  }
  figure.panels = {pitch, surge, heave, joints};
  const std::string png_path = join_path(out_dir, "arm_reaction.png");
  if (const std::string error = plot::write_png(figure, png_path); !error.empty()) {
    std::fprintf(stderr, "%s: %s\n", kTool, error.c_str());
    return 1;
  }

  JsonObject json;
  json.text("scenario", scenario);
  for (int run = 0; run < 2; ++run) {
    const std::vector<Sample>& samples = runs[static_cast<std::size_t>(run)];
    double peak_pitch = 0.0, peak_displacement = 0.0;
    for (const Sample& s : samples) {
      peak_pitch = std::max(peak_pitch, std::abs(s.pitch_deg));
      peak_displacement = std::max(peak_displacement, std::hypot(s.x - samples.front().x, s.z - samples.front().z));
    }
    const std::string prefix = run == 0 ? "coupled_" : "uncoupled_";
    json.number(prefix + "peak_pitch_deg", peak_pitch);
    json.number(prefix + "final_pitch_deg", samples.back().pitch_deg);
    json.number(prefix + "peak_displacement_m", peak_displacement);
  }
  json.text("png", png_path);
  json.text("csv", csv_path);
  std::printf("%s\n", json.str().c_str());
  return 0;
}
