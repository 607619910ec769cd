// Loading the water column's keys (world.water, physics/water_spec.cc) through the scenario loader: values,
// defaults, conversions and the errors at file:line:col (config/scenario_test_support.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "config/scenario_test_support.h"
#include "hadal/config/scenario_loader.h"

namespace hadal::config {
namespace {

TEST_F(ScenarioLoaderTest, WaterDefaults) {
  const std::string path = write("s.yaml", std::string("world: {}\nvehicles:") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const WaterSpec& water = result.model->world.water;
  EXPECT_EQ(water.density_model, DensityModel::kConstant);
  EXPECT_EQ(water.density, 1025.0);
  EXPECT_EQ(water.temperature, 4.0);
  EXPECT_EQ(water.salinity, 35.0);
  EXPECT_EQ(water.atmospheric_pressure, 101325.0);
  EXPECT_EQ(water.bulk_modulus, 2.2e9);
  EXPECT_EQ(water.rho0, 1025.0);
  EXPECT_EQ(water.pycnocline_depth, 1000.0);
  EXPECT_EQ(water.pycnocline_density_increase, 3.075);
  EXPECT_TRUE(water.ctd.empty());
  EXPECT_EQ(water.current.uniform_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(water.current.gauss_markov_sigma_W, Eigen::Vector3d::Zero());
}

TEST_F(ScenarioLoaderTest, WaterRampAndCurrentLoad) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water:
    surface_z: 2
    density_model: ramp
    rho0: 1024
    pycnocline_depth: 800
    pycnocline_density_increase: 4
    temperature_degc: 3.5
    salinity: 34.5
    atmospheric_pressure: 100000
    bulk_modulus: 2.3e9
    current:
      uniform: [0.1, 0.2, 0]
      shear: {surface: [0.3, 0, 0], decay_depth: 25}
      gauss_markov: {sigma: [0.01, 0.02, 0], time_constant_s: 300}
vehicles:)") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const WaterSpec& water = result.model->world.water;
  EXPECT_EQ(water.surface_z, 2.0);
  EXPECT_EQ(water.density_model, DensityModel::kRamp);
  EXPECT_EQ(water.rho0, 1024.0);
  EXPECT_EQ(water.density, 1024.0);  // the lumped model sees the surface density
  EXPECT_EQ(water.pycnocline_depth, 800.0);
  EXPECT_EQ(water.pycnocline_density_increase, 4.0);
  EXPECT_EQ(water.temperature, 3.5);
  EXPECT_EQ(water.salinity, 34.5);
  EXPECT_EQ(water.atmospheric_pressure, 100000.0);
  EXPECT_EQ(water.bulk_modulus, 2.3e9);
  EXPECT_EQ(water.current.uniform_W, Eigen::Vector3d(0.1, 0.2, 0.0));
  EXPECT_EQ(water.current.shear_surface_W, Eigen::Vector3d(0.3, 0.0, 0.0));
  EXPECT_EQ(water.current.shear_decay_depth, 25.0);
  EXPECT_EQ(water.current.gauss_markov_sigma_W, Eigen::Vector3d(0.01, 0.02, 0.0));
  EXPECT_EQ(water.current.gauss_markov_time_constant, 300.0);
}

TEST_F(ScenarioLoaderTest, WaterCtdLoads) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water:
    density_model: ctd
    ctd:
      - {depth: 0, temperature_degc: 20, salinity: 35}
      - {depth: 1000, temperature_degc: 4, salinity: 34.6}
vehicles:)") + kInlineVehicle);
  const LoadResult result = load_scenario_file(path);
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors.front().format());
  const WaterSpec& water = result.model->world.water;
  EXPECT_EQ(water.density_model, DensityModel::kCtd);
  ASSERT_EQ(water.ctd.size(), 2u);
  EXPECT_EQ(water.ctd[1].depth, 1000.0);
  EXPECT_EQ(water.ctd[1].temperature, 4.0);
  EXPECT_EQ(water.ctd[1].salinity, 34.6);
  // EOS-80 at S = 35, T68 = 20.0048 degC, p = 0: 1024.76 kg/m^3 (UNESCO 1983 tables, T = 20: 1024.763).
  EXPECT_NEAR(water.density, 1024.76, 0.01);
}

TEST_F(ScenarioLoaderTest, WaterErrors) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water:
    density_model: ramp
    density: 1030
    ctd: []
    rho0: 0
    current:
      shear: {surface: [1, 0, 0]}
      gauss_markov: {sigma: [0.1, -0.1, 0], time_constant_s: 0.5}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":4:5: error: world.water.density: key 'density' is not used by density_model 'ramp'",
                   path + ":5:5: error: world.water.ctd: key 'ctd' is not used by density_model 'ramp'",
                   path + ":6:11: error: world.water.rho0: must be in [900, 1300] (got 0)",
                   path + ":8:14: error: world.water.current.shear: missing required key 'decay_depth'",
                   path + ":9:35: error: world.water.current.gauss_markov.sigma[1]: must be >= 0 (got -0.1)",
                   path + ":9:62: error: world.water.current.gauss_markov.time_constant_s: must be in [1, "
                          "10000000] (got 0.5)"}));
}

TEST_F(ScenarioLoaderTest, WaterCtdErrors) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water:
    density_model: ctd
    temperature_degc: 4
    ctd:
      - {depth: 0, temperature_degc: 20, salinity: 35}
      - {depth: 500, temperature_degc: 41, salinity: 35}
      - {depth: 500, temperature_degc: 4, salinity: 43}
      - {temperature_degc: 2, salinity: 34}
  seed: 1
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(path),
            (Lines{path + ":4:5: error: world.water.temperature_degc: key 'temperature_degc' is not used by "
                          "density_model 'ctd'",
                   path + ":7:40: error: world.water.ctd[1].temperature_degc: must be in [-2.5, 40] (got 41)",
                   path + ":8:17: error: world.water.ctd[2].depth: must be greater than the previous row's "
                          "depth (500)",
                   path + ":8:53: error: world.water.ctd[2].salinity: must be in [0, 42] (got 43)",
                   path + ":9:9: error: world.water.ctd[3]: missing required key 'depth'"}));
}

TEST_F(ScenarioLoaderTest, WaterCtdNeedsTwoRows) {
  const std::string path = write("s.yaml", std::string(R"(world:
  water: {density_model: ctd, ctd: [{depth: 0, temperature_degc: 20, salinity: 35}]}
  origin: {altitude: 0}
vehicles:)") + kInlineVehicle);
  const std::string path2 = write("t.yaml", std::string(R"(world:
  water: {density_model: ctd, density_modle: 1}
vehicles:)") + kInlineVehicle);
  EXPECT_EQ(errors_of(path), (Lines{path + ":2:36: error: world.water.ctd: needs at least 2 rows (got 1)"}));
  EXPECT_EQ(errors_of(path2),
            (Lines{path2 + ":2:10: error: world.water: missing required key 'ctd' (needed by density_model 'ctd')",
                   path2 + ":2:31: error: world.water.density_modle: unknown key 'density_modle'; did you mean "
                           "'density_model'?"}));
}

}  // namespace
}  // namespace hadal::config
