// Loading a vehicle entry's and definition's keys, includes and schedules (config/vehicle_keys.cc) through
// the scenario loader: values, defaults, conversions and the errors at file:line:col
// (config/scenario_test_support.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/config/scenario_loader.h"

namespace hadal::config {
namespace {

TEST_F(ScenarioLoaderTest, InlineVehicleGetsDefaultsAndConversions) {
  const std::string path = write("s.yaml", std::string(R"(world: {}
vehicles:
  - name: rov_1
    initial_pose: {position: [1, 2, -3], rpy_deg: [0, 0, 90]}
    type: rov
    links:
      - name: frame
        mass: 100
        inertia: {ixx: 10, iyy: 10, izz: 10, ixy: 1}
        collisions:
          - {shape: box, size: [1, 0.5, 0.4]}
          - {shape: capsule, radius: 0.1, length: 0.3, pose: {position: [0, 0, 1]}}
      - name: arm
        pose: {position: [0.5, 0, 0], rpy_deg: [90, 0, 0]}
        mass: 5
        inertia: {ixx: 0.1, iyy: 0.1, izz: 0.1}
        buoyancy: {volume: 0.004}
    thrusters:
      - {name: t, link: arm, position: [0, 0, 0], direction: [0, 3, 4], propeller_diameter: 0.2,
         thrust_coefficient: 0.5, max_rpm: 600, handedness: left, torque_coefficient: 0, rotor_time_constant_s: 0}
    schedule:
      - {time_s: 1.5, setpoints: [-1]}
      - {time_s: 2, setpoints: [1]}
)"));
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& diagnostic : result.errors) ADD_FAILURE() << diagnostic.format();
  ASSERT_TRUE(result.ok());
  const Model& model = *result.model;
  EXPECT_EQ(model.world.physics_rate_hz, 500.0);
  EXPECT_EQ(model.world.seed, 0u);
  EXPECT_EQ(model.world.seabed.z, -100.0);
  EXPECT_EQ(model.world.clock_rate_hz, 100.0);
  ASSERT_EQ(model.vehicles.size(), 1u);
  const VehicleSpec& rov = model.vehicles[0];
  EXPECT_EQ(rov.type, VehicleType::kRov);
  EXPECT_EQ(rov.source_file, path);
  EXPECT_EQ(rov.odometry_rate_hz, 50.0);
  EXPECT_EQ(rov.command_timeout, 1.0);
  // Yaw 90 deg: body x points along world y.
  EXPECT_TRUE(rov.X_WB_initial.translation().isApprox(Eigen::Vector3d(1, 2, -3), kTol));
  EXPECT_TRUE(
      (rov.X_WB_initial.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), kTol));
  ASSERT_EQ(rov.links.size(), 2u);
  EXPECT_EQ(rov.links[0].I_LLcm_L(0, 1), 1.0);
  EXPECT_EQ(rov.links[0].I_LLcm_L(1, 0), 1.0);
  EXPECT_EQ(rov.links[0].buoyancy.volume, 0.0);
  ASSERT_EQ(rov.links[0].collisions.size(), 2u);
  EXPECT_EQ(rov.links[0].collisions[0].box_size, Eigen::Vector3d(1, 0.5, 0.4));
  EXPECT_EQ(rov.links[0].collisions[1].type, CollisionShapeType::kCapsule);
  EXPECT_EQ(rov.links[0].collisions[1].X_LG.translation(), Eigen::Vector3d(0, 0, 1));
  // Roll 90 deg: link y points along body z.
  EXPECT_TRUE(
      (rov.links[1].X_BL.linear() * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), kTol));
  EXPECT_EQ(rov.links[1].buoyancy.volume, 0.004);
  ASSERT_EQ(rov.actuators.size(), 1u);
  EXPECT_EQ(rov.actuators[0].link_index, 1);
  const physics::ThrusterActuator::Spec& t = spec_of<physics::ThrusterActuator>(rov.actuators[0]);
  EXPECT_TRUE(t.axis_L.isApprox(Eigen::Vector3d(0, 0.6, 0.8), kTol));
  EXPECT_EQ(t.max_rotor_speed_rev_s, 10.0);
  EXPECT_EQ(t.handedness, -1);
  EXPECT_EQ(t.torque_coefficient, 0.0);
  EXPECT_EQ(t.rotor_time_constant_s, 0.0);
  EXPECT_EQ(rov.fluid.linear_damping, Vector6d::Zero());
  ASSERT_EQ(rov.schedule.size(), 2u);
  EXPECT_EQ(rov.schedule[0].time, 1.5);
  EXPECT_EQ(rov.schedule[0].setpoints, std::vector<double>{-1.0});
}

TEST_F(ScenarioLoaderTest, ThrusterOnMissingLink) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
      - {name: fin, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
    thrusters:
      - name: main
        link: nope
        position: [0, 0, 0]
        direction: [0, 0, 0]
        propeller_diameter: 0.1
        thrust_coefficient: 0.4
        max_rpm: 100
        handedness: clockwise
)");
  EXPECT_EQ(
      errors_of(path),
      (Lines{path + ":10:15: error: vehicles[0].thrusters[0].link: no link named 'nope' in this vehicle "
                    "(links: hull, fin)",
             path + ":12:20: error: vehicles[0].thrusters[0].direction: must be non-zero (got [0, 0, 0])",
             path + ":16:21: error: vehicles[0].thrusters[0].handedness: must be one of 'right', 'left' (got "
                    "'clockwise')"}));
}

TEST_F(ScenarioLoaderTest, DuplicateLinkAndThrusterNames) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
      - {name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
    thrusters:
      - {name: t, link: hull, position: [0, 0, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
         thrust_coefficient: 0.4, max_rpm: 100}
      - {name: t, link: hull, position: [0, 0, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
         thrust_coefficient: 0.4, max_rpm: 100}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":7:16: error: vehicles[0].links[1].name: duplicate link name 'hull' (first "
                          "used by vehicles[0].links[0])",
                   path + ":11:16: error: vehicles[0].thrusters[1].name: duplicate thruster name 't' "
                          "(first used by vehicles[0].thrusters[0])"}));
}

