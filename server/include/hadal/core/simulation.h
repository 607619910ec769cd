// Simulation: the fixed-step loop body of hadald, independent of DDS.
//
// One step (docs/ARCHITECTURE.md, "One step"):
//   commands -> actuators (physics/actuators.h) -> force elements (actuators, fluid, Earth rotation;
//   physics/force_element.h) -> added-mass conversion -> Bullet step -> state snapshot -> non-finite
//   check -> sensors due (sensors/sensor_kinds.h).
// Control source per vehicle: the scenario schedule until a client first commands the vehicle, then
// the client's control vector guarded by the watchdog (no fresh command for command_timeout seconds
// of sim time -> zero controls, kFaultCommandTimeout set). Non-finite policy: a vehicle whose pose,
// velocity, actuator state or client controls become NaN/Inf, or whose position leaves the world (a
// coordinate beyond kWorldBound_m), is put back at X_WB_initial at rest,
// actuators stopped, client controls zeroed; kFaultNonFiniteState stays set (latched) and fault_resets
// counts the resets. Not thread-safe: the caller serialises access.
// Fluid per vehicle (VehicleSpec::fluid, physics/fluid_forces.h): surface or lumped model, both in the
// scenario's Ocean with its currents. Added mass (physics/added_mass.h): M_A0 about the centre of mass,
// scaled each step by kappa(d) at the centre of mass times the submerged fraction, with C_A(nu_r) nu_r
// for the velocity relative to the current; every applied wrench of a step is collected at the centre
// of mass and turned into the wrench Bullet gets. Rigid-body dynamics (world.dynamics): Bullet's
// gyroscopic moment on/off; Earth-rotation Coriolis as a force element when enabled.
// Sensors sample at the end of the step that reaches their sample time; the ray-casting ones (DVL,
// altimeter) cast into the world's Embree scene on the stepping thread, so their samples are as
// deterministic as the rest of the step. Force elements of different vehicles are independent; with two
// or more surface-model hulls of >= 4096 faces they run on a persistent worker pool (results are
// identical either way).
#pragma once

#include "hadal/core/model.h"
#include "hadal/core/state.h"
#include "hadal/geometry/world_scene.h"

#include <array>
#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hadal {

// Leaves every sensor that renders images (sensors::RendersImages: the camera) out of the model's vehicles:
// hadald --no-cameras, hadal_bench_step_rate --no-cameras.
void remove_cameras(Model& model);

class WorkerPool;

namespace sensors {
class SensorEnvironment;
struct SampleContext;
}
namespace geometry {
class RaycastService;
class SceneRays;
class SeabedHeight;
}

namespace physics {
class BulletWorld;
class Ocean;
struct SoilWrench;
struct StepWrench;
struct MassProperties;
}

class Simulation {
 public:
  // Throws std::invalid_argument if the model cannot be simulated (physics_rate_hz not > 0, a vehicle
  // without positive mass, an actuator or sensor on a missing link, a surface-model vehicle without
  // faces).
  explicit Simulation(Model model);
  ~Simulation();

  // The world's extent [m]: a vehicle position coordinate beyond +-1000 km of the origin is a fault (the
  // non-finite policy), and a reset pose there is refused. Far beyond any local ENU frame's use, and
  // far enough from double's range that a sensor's mount added to it stays finite.
  static constexpr double kWorldBound_m = 1e6;
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const Model& model() const { return model_; }
  const SimState& state() const { return state_; }
  double time() const { return state_.time; }

  // Composite mass properties of a vehicle (centre of mass, inertia, principal frame), index < count; of an
  // articulated vehicle's base body (the links that do not move relative to B).
  const physics::MassProperties& mass_properties(int vehicle_index) const;
  // The vehicle's added mass at the surface, M_A0 about its centre of mass in B axes (zero for
  // added_mass.model none) [kg, kg m, kg m^2]; an articulated vehicle's base body's.
  const Matrix6d& added_mass(int vehicle_index) const;
  // The soil's wrench on the vehicle in the last step (physics/terramechanics.h), or null for a vehicle
  // without soil contact.
  const physics::SoilWrench* soil_wrench(int vehicle_index) const;
  // The wrench the vehicle's force elements added up in the last step (actuators, fluid, Earth rotation,
  // soil), at its centre of mass in W, before the added-mass conversion; gravity is not in it. An
  // articulated vehicle's base body's.
  const physics::StepWrench& applied_wrench(int vehicle_index) const;
  // The scenario's water column.
  const physics::Ocean& ocean() const { return *ocean_; }
  // Helper threads computing force elements besides the stepping thread (0: serial).
  unsigned fluid_helper_threads() const;

