// Drop weight (actuator kind "drop_weight", YAML list `drop_weights`): ballast a lander or a glider
// carries down and lets go of to come back up. Its control is one release command: 0 holds, 1 releases.
// A weight also lets go by itself at an altitude above the seabed or after a time, whichever comes first
// (a lander's altimeter trigger and its burn-wire timer). A release is for good: a later 0 does not bring
// the weight back, and the state keeps when and why it went (a restored state continues it).
//
//   while attached   f_W = (rho(d) V - m) g z_W   at p_WW = X_WB X_BL p_LW   (wet weight; in air rho = 0)
//   released         nothing
//   triggers         command 1; altitude of B's origin above the seabed directly below it
//                    (z_B - h(x_B, y_B)) <= release_altitude; sim time >= release_time_s
// checked at the start of each step, so a trigger acts from the step it is met in.
//
// The weight's mass is a force, not part of the rigid body's mass: Bullet's inertia is fixed when the
// vehicle is built (physics/bullet_world.h), and a released mass must leave it. While attached the
// vehicle's inertia is short of m, so under a net force F it accelerates at F / (M + M_A) instead of
// F / (M + M_A + m) (M_A: added mass). Steady motion -- a lander's terminal descent speed, its resting
// load -- is exact; the transients are faster by at most m / (M + M_A + m) (2 x 25 kg on the zoo's
// 420 kg lander with ~250 kg of added mass in heave: 7 %).
//
// YAML keys: DropWeightActuator::keys() (server/src/physics/drop_weight.cc), shown in
// configs/REFERENCE.md.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "hadal/config/key_table_fwd.h"
#include "hadal/physics/actuator_kind.h"
#include "hadal/physics/drop_weight_spec.h"

namespace hadal::physics {

struct DropWeightActuator {
  static constexpr std::string_view kType = "drop_weight";
  static constexpr std::string_view kListKey = "drop_weights";
  static constexpr std::size_t kControls = 1;  // release: 0 hold, 1 release
  static constexpr double kSteelDensity = 7850.0;  // [kg/m^3], the default volume's

  // Why a weight was released (DropWeightState.reason on the wire).
  enum class Release : std::uint8_t { kAttached = 0, kCommand = 1, kAltitude = 2, kTime = 3 };

  using Spec = DropWeightSpec;
  struct State {
    using Kind = DropWeightActuator;
    bool release_commanded = false;  // the held command is 1
    Release reason = Release::kAttached;
    double release_time = std::numeric_limits<double>::quiet_NaN();  // sim time it went [s]; NaN attached
    double force_N = 0.0;            // vertical force it exerts (negative: down); 0 once released
    bool attached() const { return reason == Release::kAttached; }
  };
  struct Runtime {
    Eigen::Vector3d p_BW = Eigen::Vector3d::Zero();
    double mass = 0.0, volume = 0.0;
    double release_altitude = -std::numeric_limits<double>::infinity();
    double release_time_s = std::numeric_limits<double>::infinity();
  };

  // Its YAML keys besides name and link, declared once (configs/REFERENCE.md shows them).
  static const config::KeyTable<Spec>& keys();
  static Runtime prepare(const Spec& spec, const ActuatorSetup& setup);
  // "" when controls[0] is 0 or 1, else why not ("setpoint[2] = 0.5 is not 0 (hold) or 1 (release)").
  static std::string check(const Spec& spec, const double* controls, std::size_t first);
  static void command(State& state, const double* controls);
  static void actuate(const Runtime&, State&) {}
  // Releases on a trigger, then adds the wet weight while attached.
  static void add_wrench(const Runtime& runtime, State& state, const ActuatorForceInput& in, StepWrench& out);
  // A weight has nothing to stop: it stays attached or released.
  static void stop(State&) {}
  static bool is_finite(const State&) { return true; }
  static bool needs_seabed(const Spec& spec) { return spec.release_altitude >= 0.0; }
};

}  // namespace hadal::physics