TEST_F(ScenarioLoaderTest, DuplicateAndInvalidVehicleNames) {
  const std::string path = write(
      "s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + kInlineVehicle + R"(  - name: 2nd-auv
    include: x.yaml
)");
  write("x.yaml", "type: auv\nlinks: [{name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}]\n");
  EXPECT_EQ(
      errors_of(path),
      (Lines{path + ":18:11: error: vehicles[1].name: duplicate vehicle name 'auv' (first used by "
                    "vehicles[0])",
             path + ":32:11: error: vehicles[2].name: must match [A-Za-z][A-Za-z0-9_]* (got '2nd-auv')"}));
}

// world.soil.regions placed by world.soil.map: an 8-bit image of region numbers next to the scenario.
// A schedule keyframe is a control vector: each actuator's own check applies at load (a drop weight's
// command is 0 or 1), as for a client's command at run time; a fin turned beyond its stall is a warning.
TEST_F(ScenarioLoaderTest, ScheduleKeyframesPassEachActuatorsCheck) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: lander
    type: lander
    links:
      - name: frame
        mass: 100.0
        inertia: {ixx: 10, iyy: 10, izz: 10}
        collisions: [{shape: box, size: [1, 1, 1]}]
    fins:
      - {name: tail, link: frame, position: [-0.5, 0, 0], hinge_axis: [0, 1, 0], area: 0.02, aspect_ratio: 2,
         max_angle_deg: 35}
    drop_weights:
      - {name: weight, link: frame, position: [0, 0, -0.5], mass: 20}
    schedule:
      - {time_s: 0.0, setpoints: [0.5, 0.0]}
      - {time_s: 5.0, setpoints: [0.0, 0.5]}
      - {time_s: 6.0, setpoints: [0.0]}
)");
  const LoadResult result = load_scenario_file(path);
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":17:34: error: vehicles[0].schedule[1].setpoints: setpoint[1] = 0.5 is not 0 (hold) or "
                          "1 (release) (weight)",
                   path + ":18:34: error: vehicles[0].schedule[2].setpoints: expected 2 setpoints, one per actuator "
                          "(tail, weight) (got 1)"}));
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0].format(),
            path + ":11:9: warning: vehicles[0].fins[0]: max_angle_deg 35 is beyond stall_angle_deg 30: full "
                   "deflection stalls the fin and gives less lift than a smaller one");
}

// An entry with `include` may add sensors and lights to the included definition; their names must not
// repeat the included ones, and their links are the included vehicle's.
TEST_F(ScenarioLoaderTest, IncludedVehicleExtendedWithSensorsAndLights) {
  write("v.yaml", R"(type: auv
links:
  - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
sensors:
  - {name: depth, type: pressure}
)");
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: a
    include: v.yaml
    sensors:
      - {name: cam, type: camera, link: hull}
    lights:
      - {name: lamp, link: hull}
  - name: b
    include: v.yaml
    sensors:
      - {name: depth, type: pressure, link: mast}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":12:16: error: vehicles[1].sensors[0].name: duplicate sensor name 'depth' (first used by " +
                       dir_.string() + "/v.yaml)",
                   path + ":12:45: error: vehicles[1].sensors[0].link: no link named 'mast' in this vehicle (links: "
                          "hull)"}));
  const std::string good = write("good.yaml", R"(world: {}
vehicles:
  - name: a
    include: v.yaml
    sensors:
      - {name: cam, type: camera, link: hull}
    lights:
      - {name: lamp, link: hull}
  - name: b
    include: v.yaml
)");
  const LoadResult loaded = load_scenario_file(good);
  ASSERT_TRUE(loaded.model) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  ASSERT_EQ(loaded.model->vehicles[0].sensors.size(), 2u);
  EXPECT_EQ(loaded.model->vehicles[0].sensors[1].name, "cam");
  EXPECT_EQ(loaded.model->vehicles[0].lights.size(), 1u);
  EXPECT_EQ(loaded.model->vehicles[1].sensors.size(), 1u);  // the include itself is unchanged
  EXPECT_TRUE(loaded.model->vehicles[1].lights.empty());
}

TEST_F(ScenarioLoaderTest, IncludeAndInlineDefinitionBothOrNeither) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: a
    include: v.yaml
    type: auv
    fluid: {}
  - name: b
    odometry_rate_hz: 10
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":4:5: error: vehicles[0].include: cannot be combined with an inline definition "
                          "(found 'type', 'fluid'; an entry with 'include' may only add 'sensors', 'lights' and a 'transponder')",
                   path + ":7:5: error: vehicles[1]: needs either 'include' or an inline definition ('type', "
                          "'links', ...)"}));
}

// A transponder: in a vehicle file, or given to an included vehicle by its entry (only to that entry), with
// its keys checked as the file's; a USBL's bandwidth must stay below twice its frequency.
TEST_F(ScenarioLoaderTest, TransponderInADefinitionOrAddedToAnIncludedVehicle) {
  write("v.yaml", R"(type: auv
links:
  - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
)");
  const std::string good = write("good.yaml", R"(world: {}
vehicles:
  - name: ship
    type: surface_vessel
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: usbl, type: usbl, rate_hz: 0.5, cone_deg: 80, bearing_stddev_deg: 0.2}
  - name: a
    include: v.yaml
    transponder: {position: [0.1, -0.2, 0.3], turnaround_s: 0.02}
  - name: b
    include: v.yaml
)");
  const LoadResult loaded = load_scenario_file(good);
  ASSERT_TRUE(loaded.model) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  const auto& usbl = std::get<sensors::UsblSpec>(loaded.model->vehicles[0].sensors[0].kind);
  EXPECT_DOUBLE_EQ(usbl.cone_half_angle, 80.0 * kDegToRad);
  EXPECT_DOUBLE_EQ(usbl.bearing_stddev, 0.2 * kDegToRad);
  EXPECT_FALSE(loaded.model->vehicles[0].transponder);
  ASSERT_TRUE(loaded.model->vehicles[1].transponder);
  EXPECT_EQ(loaded.model->vehicles[1].transponder->p_BT, Eigen::Vector3d(0.1, -0.2, 0.3));
  EXPECT_DOUBLE_EQ(loaded.model->vehicles[1].transponder->turnaround_s, 0.02);
  EXPECT_DOUBLE_EQ(loaded.model->vehicles[1].transponder->source_level_db, 185.0);
  EXPECT_FALSE(loaded.model->vehicles[2].transponder);  // the include itself is unchanged
  const std::string bad = write("bad.yaml", R"(world: {}
vehicles:
  - name: ship
    type: surface_vessel
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: usbl, type: usbl, frequency_hz: 20000, bandwidth_hz: 45000}
  - name: a
    include: v.yaml
    transponder: {turnaround: 0.02, source_level_db: 300}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":8:55: error: vehicles[0].sensors[0].bandwidth_hz: must be below twice frequency_hz (40000 Hz)",
                   bad + ":11:19: error: vehicles[1].transponder.turnaround: unknown key 'turnaround'; did you mean "
                         "'turnaround_s'?",
                   bad + ":11:54: error: vehicles[1].transponder.source_level_db: must be in [100, 240] (got 300)"}));
}