  // Restores a state previously returned by state() (same model; throws std::invalid_argument if the
  // vehicle, actuator or sensor counts or kinds differ). A vehicle whose restored state is not finite gets the
  // non-finite policy at once (reset, kFaultNonFiniteState, fault_resets + 1), so NaN never enters
  // Bullet. Contact caches are cleared: restoring the same state twice continues bit-identically.
  void set_state(const SimState& state);

  // The state the simulation starts from: sim time 0, every vehicle at its scenario pose and velocity,
  // actuators at rest, no client command, no faults, the sensors' noise streams seeded from `seed` as
  // world.seed seeds them at construction (so initial_state(model().world.seed) is the first state()).
  SimState initial_state(std::uint64_t seed) const;
  // Starts over from initial_state(seed), with vehicle i placed at X_WB[i] (at rest) where that is given
  // (X_WB may be shorter than the vehicle list). The world itself (seabed, marine snow, textures) keeps
  // world.seed. Returns "" when done, else the reason (a non-finite pose, one beyond kWorldBound_m, more poses
  // than vehicles) with
  // the state untouched.
  std::string reset(std::uint64_t seed, const std::vector<std::optional<Eigen::Isometry3d>>& X_WB = {});

  // Validates and applies a client command for a vehicle: a whole control vector (one normalised
  // setpoint per thruster, each finite and in [-1, 1]; physics/actuators.h). Returns an empty string
  // when accepted, otherwise the reason (state untouched).
  std::string set_controls(int vehicle_index, const std::vector<double>& controls);
  // The validation alone: "" if set_controls would accept the command, else the reason.
  std::string check_controls(int vehicle_index, const std::vector<double>& controls) const;

  // Queues a packet on the vehicle's acoustic modem `modem` (sensors/modem_sensor.h) for `destination` ("" every
  // modem, a vehicle's modems or "<vehicle>/<modem>"), sent from now on. Returns "" when queued, else the reason
  // (not a modem of the vehicle, an empty or oversize payload, an unknown destination, a full queue) with the
  // state untouched.
  std::string send_packet(int vehicle_index, const std::string& modem, const std::string& destination,
                          std::vector<std::uint8_t> payload);
  // The validation alone: "" if send_packet would queue the packet now, else the reason.
  std::string check_packet(int vehicle_index, const std::string& modem, const std::string& destination,
                           std::size_t payload_bytes) const;

  // What the acoustic sensors (modems, USBLs, LBLs) have in flight at the state's time (sensors/sensor_kind.h,
  // AcousticLink), each with the harmonic-mean sound speed of its path: what monitors draw
  // (rt/hadal/acoustic_links). Empty without such sensors.
  std::vector<sensors::AcousticLink> acoustic_links();

  // An articulated vehicle's joint efforts (physics/articulation.h): one torque [N m] or force [N] per
  // moving joint in body order, each finite, held until the next, each within its joint's effort_limit when
  // applied. Only for a vehicle whose joint controllers (if any) are effort groups. Returns "" when accepted,
  // else the reason (an unknown vehicle, a vehicle without joints, a position or velocity controller, the
  // wrong length, a value that is not finite) with the state untouched.
  std::string set_joint_efforts(int vehicle_index, const std::vector<double>& efforts);
  // A command of one of the vehicle's joint controllers (VehicleSpec::joint_controllers, by name): one
  // value per joint of the group, in its order, held until the next (physics/joint_servo.h has the law).
  // Refused with the reason (unknown controller, wrong length, not finite, a position outside the joint's
  // limits), the state untouched.
  std::string set_joint_commands(int vehicle_index, const std::string& controller, const std::vector<double>& values);
  // The validation alone: "" if set_joint_commands would accept the command, else the reason.
  std::string check_joint_commands(int vehicle_index, const std::string& controller,
                                   const std::vector<double>& values) const;

