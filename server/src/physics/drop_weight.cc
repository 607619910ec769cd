#include "hadal/physics/drop_weight.h"

#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/physics/ocean.h"

namespace hadal::physics {

using config::Range;

const config::KeyTable<DropWeightActuator::Spec>& DropWeightActuator::keys() {
  return config::declare_keys<Spec>([](config::KeyTable<Spec>& t) {
    t.describe("drop_weight", "ballast let go on command, at an altitude or at a time, for good");
    t.vector("position", &Spec::p_LW).required().unit("m").doc("p_LW, the weight's centre in L");
    t.number("mass", &Spec::mass).required().unit("kg").range(Range::left_open(0.0, 1e6)).doc("its mass");
    t.number("volume", &Spec::volume).unit("m³").range(Range::closed(0.0, 1e3)).default_text("mass / 7850 (steel)")
        .doc("displaced");
    t.number("release_altitude", &Spec::release_altitude).unit("m").range(Range::closed(0.0, 1e4)).default_text("none")
        .doc("let go when B's origin is this high or less above the seabed under it");
    t.number("release_time_s", &Spec::release_time_s).unit("s").range(Range::non_negative()).default_text("none")
        .doc("let go at this sim time");
    t.check([](const config::KeyReads& reads, Spec& spec, config::NoContext&) {
      if (!reads.has("volume")) spec.volume = spec.mass / kSteelDensity;
      return true;
    });
  });
}
DropWeightActuator::Runtime DropWeightActuator::prepare(const Spec& spec, const ActuatorSetup& setup) {
  Runtime runtime;
  runtime.p_BW = setup.X_BL * spec.p_LW;
  runtime.mass = spec.mass;
  runtime.volume = spec.volume;
  runtime.release_altitude = spec.release_altitude;
  runtime.release_time_s = spec.release_time_s;
  return runtime;
}

std::string DropWeightActuator::check(const Spec&, const double* controls, std::size_t first) {
  const double value = controls[0];
  if (value == 0.0 || value == 1.0) return {};
  const std::string label = "setpoint[" + std::to_string(first) + "]";
  if (std::isnan(value)) return label + " is NaN, not 0 (hold) or 1 (release)";
  return label + " = " + config::format_number(value) + " is not 0 (hold) or 1 (release)";
}

void DropWeightActuator::command(State& state, const double* controls) { state.release_commanded = controls[0] == 1.0; }

void DropWeightActuator::add_wrench(const Runtime& runtime, State& state, const ActuatorForceInput& in,
                                    StepWrench& out) {
  if (state.attached()) {
    const double altitude = in.X_WB.translation().z() - in.seabed_z_below;  // +infinity without a seabed
    if (state.release_commanded) {
      state.reason = Release::kCommand;
    } else if (altitude <= runtime.release_altitude) {
      state.reason = Release::kAltitude;
    } else if (in.time >= runtime.release_time_s) {
      state.reason = Release::kTime;
    }
    if (!state.attached()) state.release_time = in.time;
  }
  if (!state.attached()) {
    state.force_N = 0.0;
    return;
  }
  const Eigen::Vector3d p_WW = in.X_WB * runtime.p_BW;
  const double g = in.ocean ? in.ocean->gravity() : 9.80665;
  const double rho = (in.ocean && p_WW.z() < in.surface_z) ? in.ocean->density(in.ocean->depth(p_WW.z())) : 0.0;
  state.force_N = (rho * runtime.volume - runtime.mass) * g;
  const Eigen::Vector3d f_W(0.0, 0.0, state.force_N);
  out.f_W += f_W;
  out.tau_W += (p_WW - in.p_WBcm).cross(f_W);
}

}  // namespace hadal::physics