// An acoustic modem: a preset sets its figures, keys given beside it override them; bad values are refused at
// their key, as a modulation the curve does not know.
TEST_F(ScenarioLoaderTest, ModemPresetsAndKeys) {
  const std::string good = write("good.yaml", R"(world: {}
vehicles:
  - name: ship
    type: surface_vessel
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: modem, type: modem, preset: evologics_s2cr_18_34, source_level_db: 178, queue_length: 0}
      - {name: slow, type: modem}
)");
  const LoadResult loaded = load_scenario_file(good);
  ASSERT_TRUE(loaded.model) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  const auto& modem = std::get<sensors::ModemSpec>(loaded.model->vehicles[0].sensors[0].kind);
  EXPECT_DOUBLE_EQ(modem.frequency_hz, 26000.0);
  EXPECT_DOUBLE_EQ(modem.bandwidth_hz, 16000.0);
  EXPECT_DOUBLE_EQ(modem.bit_rate_bps, 13900.0);
  EXPECT_EQ(modem.modulation, sensors::ModemModulation::kPsk);
  EXPECT_EQ(modem.max_payload_bytes, 1024);
  EXPECT_DOUBLE_EQ(modem.source_level_db, 178.0);  // the file's, over the preset's 184
  EXPECT_EQ(modem.queue_length, 0);
  const auto& slow = std::get<sensors::ModemSpec>(loaded.model->vehicles[0].sensors[1].kind);
  EXPECT_DOUBLE_EQ(slow.bit_rate_bps, 80.0);  // the defaults: the Micro-Modem's FH-FSK
  EXPECT_EQ(slow.modulation, sensors::ModemModulation::kFsk);
  const std::string bad = write("bad.yaml", R"(world: {}
vehicles:
  - name: ship
    type: surface_vessel
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
      - {name: a, type: modem, preset: whoi_micromodem, queue_length: -1}
      - {name: b, type: modem, modulation: qam, max_payload_bytes: 2.5, bit_rate_bps: 0}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":8:40: error: vehicles[0].sensors[0].preset: unknown modem preset 'whoi_micromodem' "
                         "(presets: 'whoi_micromodem_fhfsk', 'whoi_micromodem_psk_rate5', 'evologics_s2cr_18_34')",
                   bad + ":8:71: error: vehicles[0].sensors[0].queue_length: must be in [0, 1024] (got -1)",
                   bad + ":9:44: error: vehicles[0].sensors[1].modulation: must be one of 'fsk', 'psk' (got 'qam')",
                   bad + ":9:68: error: vehicles[0].sensors[1].max_payload_bytes: must be a whole number (got 2.5)",
                   bad + ":9:87: error: vehicles[0].sensors[1].bit_rate_bps: must be > 0 (got 0)"}));
}

// Cables: each end fixed in W, on a vehicle's link (resolved to indices) or free; bad values refused at their key:
// a length, diameter or EA that is not positive, an end on a vehicle or link the scenario does not have, an end
// that says nothing, two free ends, a duplicate name.
TEST_F(ScenarioLoaderTest, CablesAndTheirEnds) {
  const std::string vehicles = R"(vehicles:
  - name: rov
    type: rov
    links:
      - {name: frame, mass: 100.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
      - {name: bail, parent: frame, mass: 1.0, inertia: {ixx: 1, iyy: 1, izz: 1}, pose: {position: [0, 0, 0.5]}}
)";
  const std::string good = write("good.yaml", "world: {}\n" + vehicles + R"(cables:
  - name: umbilical
    length: 120
    segments: 40
    diameter: 0.03
    density: 2500
    axial_stiffness: 5.0e6
    from: {position: [0, 0, -5]}
    to: {vehicle: rov, link: bail, position: [0, 0, 0.1]}
  - {name: tail, length: 10, diameter: 0.01, density: 1100, axial_stiffness: 1.0e4, from: {vehicle: rov},
     to: {free: true}}
)");
  const LoadResult loaded = load_scenario_file(good);
  ASSERT_TRUE(loaded.model) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  ASSERT_EQ(loaded.model->cables.size(), 2u);
  const physics::CableModel& umbilical = loaded.model->cables[0];
  EXPECT_EQ(umbilical.spec.segments, 40);
  EXPECT_DOUBLE_EQ(umbilical.spec.axial_stiffness, 5.0e6);
  EXPECT_FALSE(umbilical.ends[0].on_vehicle());
  EXPECT_EQ(umbilical.ends[0].position, Eigen::Vector3d(0, 0, -5));
  EXPECT_EQ(umbilical.ends[1].vehicle_index, 0);
  EXPECT_EQ(umbilical.ends[1].link_index, 1);
  EXPECT_EQ(loaded.model->cables[1].ends[0].link_index, 0);  // the base link
  EXPECT_TRUE(loaded.model->cables[1].ends[1].free);
  EXPECT_EQ(loaded.model->cables[1].spec.segments, 20);  // the default
  const std::string bad = write("bad.yaml", "world: {}\n" + vehicles + R"(cables:
  - {name: a, length: 0, diameter: 0.03, density: 2500, axial_stiffness: -1, from: {position: [0, 0, -5]},
     to: {vehicle: auv}}
  - {name: a, length: 5, diameter: 0.03, density: 2500, axial_stiffness: 1.0e5, from: {vehicle: rov, link: arm},
     to: {link: frame}}
  - {name: c, length: 5, diameter: 0.03, density: 2500, axial_stiffness: 1.0e5, from: {free: true},
     to: {free: true}}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":9:23: error: cables[0].length: must be > 0 (got 0)",
                   bad + ":9:74: error: cables[0].axial_stiffness: must be > 0 (got -1)",
                   bad + ":10:11: error: cables[0].to.vehicle: unknown vehicle 'auv' (vehicles: 'rov')",
                   bad + ":11:6: error: cables[1].name: duplicate cable name 'a' (first used by cables[0])",
                   bad + ":11:102: error: cables[1].from.link: vehicle 'rov' has no link 'arm' (its links: 'frame', "
                         "'bail')",
                   bad + ":12:11: error: cables[1].to.link: a link needs its `vehicle`",
                   bad + ":14:6: error: cables[2].to: a cable needs at least one held end"}));
}