  // A trajectory for one of the vehicle's position groups (physics/joint_trajectory.h): its joints named
  // in any order, its waypoints each within the joints' limits. It replaces the group's trajectory or
  // command when its start time comes (the next step when it has none), and is followed from the joints'
  // state then; after its last waypoint the group holds that waypoint. A command
  // (set_joint_commands) cancels it. Refused with the reason (an unknown controller, not a position group,
  // joint names that are not the group's, a malformed point), the state untouched.
  std::string set_joint_trajectory(int vehicle_index, const std::string& controller,
                                   const physics::JointTrajectoryCommand& trajectory);
  // The validation alone: "" if set_joint_trajectory would accept the trajectory, else the reason.
  std::string check_joint_trajectory(int vehicle_index, const std::string& controller,
                                     const physics::JointTrajectoryCommand& trajectory) const;

  // Where each end of cable c is held in `state` (a fixed point, a vehicle's link point); a free end hangs the
  // cable's length below the other.
  std::array<Eigen::Vector3d, 2> cable_ends_W(std::size_t c, const SimState& state) const;
  // Tells cable `cable_index`'s winch to run at `speed` [m/s, + paying out] or, with a target_length > 0 [m], to
  // run at |speed| toward that length in the water and stop there (physics::advance_winch). Returns "" or why it
  // is refused (no such cable, a cable without a winch, physics::check_winch_command; the caller names the cable),
  // the state untouched.
  std::string command_winch(int cable_index, double speed, double target_length);
  std::string check_winch_command(int cable_index, double speed, double target_length) const;

  // Advances by one physics step of model().world.step_size() seconds.
  void step();

  // The world's ray-cast workers (geometry/raycast_service.h) over a view of the one world scene
  // (seabed and every vehicle's surface) the sensors see: captured sensors use them, and so may a
  // caller, e.g. for a probe against the last state. Made on first use.
  geometry::RaycastService& raycast_service();
  // Every ray body's pose at `state` (geometry/world_scene.h: the vehicles' X_WB, then each articulated
  // vehicle's moving bodies as "B as the body carries it", X_WK X_BK0^-1): what a batch cast against the
  // state's snapshot needs (RayBatch::set_snapshot).
  std::vector<Eigen::Isometry3d> ray_body_poses(const SimState& state) const;
  // What a captured sensor's capture at the current state takes, for a frame rendered outside the step
  // (hadal-render, the camera benchmark): the ray bodies' poses, the sensor's mounting in B at the current
  // joint positions, and the ray body it is mounted on (its rays pass through that one). Throws
  // std::out_of_range for a vehicle or sensor index that does not exist.
  struct CaptureMount {
    std::vector<Eigen::Isometry3d> X_Wb;
    Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();
    int ray_body = 0;
  };
  CaptureMount capture_mount(int vehicle_index, int sensor_index) const;

  // Captures due at a step: waited for (default: lockstep, fast, tests; deterministic), or dropped when
  // their rays are not done yet (real time: the step never waits), counted in dropped_captures().
  void set_wait_for_captures(bool wait) { wait_for_captures_ = wait; }
  std::uint64_t dropped_captures() const { return dropped_captures_; }
  // Of the dropped captures done as scene work (cameras), those no worker had started when they were
  // dropped: skipped, their work never runs (so one late frame does not hold up the ones behind it).
  // Counted when a worker reaches them, so it may trail dropped_captures() while they wait in the queue.
  std::uint64_t skipped_captures() const { return skipped_captures_->load(); }

 private:
  struct VehicleRuntime;  // per-vehicle actuators, force elements, added mass, sensor mounts (simulation.cc)

