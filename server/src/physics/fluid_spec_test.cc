// Loading the fluid model's keys (fluid, physics/fluid_spec.cc) through the scenario loader: values,
// defaults, conversions and the errors at file:line:col (config/scenario_test_support.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/config/scenario_loader.h"

namespace hadal::config {
namespace {

TEST_F(ScenarioLoaderTest, SurfaceFluidModelWithHydrodynamicCoefficients) {
  const std::string path = write("s.yaml", R"(world: {}
vehicles:
  - name: auv
    type: auv
    links:
      - name: hull
        mass: 30.0
        inertia: {ixx: 0.09, iyy: 6.4, izz: 6.4}
        collisions: [{shape: sphere, radius: 0.2}]
    fluid:
      model: surface
      hydrodynamics: {drag: 0.8, skin_friction: 0.003, lift: 0, magnus: 0.01}
  - name: rov
    type: rov
    links:
      - name: hull
        mass: 30.0
        inertia: {ixx: 0.09, iyy: 6.4, izz: 6.4}
        collisions: [{shape: box, size: [1, 1, 1]}]
    fluid: {model: surface}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const FluidSpec& auv = result.model->vehicles[0].fluid;
  EXPECT_EQ(auv.model, FluidModelType::kSurface);
  EXPECT_EQ(auv.hydrodynamics.drag, 0.8);
  EXPECT_EQ(auv.hydrodynamics.skin_friction, 0.003);
  EXPECT_EQ(auv.hydrodynamics.lift, 0.0);
  EXPECT_EQ(auv.hydrodynamics.magnus, 0.01);
  EXPECT_TRUE(auv.hydrodynamics.buoyancy);
  const FluidSpec& rov = result.model->vehicles[1].fluid;
  EXPECT_EQ(rov.model, FluidModelType::kSurface);
  EXPECT_EQ(rov.hydrodynamics.drag, 1.0);  // HydrodynamicCoefficients defaults
  EXPECT_EQ(rov.hydrodynamics.skin_friction, 0.004);
  EXPECT_EQ(rov.hydrodynamics.lift, 1.0);
  EXPECT_EQ(rov.hydrodynamics.magnus, 0.0);
}

TEST_F(ScenarioLoaderTest, DefaultFluidModelFollowsTheGeometry) {
  const std::string path = write("s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle + R"(
  - name: boxy
    type: rov
    links:
      - name: hull
        mass: 30.0
        inertia: {ixx: 1, iyy: 1, izz: 1}
        collisions: [{shape: box, size: [1, 1, 1]}]
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  EXPECT_EQ(result.model->vehicles[0].fluid.model, FluidModelType::kLumped);   // no faces
  EXPECT_EQ(result.model->vehicles[0].fluid.added_mass.model, AddedMassModel::kNone);
  EXPECT_EQ(result.model->vehicles[1].fluid.model, FluidModelType::kSurface);  // collision shapes
  EXPECT_EQ(result.model->vehicles[1].fluid.added_mass.model, AddedMassModel::kEllipsoid);
  EXPECT_FALSE(result.model->vehicles[1].fluid.added_mass.semi_axes_E.has_value());
  EXPECT_TRUE(result.model->vehicles[1].fluid.added_mass.coriolis);
  EXPECT_TRUE(result.model->world.dynamics.gyroscopic);
  EXPECT_FALSE(result.model->world.dynamics.earth_rotation);
}

TEST_F(ScenarioLoaderTest, AddedMassAndDynamicsKeys) {
  const std::string path = write("s.yaml", R"(world:
  dynamics: {gyroscopic: false, earth_rotation: true}
vehicles:
  - name: a
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass:
        semi_axes: [0.8, 0.1, 0.1]
        pose: {position: [0.1, 0, 0], rpy_deg: [0, 0, 90]}
        coriolis: false
  - name: b
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass:
        model: matrix
        reference_point: [0, 0, 0.05]
        matrix: [1, 0, 0, 0, 0, 0,  0, 20, 0, 0, 0, 0.5,  0, 0, 20, 0, 0, 0,
                 0, 0, 0, 0.1, 0, 0,  0, 0, 0, 0, 3, 0,  0, 0.5, 0, 0, 0, 3]
  - name: c
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid: {model: lumped, added_mass: {model: none}}
)");
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  EXPECT_FALSE(result.model->world.dynamics.gyroscopic);
  EXPECT_TRUE(result.model->world.dynamics.earth_rotation);
  const AddedMassSpec& a = result.model->vehicles[0].fluid.added_mass;
  EXPECT_EQ(a.model, AddedMassModel::kEllipsoid);
  ASSERT_TRUE(a.semi_axes_E.has_value());
  EXPECT_EQ(*a.semi_axes_E, Eigen::Vector3d(0.8, 0.1, 0.1));
  EXPECT_EQ(a.X_BE.translation(), Eigen::Vector3d(0.1, 0, 0));
  EXPECT_NEAR((a.X_BE.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-15);
  EXPECT_FALSE(a.coriolis);
  const AddedMassSpec& b = result.model->vehicles[1].fluid.added_mass;
  EXPECT_EQ(b.model, AddedMassModel::kMatrix);
  EXPECT_EQ(b.p_BR, Eigen::Vector3d(0, 0, 0.05));
  EXPECT_EQ(b.M_A0(1, 1), 20.0);
  EXPECT_EQ(b.M_A0(5, 1), 0.5);
  EXPECT_EQ(b.M_A0(1, 5), 0.5);
  EXPECT_EQ(result.model->vehicles[2].fluid.added_mass.model, AddedMassModel::kNone);
}

TEST_F(ScenarioLoaderTest, AddedMassErrors) {
  const std::string path = write("s.yaml", R"(world:
  dynamics: {gyroscopic: yes, coriolis: true}
vehicles:
  - name: a
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass: {model: ellipsoid, pose: {position: [0, 0, 0]}, matrix: [1]}
  - name: b
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass: {semi_axes: [1, 0, 1], coriolis: 1}
  - name: c
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass:
        model: matrix
        matrix: [1, 2, 0, 0, 0, 0,  0, 1, 0, 0, 0, 0,  0, 0, 1, 0, 0, 0,
                 0, 0, 0, 1, 0, 0,  0, 0, 0, 0, 1, 0,  0, 0, 0, 0, 0, 1]
  - name: d
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass:
        model: matrix
        matrix: [1, 0, 0, 0, 0, 0,  0, -1, 0, 0, 0, 0,  0, 0, 1, 0, 0, 0,
                 0, 0, 0, 1, 0, 0,  0, 0, 0, 0, 1, 0,  0, 0, 0, 0, 0, 1]
  - name: e
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}, collisions: [{shape: sphere, radius: 0.2}]}
    fluid:
      added_mass: {model: matrix}
)");
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":2:26: error: world.dynamics.gyroscopic: expected true or false (got 'yes')",
                   path + ":2:31: error: world.dynamics.coriolis: unknown key 'coriolis'",
                   path + ":9:38: error: vehicles[0].fluid.added_mass.pose: key 'pose' needs 'semi_axes' (without them "
                          "the ellipsoid is fitted to the hull, centre and axes included)",
                   path + ":9:67: error: vehicles[0].fluid.added_mass.matrix: key 'matrix' is not used by "
                          "added_mass model 'ellipsoid'",
                   path + ":15:35: error: vehicles[1].fluid.added_mass.semi_axes[1]: must be > 0 (got 0)",
                   path + ":15:52: error: vehicles[1].fluid.added_mass.coriolis: expected true or false (got '1')",
                   path + ":23:17: error: vehicles[2].fluid.added_mass.matrix: must be symmetric (largest "
                          "|M_ij - M_ji| = 2)",
                   path + ":32:17: error: vehicles[3].fluid.added_mass.matrix: must be positive semidefinite "
                          "(an added mass cannot lower the kinetic energy)",
                   path + ":39:19: error: vehicles[4].fluid.added_mass: missing required key 'matrix' (model "
                          "'matrix' needs the 6x6 added-mass matrix)"}));
}

TEST_F(ScenarioLoaderTest, FluidKeysArePerModel) {
  const std::string surface = write("surface.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle +
                                                        R"(    fluid:
      model: surface
      linear_damping: [1, 1, 1, 1, 1, 1]
      hydrodynamics: {drag: -1, magnus: -0.5}
)");
  EXPECT_EQ(errors_of(surface),
            (Lines{surface + ":18:14: error: vehicles[0].fluid.model: fluid model 'surface' needs a hydrodynamic "
                             "mesh: no link has a 'mesh' or 'collisions'",
                   surface + ":19:7: error: vehicles[0].fluid.linear_damping: key 'linear_damping' is not used "
                             "by fluid model 'surface'",
                   surface + ":20:29: error: vehicles[0].fluid.hydrodynamics.drag: must be >= 0 (got -1)",
                   surface + ":20:41: error: vehicles[0].fluid.hydrodynamics.magnus: must be >= 0 (got -0.5)"}));
  const std::string lumped = write("lumped.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle +
                                                      R"(    fluid:
      quadratic_damping: [1, 1, 1, 1, 1, 1]
      hydrodynamics: {drag: 1}
)");
  EXPECT_EQ(errors_of(lumped),
            (Lines{lumped + ":19:7: error: vehicles[0].fluid.hydrodynamics: key 'hydrodynamics' is not used by "
                            "fluid model 'lumped' (the default for a vehicle without a mesh or collision shapes)"}));
}

}  // namespace
}  // namespace hadal::config