// A cable may hold an articulated vehicle by any link, also one that moves on a joint; a winch holds one end of a
// cable (at most one), its drum at least the cable's length, and not on a free end.
TEST_F(ScenarioLoaderTest, CablesOnMovingLinksAndWinches) {
  const std::string vehicles = R"(vehicles:
  - name: rov
    type: rov
    links:
      - {name: frame, mass: 100, inertia: {ixx: 10, iyy: 10, izz: 10}, collisions: [{shape: box, size: [1, 1, 1]}]}
      - {name: arm, mass: 5, inertia: {ixx: 0.1, iyy: 0.1, izz: 0.1}, joint: {type: revolute, axis: [0, 1, 0]}}
    fluid: {model: surface}
)";
  const std::string good = write("good.yaml", "world: {}\n" + vehicles + R"(cables:
  - {name: a, length: 5, diameter: 0.03, density: 2500, axial_stiffness: 1.0e5, to: {vehicle: rov, link: arm},
     from: {position: [0, 0, -5], winch: {drum_length: 300, max_speed: 1.5}}}
)");
  const LoadResult loaded = load_scenario_file(good);
  ASSERT_TRUE(loaded.model) << (loaded.errors.empty() ? "" : loaded.errors.front().format());
  const physics::CableModel& cable = loaded.model->cables[0];
  EXPECT_EQ(cable.ends[1].link_index, 1);
  EXPECT_EQ(cable.winch_end(), 0);
  EXPECT_DOUBLE_EQ(cable.ends[0].winch->drum_length, 300.0);
  EXPECT_DOUBLE_EQ(cable.ends[0].winch->max_speed, 1.5);
  EXPECT_DOUBLE_EQ(cable.ends[0].winch->min_length, 1.0);  // the defaults
  EXPECT_DOUBLE_EQ(cable.ends[0].winch->max_acceleration, 0.5);
  const std::string bad = write("bad.yaml", "world: {}\n" + vehicles + R"(cables:
  - {name: a, length: 50, diameter: 0.03, density: 2500, axial_stiffness: 1.0e5, to: {vehicle: rov},
     from: {position: [0, 0, -5], winch: {drum_length: 40}}}
  - {name: b, length: 50, diameter: 0.03, density: 2500, axial_stiffness: 1.0e5, to: {vehicle: rov},
     from: {position: [0, 0, -5], winch: {drum_length: 400, min_length: 60}}}
  - {name: c, length: 50, diameter: 0.03, density: 2500, axial_stiffness: 1.0e5, to: {free: true, winch: {drum_length: 60}},
     from: {position: [0, 0, -5], winch: {drum_length: 100, min_length: 100}}}
  - {name: d, length: 50, diameter: 0.03, density: 2500, axial_stiffness: 1.0e5, to: {vehicle: rov, winch: {drum_length: 60}},
     from: {position: [0, 0, -5], winch: {drum_length: 100}}}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":11:43: error: cables[0].from.winch.drum_length: the drum holds less than the cable's length "
                         "(50 m in the water)",
                   bad + ":13:61: error: cables[1].from.winch.min_length: more than the cable's length (50 m in the water)",
                   bad + ":14:87: error: cables[2].to.free: a free end is held by nothing: leave out vehicle, link, "
                         "position, velocity and winch",
                   bad + ":15:61: error: cables[2].from.winch.min_length: must be less than drum_length (100 m)",
                   bad + ":16:82: error: cables[3].to: a cable has at most one winch (`from` has one)"}));
}

TEST_F(ScenarioLoaderTest, ScheduleSetpointCountUsesTheIncludedVehicle) {
  write("vehicles/v.yaml", R"(type: auv
links: [{name: hull, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}]
thrusters:
  - {name: left, link: hull, position: [0, 1, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
     thrust_coefficient: 0.4, max_rpm: 100}
  - {name: right, link: hull, position: [0, -1, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
     thrust_coefficient: 0.4, max_rpm: 100}
)");
  const std::string path = write("scenarios/s.yaml", R"(world: {}
vehicles:
  - name: auv
    include: ../vehicles/v.yaml
    schedule:
      - {time_s: 0, setpoints: [0.5, 0.5]}
      - {time_s: 10, setpoints: [0.5]}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":7:33: error: vehicles[0].schedule[1].setpoints: expected 2 setpoints, one "
                          "per actuator (left, right) (got 1)"}));
}

TEST_F(ScenarioLoaderTest, ScheduleTimesMustIncreaseAndSetpointsStayInRange) {
  const std::string path =
      write("s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + R"(    schedule:
      - {time_s: 0, setpoints: [0.5]}
      - {time_s: 10, setpoints: [1.5]}
      - {time_s: 10, setpoints: [-1]}
      - {time_s: -1, setpoints: [0]}
      - {setpoints: [0]}
)");
  EXPECT_EQ(
      errors_of(path),
      (Lines{path + ":19:34: error: vehicles[0].schedule[1].setpoints[0]: must be in [-1, 1] (got 1.5)",
             path + ":20:18: error: vehicles[0].schedule[2].time_s: must be greater than the previous time_s "
                    "(10) (got 10)",
             path + ":21:18: error: vehicles[0].schedule[3].time_s: must be >= 0 (got -1)",
             path + ":22:9: error: vehicles[0].schedule[4]: missing required key 'time_s'"}));
}

// A key's former name is refused at the key, naming the new one (not "unknown key").
TEST_F(ScenarioLoaderTest, ARenamedKeyIsRefusedNamingItsNewName) {
  const std::string path =
      write("s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + "    thruster_state_rate_hz: 10\n");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":17:5: error: vehicles[0].thruster_state_rate_hz: key 'thruster_state_rate_hz' was renamed "
                          "'actuator_state_rate_hz' (it sets every actuator kind's state rate)"}));
}

TEST_F(ScenarioLoaderTest, IncludeFileMissing) {
  const std::string path = write("scenarios/s.yaml", R"(world: {}
vehicles:
  - name: auv
    include: ../vehicles/nope.yaml
    schedule:
      - {time_s: 0, setpoints: [1, 1]}
)");
  // The setpoint count cannot be checked without the vehicle: no further error.
  EXPECT_EQ(errors_of(path), (Lines{path + ":4:14: error: vehicles[0].include: cannot open '" +
                                    dir_.string() + "/scenarios/../vehicles/nope.yaml' (file not found)"}));
}

TEST_F(ScenarioLoaderTest, ErrorsInsideAnIncludedFileNameThatFile) {
  const std::string vehicle = write("vehicles/v.yaml", R"(type: auv
links:
  - name: hull
    mass: 1
    inertia: {ixx: 1, iyy: 1, izz: 1}
thrusters:
  - name: main
    link: hull
    position: [0, 0, 0]
    direction: [1, 0, 0]
    propeller_diameter: 0.1
    thrust_coefficient: 0.4
    max_rpm: -5
    colour: red
)");
  // Two vehicles include the same file: its errors are reported once.
  const std::string path = write("scenarios/s.yaml", R"(world: {}
vehicles:
  - {name: a, include: ../vehicles/v.yaml}
  - {name: b, include: ../vehicles/v.yaml, odometry_rate_hz: 0}
)");
  const std::string included = dir_.string() + "/scenarios/../vehicles/v.yaml";
  EXPECT_EQ(errors_of(path), (Lines{path + ":4:62: error: vehicles[1].odometry_rate_hz: must be > 0 (got 0)",
                                    included + ":13:14: error: thrusters[0].max_rpm: must be > 0 (got -5)",
                                    included + ":14:5: error: thrusters[0].colour: unknown key 'colour'"}));
}