  // The stages of step(), in order.
  void actuate(double t, double dt);
  void apply_forces(double t);
  // Each cable over the step (physics/cable.h), its held ends following their vehicles' points at the step
  // start's velocity; the forces on vehicles go into cable_loads_, added to their wrenches by apply_forces.
  void step_cables(double t, double dt);
  // Each cable of `state` laid straight and at rest between where its ends are in it (physics::straight_cable).
  void lay_cables_straight(SimState& state) const;
  // The cables' forces on a vehicle's body (0: the base), into `wrench` about p_Wcm.
  void add_cable_loads(std::size_t vehicle, int body, const Eigen::Vector3d& p_Wcm, physics::StepWrench& wrench) const;
  // A held cable end in a state: its point and velocity [m, m/s, W] and the body of its vehicle holding it
  // (an arm's link moves with its body; 0: the base body or not on a vehicle).
  struct HeldPoint {
    Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
    int body = 0;
  };
  HeldPoint cable_end_point(const physics::CableEndSpec& end, const SimState& state) const;
  void convert_for_added_mass(VehicleRuntime& runtime, const VehicleState& vehicle, Eigen::Vector3d& f_W,
                              Eigen::Vector3d& tau_W) const;
  void apply_articulated_forces(std::size_t vehicle);
  void hand_articulated_forces(std::size_t vehicle);
  void measure_joint_wrenches(std::size_t vehicle, const Eigen::VectorXd& u_dot, double dt);
  // The position targets and their rates of the vehicle's groups that follow trajectories, at sim time t.
  void follow_joint_trajectories(std::size_t vehicle, double t);
  // check_joint_trajectory's checks; when they pass and `out` is given, the trajectory's points in the
  // group's joint order.
  std::string group_trajectory(int vehicle_index, const std::string& controller,
                               const physics::JointTrajectoryCommand& command, physics::JointTrajectory* out) const;
  // The vehicle's joint controller by name, or null with the reason in *reason.
  const physics::JointControllerSpec* find_joint_controller(int vehicle_index, const std::string& name,
                                                            std::string* reason) const;
  void write_body(int vehicle_index, const VehicleState& vehicle);
  void take_snapshot(double dt);
  // A sensor's mounting in B at the vehicle's current joint positions; X_WK holds the vehicle's body
  // poses, computed here on first need (empty: not yet).
  Eigen::Isometry3d mounting_B(const VehicleRuntime& runtime, int sensor, const VehicleState& vehicle,
                               std::vector<Eigen::Isometry3d>& X_WK) const;
  void keep_momentum(std::size_t i);
  bool measures_joint_wrenches(std::size_t i) const;
  void reset_non_finite_vehicles();
  void sample_sensors(double dt);
  // What sensor k of vehicle i sees at the state, mounted at X_BS (which must outlive the context).
  sensors::SampleContext sensor_context(std::size_t i, std::size_t k, const Eigen::Isometry3d& X_BS, double dt);
  template <class Kind>
  void submit_capture(std::size_t vehicle, std::size_t sensor, const typename Kind::Spec& spec,
                      const PendingCapture& capture);
  void restart_captures();
  geometry::SceneRays& scene_rays();

  Model model_;
  SimState state_;
  std::unique_ptr<physics::BulletWorld> world_;
  std::unique_ptr<physics::Ocean> ocean_;  // the water column
  std::unique_ptr<geometry::SeabedHeight> seabed_height_;  // for soil contact and cables; null when nothing needs it
  // Per vehicle, the cables' forces on it this step: (force [N, W], where it acts [m, W]).
  struct CableLoad {
    Eigen::Vector3d f_W;  // [N]
    Eigen::Vector3d p_W;  // where it acts [m]
    int body = 0;         // of the vehicle's bodies
  };
  std::vector<std::vector<CableLoad>> cable_loads_;
  std::vector<std::unique_ptr<VehicleRuntime>> runtime_;  // one per VehicleSpec
  std::unique_ptr<WorkerPool> pool_;  // force elements in parallel; null when it does not pay
  std::unique_ptr<sensors::SensorEnvironment> environment_;  // WMM, W's geodetic frame (on first use)
  // The one ray-cast world: the stepping thread's view of it (null until needed), and the workers with
  // their own view.
  std::unique_ptr<geometry::SceneRays> rays_;
  std::unique_ptr<geometry::RaycastService> service_;
  geometry::RayBodies ray_bodies_;  // which vehicle and body each ray body is
  bool wait_for_captures_ = true;
  std::uint64_t dropped_captures_ = 0;
  // Shared with the queued scene work, which counts itself when it finds it was dropped.
  std::shared_ptr<std::atomic<std::uint64_t>> skipped_captures_ = std::make_shared<std::atomic<std::uint64_t>>(0);
};

}  // namespace hadal