TEST_F(ScenarioLoaderTest, SyntaxErrorInsideAnIncludedFile) {
  write("v.yaml", "type: auv\nlinks: [\n");
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - {name: a, include: v.yaml, schedule: [{time_s: 0, setpoints: [1]}]}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{dir_.string() + "/v.yaml:3:1: error: yaml: end of sequence flow not found"}));
}

}  // namespace
}  // namespace hadal::config

namespace hadal::config {
namespace {

// A depth written as a height: an AUV starting 90 m above the surface loads, with a warning at its initial_pose
// naming the fix; a surface vessel there, or an AUV surfaced (its origin less than 1 m up), gives none.
TEST_F(ScenarioLoaderTest, AVehicleThatWorksUnderWaterStartingInTheAirIsAWarning) {
  const std::string path = write("s.yaml", std::string("world: {water: {surface_z: 5}}\nvehicles:") + kInlineVehicle +
                                               "    initial_pose: {position: [0, 0, 95]}\n");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.ok());
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0].format(),
            path + ":17:19: warning: vehicles[0].initial_pose: a vehicle of type auv starting 90 m above the water "
                   "surface (world.water.surface_z = 5 m): z is up in W, so 90 m down is z: -85");
  const std::string surfaced = write("t.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle +
                                                   "    initial_pose: {position: [0, 0, 0.8]}\n");
  const LoadResult at_surface = load_scenario_file(surfaced);
  ASSERT_TRUE(at_surface.ok());
  EXPECT_TRUE(at_surface.warnings.empty());
  std::string vessel_yaml = std::string("world: {}\nvehicles:") + kInlineVehicle + "    initial_pose: {position: [0, 0, 3]}\n";
  vessel_yaml.replace(vessel_yaml.find("type: auv"), 9, "type: surface_vessel");
  const LoadResult vessel = load_scenario_file(write("v.yaml", vessel_yaml));
  ASSERT_TRUE(vessel.ok());
  EXPECT_TRUE(vessel.warnings.empty());
}

// Radians in a degree key: rpy_deg: [0, 0, 1.5708] (π/2) and fov_deg: 1.0472 (π/3) are warned about, naming
// the degrees meant; a 5° pitch, a 1° beam or a 0.5° value are degrees and pass.
TEST_F(ScenarioLoaderTest, RadiansInADegreeKeyAreAWarning) {
  const std::string path = write("s.yaml", std::string("world: {}\n") + kSensorVehicle +
                                               "      - {name: scan, type: profiler, fov_deg: 1.0472, beam_width_deg: 1}\n"
                                               "    initial_pose: {rpy_deg: [0, 0, 1.5708]}\n");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.ok());
  std::vector<std::string> warnings;
  for (const auto& w : result.warnings) warnings.push_back(w.format());
  EXPECT_EQ(warnings,
            std::vector<std::string>(
                {path + ":8:47: warning: vehicles[0].sensors[0].fov_deg: 1.0472 is 60 deg in radians, but this key is "
                        "in degrees: did you mean 60?",
                 path + ":9:29: warning: vehicles[0].initial_pose.rpy_deg: 1.5708 is 90 deg in radians, but this key "
                        "is in degrees: did you mean 90?"}));
  const std::string degrees = write("d.yaml", std::string("world: {}\n") + kSensorVehicle +
                                                  "      - {name: scan, type: profiler, fov_deg: 90, beam_width_deg: 0.5}\n"
                                                  "    initial_pose: {rpy_deg: [0, 5, 0]}\n");
  const LoadResult fine = load_scenario_file(degrees);
  ASSERT_TRUE(fine.ok());
  EXPECT_TRUE(fine.warnings.empty()) << fine.warnings[0].format();
}

}  // namespace
}  // namespace hadal::config

namespace hadal::config {
namespace {

// static: true fixes a vehicle at its initial pose; an initial velocity with it is an error at that key.
TEST_F(ScenarioLoaderTest, AStaticVehicleTakesNoInitialVelocity) {
  const std::string path = write("s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle +
                                               "    static: true\n    initial_velocity: [0, 0, 1]\n");
  EXPECT_EQ(errors_of(path), std::vector<std::string>({path + ":18:5: error: vehicles[0].initial_velocity: a static "
                                                               "vehicle never moves (static: true): leave it out"}));
  const std::string fine = write("f.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + "    static: true\n");
  const LoadResult result = load_scenario_file(fine);
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result.model->vehicles[0].is_static);
}

// Links on joints: `parent` names an earlier link, `pose` is then in the parent's frame (X_BL composes),
// `joint` gives the type, axis, limits in degrees (revolute) or metres (prismatic), damping, friction and
// the initial position.
TEST_F(ScenarioLoaderTest, LinksHangOnTheirParentsThroughJoints) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: rov
    type: rov
    links:
      - {name: frame, mass: 100, inertia: {ixx: 10, iyy: 10, izz: 10}}
      - name: shoulder
        pose: {position: [1, 0, 0]}
        mass: 5
        inertia: {ixx: 0.1, iyy: 0.1, izz: 0.1}
        joint: {type: revolute, axis: [0, 0, 2], lower_deg: -90, upper_deg: 45, damping: 3, friction: 0.5,
                initial_deg: 30}
      - name: slide
        parent: shoulder
        pose: {position: [0.5, 0, 0], rpy_deg: [0, 0, 90]}
        mass: 1
        inertia: {ixx: 0.01, iyy: 0.01, izz: 0.01}
        joint: {type: prismatic, axis: [1, 0, 0], lower: 0, upper: 0.2}
      - {name: camera_mount, parent: slide, pose: {position: [0, 0.1, 0]}, mass: 0.1,
         inertia: {ixx: 0.001, iyy: 0.001, izz: 0.001}}
)");
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& diagnostic : result.errors) ADD_FAILURE() << diagnostic.format();
  ASSERT_TRUE(result.ok());
  const std::vector<LinkSpec>& links = result.model->vehicles[0].links;
  ASSERT_EQ(links.size(), 4u);
  EXPECT_EQ(links[1].parent, -1);
  EXPECT_EQ(links[1].joint.type, JointType::kRevolute);
  EXPECT_EQ(links[1].joint.axis_L, Eigen::Vector3d(0, 0, 2));
  EXPECT_NEAR(links[1].joint.lower, -0.5 * kPi, 1e-15);
  EXPECT_NEAR(links[1].joint.upper, 0.25 * kPi, 1e-15);
  EXPECT_NEAR(links[1].joint.initial, kPi / 6, 1e-15);
  EXPECT_EQ(links[1].joint.damping, 3.0);
  EXPECT_EQ(links[1].joint.friction, 0.5);
  EXPECT_EQ(links[2].parent, 1);
  EXPECT_EQ(links[2].joint.type, JointType::kPrismatic);
  EXPECT_EQ(links[2].joint.upper, 0.2);
  // X_BL = X_B,shoulder X_shoulder,slide: (1.5, 0, 0), turned 90 deg about z; the mount 0.1 m along the
  // slide's y, which is B's -x.
  EXPECT_TRUE(links[2].X_BL.translation().isApprox(Eigen::Vector3d(1.5, 0, 0), kTol));
  EXPECT_TRUE(links[3].X_BL.translation().isApprox(Eigen::Vector3d(1.4, 0, 0), kTol));
  EXPECT_EQ(links[3].parent, 2);
  EXPECT_EQ(links[3].joint.type, JointType::kFixed);
}

// A scenario's head up to a vehicle's base link (a rigid frame); tests add links after it.
constexpr const char* kRovFrame = R"(world: {}
vehicles:
  - name: rov
    type: rov
    links:
      - {name: frame, mass: 100, inertia: {ixx: 10, iyy: 10, izz: 10}}
)";

// A parent that is not an earlier link (missing, itself or later: no cycle can be written), a joint on the
// base link, a zero axis, limits the wrong way round, an inertia that is zero about an axis, and an imu on
// a moving link: each refused at its key.
TEST_F(ScenarioLoaderTest, BadJointsAreRefusedAtTheirKeys) {
  const std::string head = kRovFrame;
  const std::string missing = write("m.yaml", head + R"(      - {name: arm, parent: elbow, mass: 1,
         inertia: {ixx: 1, iyy: 1, izz: 1}}
      - {name: elbow, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
)");
  EXPECT_EQ(errors_of(missing), (Lines{missing + ":7:29: error: vehicles[0].links[1].parent: no earlier link named "
                                                 "'elbow' (a parent comes before its children in `links`; earlier: "
                                                 "frame)"}));
  const std::string base = write("b.yaml", R"(world: {}
vehicles:
  - name: rov
    type: rov
    links:
      - {name: frame, mass: 100, inertia: {ixx: 10, iyy: 10, izz: 10}, joint: {type: revolute, axis: [0, 0, 1]}}
)");
  EXPECT_EQ(errors_of(base), (Lines{base + ":6:72: error: vehicles[0].links[0].joint: links[0] is the base link: "
                                           "it has no joint"}));
  const std::string joint = write("j.yaml", head + R"(      - {name: arm, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1},
         joint: {type: revolute, axis: [0, 0, 0], lower_deg: 10, upper_deg: -10}}
)");
  EXPECT_EQ(errors_of(joint),
            (Lines{joint + ":8:34: error: vehicles[0].links[1].joint.axis: must not be zero",
                   joint + ":8:66: error: vehicles[0].links[1].joint.upper_deg: must not be below the lower limit"}));
  const std::string point = write("p.yaml", head + R"(      - {name: arm, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 0},
         joint: {type: revolute, axis: [0, 0, 1]}}
)");
  EXPECT_EQ(errors_of(point), (Lines{point + ":7:61: error: vehicles[0].links[1].inertia.izz: must be > 0 (got 0)"}));
  const std::string flat = write("f.yaml", head + R"(      - {name: arm, mass: 1,
         inertia: {ixx: 1, iyy: 1, izz: 1, ixy: 1},
         joint: {type: revolute, axis: [0, 0, 1]}}
)");
  EXPECT_EQ(errors_of(flat), (Lines{flat + ":8:19: error: vehicles[0].links[1].inertia: must be positive definite "
                                           "(principal moments 0, 1, 2)"}));
  const std::string sensor = write("s.yaml", head + R"(      - {name: arm, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1},
         joint: {type: continuous, axis: [0, 0, 1]}}
    sensors:
      - {name: imu, type: imu, link: arm}
)");
  EXPECT_EQ(errors_of(sensor),
            (Lines{sensor + ":10:38: error: vehicles[0].sensors[0].link: link 'arm' moves on a joint: an imu sensor "
                            "reads its vehicle body's motion, which is not its link's: mount it on a link that does "
                            "not move"}));
  // A thruster on an arm is refused (actuators act on the base body); a lamp on it follows it.
  const std::string thruster = write("t.yaml", head + R"(      - {name: arm, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1},
         joint: {type: continuous, axis: [0, 0, 1]}}
    thrusters:
      - {name: t, link: arm, position: [0, 0, 0], direction: [1, 0, 0], propeller_diameter: 0.1,
         thrust_coefficient: 0.4, max_rpm: 500}
)");
  EXPECT_EQ(errors_of(thruster),
            (Lines{thruster + ":10:25: error: vehicles[0].thrusters[0].link: link 'arm' moves on a joint: actuators "
                              "on moving links are not supported yet"}));
  const std::string lamp = write("l.yaml", head + R"(      - {name: arm, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1},
         joint: {type: continuous, axis: [0, 0, 1]}}
    lights:
      - {name: lamp, link: arm}
)");
  const LoadResult lit = load_scenario_file(lamp);
  for (const Diagnostic& diagnostic : lit.errors) ADD_FAILURE() << diagnostic.format();
  ASSERT_TRUE(lit.ok());
  EXPECT_EQ(lit.model->vehicles[0].lights.at(0).link_index, 1);
}

// A force_torque sensor measures its link's joint: it is on a link on a moving joint, refused on a link on a
// fixed joint and without `link`, in either order of `type` and `link` in the entry. A pressure sensor may
// follow a moving link (an imu may not: BadJointsAreRefusedAtTheirKeys).
TEST_F(ScenarioLoaderTest, AForceTorqueSensorIsOnTheLinkOfAMovingJoint) {
  const std::string head = R"(world: {}
vehicles:
  - name: rov
    type: rov
    links:
      - {name: frame, mass: 100, inertia: {ixx: 10, iyy: 10, izz: 10}, collisions: [{shape: box, size: [1, 1, 1]}]}
      - {name: arm, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.1}],
         pose: {position: [1, 0, 0]}, joint: {type: revolute, axis: [0, 1, 0]}}
      - {name: tool, parent: arm, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
)";
  const std::string good = write("ft.yaml", head + R"(      - {name: wrist, link: arm, type: force_torque,
         force_noise_stddev: 0.5, measure_direction: parent_to_child, pose: {position: [0.1, 0, 0]}}
      - {name: depth, type: pressure, link: tool}
)");
  const auto loaded = load_scenario_file(good);
  ASSERT_TRUE(loaded.ok()) << (loaded.errors.empty() ? "" : loaded.errors.front().message);
  const SensorSpec& sensor = loaded.model->vehicles[0].sensors[0];
  EXPECT_EQ(sensor.type(), "force_torque");
  EXPECT_EQ(sensor.link_index, 1);
  EXPECT_TRUE(std::get<sensors::ForceTorqueSpec>(sensor.kind).parent_to_child);
  EXPECT_EQ(std::get<sensors::ForceTorqueSpec>(sensor.kind).force_noise_stddev, 0.5);
  EXPECT_EQ(loaded.model->vehicles[0].sensors[1].link_index, 2);  // a pressure sensor follows a moving link
  const std::string fixed = write("fixed.yaml", head + R"(      - {name: wrist, type: force_torque, link: tool}
)");
  EXPECT_EQ(errors_of(fixed), (Lines{fixed + ":11:49: error: vehicles[0].sensors[0].link: link 'tool' is not on a "
                                             "moving joint: a force_torque sensor measures the wrench across its "
                                             "link's joint (revolute, continuous or prismatic)"}));
  const std::string base = write("base.yaml", head + R"(      - {name: wrist, type: force_torque}
)");
  EXPECT_EQ(errors_of(base), (Lines{base + ":11:23: error: vehicles[0].sensors[0].type: a force_torque sensor needs "
                                           "`link`: the link on a moving joint whose joint it measures"}));
}

// A joint whose limits meet is locked: loaded fixed at its lock (10 deg here), its links part of the parent's
// body. A controller or a force_torque sensor that names it is refused with that reason.
TEST_F(ScenarioLoaderTest, ALockedJointIsFixedAndCannotBeDriven) {
  const std::string head = std::string(kRovFrame) + R"(      - {name: pin, mass: 5, inertia: {ixx: 1, iyy: 1, izz: 1},
         pose: {position: [1, 0, 0]}, joint: {type: revolute, axis: [0, 0, 1], lower_deg: 10, upper_deg: 10}}
      - {name: tip, parent: pin, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}, pose: {position: [1, 0, 0]},
         joint: {type: revolute, axis: [0, 0, 1]}}
)";
  const std::string path = write("s.yaml", head);
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& diagnostic : result.errors) ADD_FAILURE() << diagnostic.format();
  ASSERT_TRUE(result.ok());
  const std::vector<LinkSpec>& links = result.model->vehicles[0].links;
  EXPECT_EQ(links[1].joint.type, JointType::kFixed);
  EXPECT_EQ(links[1].joint.locked_type, JointType::kRevolute);
  // The tip's origin 1 m along the pin turned 10 deg about z.
  const double a = 10.0 * M_PI / 180.0;
  EXPECT_LT((links[2].X_BL.translation() - Eigen::Vector3d(1.0 + std::cos(a), std::sin(a), 0.0)).norm(), 1e-15);
  // Without `initial_deg` a joint starts at 0, or at the nearer limit when 0 is outside them (here 10 deg: the
  // lock; it was once a silent failure of the load).
  EXPECT_EQ(links[1].joint.initial, links[1].joint.lower);
  const std::string driven = write("d.yaml", head + R"(    joint_controllers:
      - {name: arm, type: effort, joints: [tip, pin]}
    sensors:
      - {name: ft, type: force_torque, link: pin}
)");
  EXPECT_EQ(errors_of(driven),
            (Lines{driven + ":12:49: error: vehicles[0].joint_controllers[0].joints[1]: joint 'pin' is locked (its "
                            "limits meet): nothing can move it",
                   driven + ":14:46: error: vehicles[0].sensors[0].link: link 'pin' is not on a moving joint (its "
                            "joint's limits meet: it is locked): a force_torque sensor measures the wrench across its "
                            "link's joint (revolute, continuous or prismatic)"}));
}

// joint_controllers: groups of moving joints by their names (a link's own unless its joint names itself), in
// command order; gains and the joints' own limits. Two joints of one name are refused.
TEST_F(ScenarioLoaderTest, JointControllersNameMovingJoints) {
  const std::string head =
      std::string(kRovFrame) + R"(      - {name: shoulder, mass: 5, inertia: {ixx: 1, iyy: 1, izz: 1},
         joint: {type: revolute, axis: [0, 1, 0], effort_limit: 80, velocity_limit: 0.5}}
      - {name: camera, parent: shoulder, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}
      - {name: elbow, parent: shoulder, mass: 3, inertia: {ixx: 1, iyy: 1, izz: 1},
         joint: {type: revolute, axis: [0, 1, 0]}}
      - {name: jaw, parent: elbow, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1},
         joint: {name: grip, type: prismatic, axis: [0, 1, 0], lower: 0, upper: 0.1}}
    joint_controllers:
)";
  const std::string path = write("s.yaml", head + R"(      - {name: arm, type: position, joints: [elbow, shoulder],
         kp: 300, kd: [30, 60]}
      - {name: gripper, type: effort, joints: [grip]}
)");
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& diagnostic : result.errors) ADD_FAILURE() << diagnostic.format();
  ASSERT_TRUE(result.ok());
  const VehicleSpec& rov = result.model->vehicles[0];
  ASSERT_EQ(rov.joint_controllers.size(), 2u);
  EXPECT_EQ(rov.joint_controllers[0].name, "arm");
  EXPECT_EQ(rov.joint_controllers[0].mode, physics::JointCommandMode::kPosition);
  EXPECT_EQ(rov.joint_controllers[0].joints, (std::vector<int>{1, 0}));  // elbow is the second moving joint
  // One kp for both joints; kd per joint, in `joints` order.
  EXPECT_EQ(rov.joint_controllers[0].kp, (std::vector<double>{300.0, 300.0}));
  EXPECT_EQ(rov.joint_controllers[0].kd, (std::vector<double>{30.0, 60.0}));
  EXPECT_EQ(rov.joint_controllers[1].joints, std::vector<int>{2});  // by the joint's own name
  EXPECT_EQ(rov.links[4].joint.name, "grip");
  EXPECT_EQ(rov.links[1].joint.effort_limit, 80.0);
  EXPECT_EQ(rov.links[1].joint.velocity_limit, 0.5);

  const std::string gains = write("g.yaml", head + R"(      - {name: arm, type: position, joints: [elbow, shoulder],
         kp: [1, 2, 3], kd: [-1, 1]}
)");
  EXPECT_EQ(errors_of(gains),
            (Lines{gains + ":16:10: error: vehicles[0].joint_controllers[0].kp: has 3 gains for 2 joints (give one, or "
                           "one per joint)",
                   gains + ":16:30: error: vehicles[0].joint_controllers[0].kd[0]: must be >= 0 (got -1)"}));

  const std::string bad = write("b.yaml", head + R"(      - {name: arm, type: position, joints: [elbow,camera,nope,elbow]}
)");
  EXPECT_EQ(errors_of(bad),
            (Lines{bad + ":15:9: error: vehicles[0].joint_controllers[0]: missing required key 'kp' (needed by joint "
                         "controller type 'position')",
                   bad + ":15:52: error: vehicles[0].joint_controllers[0].joints[1]: no moving joint named 'camera' "
                         "in this vehicle (joints: shoulder, elbow, grip)",
                   bad + ":15:59: error: vehicles[0].joint_controllers[0].joints[2]: no moving joint named 'nope' in "
                         "this vehicle (joints: shoulder, elbow, grip)",
                   bad + ":15:64: error: vehicles[0].joint_controllers[0].joints[3]: joint 'elbow' is listed twice"}));
  const std::string twice = write("t.yaml", head + R"(      - {name: arm, type: position, joints: [elbow], kp: 1}
      - {name: hold, type: velocity, joints: [elbow], kd: 5}
)");
  const std::string clash = write("c.yaml", R"(world: {}
vehicles:
  - name: rov
    type: rov
    links:
      - {name: frame, mass: 100, inertia: {ixx: 10, iyy: 10, izz: 10}}
      - {name: shoulder, mass: 5, inertia: {ixx: 1, iyy: 1, izz: 1}, joint: {type: revolute, axis: [0, 1, 0]}}
      - {name: elbow, mass: 5, inertia: {ixx: 1, iyy: 1, izz: 1},
         joint: {name: shoulder, type: revolute, axis: [0, 1, 0]}}
)");
  EXPECT_EQ(errors_of(clash), (Lines{clash + ":8:9: error: vehicles[0].links[2]: joint name 'shoulder' (link 'elbow') is taken by "
                                             "the joint of link 'shoulder'"}));
  EXPECT_EQ(errors_of(twice),
            (Lines{twice + ":16:9: error: vehicles[0].joint_controllers[1]: joint 'elbow' is already driven by joint "
                           "controller 'arm' (a joint is in one controller at most)"}));
  // A gripper: its fingers' multipliers default to 1; given, one per joint and none zero; kp required.
  const std::string grip = write("gr.yaml", head + R"(      - {name: hand, type: gripper, joints: [elbow, grip], kp: 5}
      - {name: wrist, type: gripper, joints: [shoulder], kp: 5, multipliers: [-0.5]}
)");
  const LoadResult gripped = load_scenario_file(grip);
  for (const Diagnostic& diagnostic : gripped.errors) ADD_FAILURE() << diagnostic.format();
  ASSERT_TRUE(gripped.ok());
  const auto& hand = gripped.model->vehicles[0].joint_controllers;
  EXPECT_EQ(hand[0].mode, physics::JointCommandMode::kGripper);
  EXPECT_EQ(hand[0].multipliers, (std::vector<double>{1.0, 1.0}));
  EXPECT_EQ(hand[0].kd, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(hand[1].multipliers, std::vector<double>{-0.5});
  const std::string bad_grip = write("bg.yaml", head + R"(      - {name: hand, type: gripper, joints: [elbow, grip],
         multipliers: [1, 1, 1]}
      - {name: other, type: position, joints: [shoulder], kp: 5, multipliers: [1]}
)");
  EXPECT_EQ(errors_of(bad_grip),
            (Lines{bad_grip + ":15:9: error: vehicles[0].joint_controllers[0]: missing required key 'kp' (needed by "
                              "joint controller type 'gripper')",
                   bad_grip + ":16:10: error: vehicles[0].joint_controllers[0].multipliers: has 3 multipliers for 2 "
                              "joints (one per joint)",
                   bad_grip + ":17:66: error: vehicles[0].joint_controllers[1].multipliers: key 'multipliers' is not "
                              "used by joint controller type 'position'"}));
  const std::string zero = write("z.yaml", head + R"(      - {name: hand, type: gripper, joints: [grip], kp: 5, multipliers: [0]}
)");
  EXPECT_EQ(errors_of(zero), (Lines{zero + ":15:74: error: vehicles[0].joint_controllers[0].multipliers[0]: a finger's "
                                           "multiplier must not be 0 (the finger would not move)"}));
}

// `objects`: free objects after the vehicles, of type object, inline or from an object file; no actuators
// (or any key only a vehicle has), and one namespace of names with the vehicles.
TEST_F(ScenarioLoaderTest, ObjectsFollowTheVehiclesWithoutActuators) {
  write("objects/tube.yaml", R"(links:
  - {name: tube, mass: 0.8, inertia: {ixx: 0.002, iyy: 0.002, izz: 0.0002},
     collisions: [{shape: cylinder, radius: 0.03, length: 0.3}]}
)");
  const std::string path = write("s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + R"(objects:
  - name: sample
    include: objects/tube.yaml
    initial_pose: {position: [1, 0, -99.8]}
  - name: rock
    links:
      - {name: rock, mass: 30, inertia: {ixx: 0.2, iyy: 0.2, izz: 0.2}, collisions: [{shape: sphere, radius: 0.15}]}
)");
  const LoadResult result = load_scenario_file(path);
  for (const Diagnostic& diagnostic : result.errors) ADD_FAILURE() << diagnostic.format();
  ASSERT_TRUE(result.ok());
  const Model& model = *result.model;
  ASSERT_EQ(model.vehicles.size(), 3u);
  EXPECT_EQ(model.vehicles[0].type, VehicleType::kAuv);
  EXPECT_EQ(model.vehicles[1].name, "sample");
  EXPECT_EQ(model.vehicles[1].type, VehicleType::kObject);
  EXPECT_EQ(model.vehicles[1].links.at(0).mass, 0.8);
  EXPECT_EQ(model.vehicles[1].X_WB_initial.translation(), Eigen::Vector3d(1, 0, -99.8));
  EXPECT_EQ(model.vehicles[2].type, VehicleType::kObject);
  EXPECT_TRUE(model.vehicles[2].actuators.empty());

  const std::string bad = write("b.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + R"(objects:
  - name: auv
    links: [{name: l, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}]
  - name: crate
    type: rov
    links: [{name: l, mass: 1, inertia: {ixx: 1, iyy: 1, izz: 1}}]
    thrusters: []
)");
  const auto errors = errors_of(bad);
  ASSERT_EQ(errors.size(), 3u) << ::testing::PrintToString(errors);
  EXPECT_EQ(errors[0], bad + ":18:11: error: objects[0].name: duplicate object name 'auv' (first used by vehicles[0]; "
                             "vehicles and objects share their names)");
  EXPECT_EQ(errors[1].rfind(bad + ":21:5: error: objects[1].type: unknown key 'type'", 0), 0u) << errors[1];
  EXPECT_EQ(errors[2].rfind(bad + ":23:5: error: objects[1].thrusters: unknown key 'thrusters'", 0), 0u) << errors[2];
}

}  // namespace
}  // namespace hadal::config
